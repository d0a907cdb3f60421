//! The conformance kit: judge a traversal method written outside tetwalk from its own `cargo test`,
//! with the oracle, stress rows, lattice-tie walks, far-offset scenes and fuzz generators that judge
//! tetwalk's methods. Everything a user names is in [`prelude`]:
//!
//! ```no_run
//! use tetwalk::kit::prelude::*;
//!
//! /// Six Plücker side products, Platis & Theoharis' rule.
//! struct MyPlucker;
//!
//! impl ExitMethod for MyPlucker {
//!     type RayData = (Vec3, Vec3);
//!     fn prepare<A: Arith>(r: &Ray) -> (Vec3, Vec3) {
//!         (r.dir, r.org.cross(r.dir))
//!     }
//!     fn exit_face<A: Arith>(t: &Tet, &(d, m): &(Vec3, Vec3), _entry: Option<usize>) -> Option<usize> {
//!         let side = |a: Vec3, b: Vec3| d.dot(a.cross(b)) + m.dot(b - a);
//!         (0..4).find(|&f| {
//!             let [a, b, c] = FACE_VERTICES[f].map(|i| t[i]);
//!             let s = [side(a, b), side(b, c), side(c, a)];
//!             s.iter().all(|&x| x >= 0.0) && s.iter().any(|&x| x != 0.0)
//!         })
//!     }
//! }
//!
//! #[test]
//! fn my_plucker_conforms() {
//!     exit_faces::<MyPlucker>(&Settings::default()).unwrap();
//! }
//! ```
//!
//! The method's family is run group by group — every stress row of `tetwalk stress`, then a property
//! campaign of random inputs through the fuzz targets' generators (an exit-face method also walks the
//! lattice-tie scenes, the stress rows of walks) — and the first group whose failures exceed what
//! [`Accept`] allows stops the run with a [`Failed`] report: the group, its first failing case shrunk
//! to the simplest one the method still fails the same way and written out exactly (the case format
//! `tetwalk exit`, `hit` and `judge` read, and the found-case line of `corpora/found/`), the case as
//! found, the method's answer and the right ones. `examples/conformance/` is a
//! complete user crate; it builds with `default-features = false`.
#![warn(missing_docs)]

use std::fmt;

// The run over any family, generic over the crate's `Family` trait: public only with `internals`
// (tetwalk's own tests), as that trait is.
#[cfg(feature = "internals")]
pub mod run;
#[cfg(not(feature = "internals"))]
pub(crate) mod run;

/// What a user's crate names: the method traits, the geometry their signatures use, the kit.
pub mod prelude {
    pub use super::{Accept, Failed, Passed, Settings, cells, exit_faces, triangles};
    pub use crate::choice::Model;
    pub use crate::family::contract::{Contract, EntryGiven, Orientation, Origin, Origins};
    pub use crate::methods::triangle::{HitMethod, SingleRay};
    pub use crate::methods::{Arith, CellMethod, ExitMethod, Plain};
    pub use crate::octree::cell;
    pub use crate::tet::{FACE_VERTICES, Ray, Tet, Tri};
    pub use glam::Vec3;
}

use crate::choice::Model;

/// How much a run asks, and which failures the user accepts.
#[derive(Clone, Debug)]
pub struct Settings {
    /// Cases per stress row (a ray–triangle row takes a tenth: there are 75).
    pub cases: usize,
    /// Random inputs of each property campaign (walks take an eighth).
    pub properties: usize,
    /// Seed of the stress rows and campaigns (the same seed, the same cases).
    pub seed: u64,
    /// The arithmetic the method computes in, one of the list tetwalk's CPU backends run
    /// ([`Model::ALL`]): plain f32 (`Plain`), fused multiply-adds as a GPU compiler may compile it
    /// (`Fused`), subnormals flushed (`Flushed`), both (`FusedFlushed`, as an NVIDIA GPU computes).
    /// A method that computes with glam's own operations rather than the model's
    /// ([`crate::methods::Arith`]) runs in plain f32 whatever is chosen.
    pub model: Model,
    /// Which failures pass.
    pub accept: Accept,
    /// What the method assumes of its cases (docs/answerers.md, "Contracts"): every stress row's and
    /// campaign's case is made to hold it, and a failure is shrunk inside it. Exit faces take every
    /// field; the other families a unit direction (the rest is not theirs to hold).
    pub contract: crate::family::contract::Contract,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            cases: 1000,
            properties: 2000,
            seed: 1,
            model: Model::Plain,
            accept: Accept::default(),
            contract: Default::default(),
        }
    }
}

/// Failures a run lets pass. The default accepts none.
#[derive(Clone, Copy, Debug, Default)]
pub struct Accept {
    /// Wrong exit faces on lines that only touch the closed tetrahedron: the exact line meets it,
    /// but the oracle's symbolically perturbed line (Simulation of Simplicity, as the `exact` walk
    /// perturbs it) misses it, so the line grazes an edge or vertex, or runs along a face, without
    /// crossing the interior. (A touching line that the perturbation keeps on the tetrahedron is
    /// judged like any other.)
    pub touch_only: bool,
    /// Failures per million judged cases each group may have.
    pub per_million: f64,
    /// Judge only what the family's claim promises, not every answer: for ray–triangle tests, leaks
    /// (a ray through a closed surface that hits none of it: the watertight claim), not every first
    /// hit.
    pub claim_only: bool,
}

/// One group of a run: its name, cases judged, failures.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Group {
    /// The group: a stress row or a property campaign.
    pub name: String,
    /// Cases judged in it.
    pub judged: u64,
    /// Failures among them (accepted, since the run passed).
    pub failed: u64,
}

/// A run that passed: each group, its failures accepted.
#[derive(Clone, Debug, Default)]
pub struct Passed {
    /// Each group run, in order.
    pub groups: Vec<Group>,
}

impl fmt::Display for Passed {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        for g in &self.groups {
            let failures = if g.failed == 1 { "failure" } else { "failures" };
            writeln!(
                f,
                "{}: {} judged, {} {failures} accepted",
                g.name, g.judged, g.failed
            )?;
        }
        Ok(())
    }
}

/// Why a run failed: the group, how often, and its first failure written out exactly.
#[derive(Clone)]
pub struct Failed {
    /// The method's name (its type's, without module paths).
    pub method: String,
    /// The method's family (`exit-face`, `walk`, `triangle`, `octree`).
    pub family: &'static str,
    /// The group that failed.
    pub group: String,
    /// Cases judged in that group.
    pub judged: u64,
    /// Failures in it, beyond what the settings accept.
    pub failures: u64,
    /// The failing case alone, shrunk (`tetwalk shrink`: the simplest case the method still fails the
    /// same way), one line of the case format (`tetwalk exit`, `hit` and `judge` read it).
    pub case: String,
    /// The case as the group first found it failing, before it was shrunk.
    pub original: String,
    /// The failure as a found case (`corpora/found/`'s format; `tetwalk replay --found` reads it).
    pub found: String,
    /// What the method answered, in words, and where it ran.
    pub answered: String,
    /// What was right there, in words.
    pub right: String,
    /// Whether the case line, read back, makes the method fail the same way again.
    pub reproduced: bool,
}

/// Failures per million of `of` judged.
fn per_million(n: u64, of: u64) -> f64 {
    if of == 0 {
        0.0
    } else {
        n as f64 * 1e6 / of as f64
    }
}

impl fmt::Display for Failed {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        writeln!(
            f,
            "tetwalk conformance: method `{}` fails {} group `{}`: {} of {} judged cases ({:.0} per million)",
            self.method,
            self.family,
            self.group,
            self.failures,
            self.judged,
            per_million(self.failures, self.judged)
        )?;
        writeln!(f, "  case:     {}", self.case)?;
        writeln!(f, "  original: {}", self.original)?;
        writeln!(f, "  answered: {}", self.answered)?;
        writeln!(f, "  right:    {}", self.right)?;
        write!(f, "  found:    {}", self.found)
    }
}

/// The report itself, so that `.unwrap()` in a test prints it.
impl fmt::Debug for Failed {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        fmt::Display::fmt(self, f)
    }
}

impl std::error::Error for Failed {}

// The entry points, one per family a user's method may belong to (`exit_faces`, `triangles`,
// `cells`): each written in its family's folder (`src/family/NAME/kit.rs`), re-exported from the
// families' list.
crate::families!(__kit_entries);

/// A type's name without its module paths (`Portalez16<Direction>`).
pub(crate) fn short_name<M>() -> &'static str {
    let full = std::any::type_name::<M>();
    let mut out = String::with_capacity(full.len());
    let mut segment = String::new();
    for c in full.chars() {
        if c.is_alphanumeric() || c == '_' {
            segment.push(c);
        } else if c == ':' {
            // A path separator: the segment before it was a module.
            segment.clear();
        } else {
            out.push_str(&segment);
            out.push(c);
            segment.clear();
        }
    }
    out.push_str(&segment);
    Box::leak(out.into_boxed_str())
}
