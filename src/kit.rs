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
//!
//! An exit-face run begins with a convention check (the method's answers on well-shaped cases under
//! every face numbering, and with the tetrahedra mirrored), stopping where another convention than
//! tetwalk's fits, and saying which. [`Settings::every_group`] runs every group; [`SCALE_VARIABLE`]
//! scales them all. For a user's own property tests, fuzz targets and regression tests, each family's
//! case type is a [`KitCase`] (decoded from fuzzer bytes, `arbitrary::Arbitrary`, drawn from a stress
//! row, read back from a reported line), [`strategy`] holds proptest strategies of them (the
//! `proptest` feature), and one case is judged with [`judge_exit_face`], [`judge_walk`],
//! [`judge_triangle`] or [`judge_cell`].
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
    pub use super::{
        Accept, Failed, KitCase, Passed, Settings, cells, exit_faces, judge_cell, judge_exit_face,
        judge_triangle, judge_walk, triangles,
    };
    pub use crate::cases::{BoxCase, Case, HitCase, WalkCase};
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
    /// Run every group, each failing one reported ([`Failed::also`]), rather than stop at the first.
    pub every_group: bool,
}

/// The variable that scales every group of a run (nightly runs): `cases` and `properties` are
/// multiplied by its value, a whole number from 1 to 10,000 (unset: 1).
pub const SCALE_VARIABLE: &str = "TETWALK_KIT_SCALE";

impl Default for Settings {
    fn default() -> Self {
        Settings {
            cases: 1000,
            properties: 2000,
            seed: 1,
            model: Model::Plain,
            accept: Accept::default(),
            contract: Default::default(),
            every_group: false,
        }
    }
}

impl Settings {
    /// These settings with `cases` and `properties` times [`SCALE_VARIABLE`]'s value; an error naming
    /// the variable where it holds no whole number from 1 to 10,000.
    pub(crate) fn scaled_by_environment(&self) -> Result<Settings, String> {
        let times = match std::env::var(SCALE_VARIABLE) {
            Err(std::env::VarError::NotPresent) => 1,
            Ok(v) => v
                .trim()
                .parse::<usize>()
                .ok()
                .filter(|n| (1..=10_000).contains(n))
                .ok_or_else(|| {
                    format!("{SCALE_VARIABLE}='{v}' is not a whole number from 1 to 10,000")
                })?,
            Err(e) => return Err(format!("{SCALE_VARIABLE}: {e}")),
        };
        Ok(Settings {
            cases: self.cases.saturating_mul(times),
            properties: self.properties.saturating_mul(times),
            ..self.clone()
        })
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
    /// What the run found beside the failure: the face numbering or orientation the method's answers
    /// fit (the convention check, run first), or why nothing was judged.
    pub note: Option<String>,
    /// The other groups that failed, where [`Settings::every_group`] ran them all.
    pub also: Vec<Failed>,
}

impl Failed {
    /// A run that judged nothing: the settings, the case or the method's convention stop it, `why`.
    pub(crate) fn not_run(method: &str, family: &'static str, group: &str, why: String) -> Failed {
        Failed {
            method: method.to_string(),
            family,
            group: group.to_string(),
            judged: 0,
            failures: 0,
            case: String::new(),
            original: String::new(),
            found: String::new(),
            answered: String::new(),
            right: String::new(),
            reproduced: false,
            note: Some(why),
            also: Vec::new(),
        }
    }
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
        if self.judged == 0 {
            let why = self.note.as_deref().unwrap_or("nothing judged");
            return write!(
                f,
                "tetwalk conformance: method `{}` ({}) not judged in `{}`: {why}",
                self.method, self.family, self.group
            );
        }
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
        // The found line holds the shrunk case and the case as found ("original"): each printed once.
        writeln!(f, "  found:    {}", self.found)?;
        writeln!(f, "  answered: {}", self.answered)?;
        write!(f, "  right:    {}", self.right)?;
        if let Some(note) = &self.note {
            write!(f, "\n  note:     {note}")?;
        }
        for other in &self.also {
            write!(f, "\n{other}")?;
        }
        Ok(())
    }
}

/// The report itself, so that `.unwrap()` in a test prints it.
impl fmt::Debug for Failed {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        fmt::Display::fmt(self, f)
    }
}

impl std::error::Error for Failed {}

/// A case of one of the kit's families — [`crate::cases::Case`] (exit faces),
/// [`crate::cases::WalkCase`] (walks), [`crate::cases::HitCase`] (ray–triangle),
/// [`crate::cases::BoxCase`] (octree cells) — made as the fuzz targets and the stress rows make it,
/// held to a contract, read from a reported line and written as one. Each is also
/// `arbitrary::Arbitrary` through its fuzz target's own decoder (a cargo-fuzz target of yours takes it
/// as its input), and with the `proptest` feature [`strategy`] draws it.
pub trait KitCase: Copy + fmt::Debug + PartialEq + Send + Sync + sealed::Sealed + 'static {
    /// Its family (`exit-face`, `walk`, `triangle`, `octree`).
    const FAMILY: &'static str;
    /// Read a case back from a line a report printed: its `case:` or `original:` line (the case
    /// format), or its `found:` line (a found case, whose failure fields are left aside).
    fn from_line(line: &str) -> Result<Self, crate::cases::CaseError>;
    /// The case as one line of the case format (every number reads back as the same f32).
    fn to_line(&self) -> String;
    /// The case the family's fuzz target decodes from `bytes` (favouring near-degenerate geometry);
    /// `None` for bytes that make none.
    fn from_bytes(bytes: &[u8]) -> Option<Self>;
    /// The case made to hold `contract` (`key` a pure choice per case, such as which cases are
    /// mirrored), judged again as it then is: `None` where it cannot be made to hold it.
    fn within(&self, contract: &crate::family::contract::Contract, key: u64) -> Option<Self>;
    /// The family's stress rows, by name (as `tetwalk stress` and a run's groups name them).
    fn rows() -> Vec<String>;
    /// Case `i` of stress row `row` drawn with `seed`, as `tetwalk stress --seed SEED` draws it; an
    /// error naming the rows where `row` is none of them, `None` where the oracle cannot judge it.
    fn row_case(row: &str, seed: u64, i: usize) -> Result<Option<Self>, crate::cases::CaseError>;
}

/// Only the kit's families' cases are [`KitCase`]s.
pub(crate) mod sealed {
    /// Implemented for each family's case type, in its folder's `kit.rs`.
    pub trait Sealed {}
}

/// proptest strategies for each family's cases (with the `proptest` feature): the fuzz targets'
/// decoder fed random bytes, optionally held to a contract, and the stress rows drawn by seed and
/// index. A user's property test:
///
/// ```ignore
/// use tetwalk::kit::prelude::*;
/// use proptest::prelude::*;
///
/// proptest! {
///     #[test]
///     fn my_plucker_on_fuzzed_tetrahedra(case in tetwalk::kit::strategy::cases::<Case>()) {
///         judge_exit_face::<MyPlucker>(&case, &Settings::default()).map_err(|f| TestCaseError::fail(f.to_string()))?;
///     }
/// }
/// ```
///
/// `PROPTEST_CASES` scales these as proptest scales any strategy; the kit's own groups scale with
/// [`SCALE_VARIABLE`].
#[cfg(feature = "proptest")]
pub mod strategy {
    use super::KitCase;
    use crate::family::contract::Contract;
    use proptest::prelude::*;

    /// Inputs of 16 to 159 bytes, as the kit's property campaigns draw them.
    fn bytes() -> impl Strategy<Value = Vec<u8>> {
        proptest::collection::vec(any::<u8>(), 16..160)
    }

    /// Cases of `C`'s family as its fuzz target decodes random bytes into them (shrunk by shrinking
    /// the bytes).
    pub fn cases<C: KitCase>() -> impl Strategy<Value = C> {
        bytes().prop_filter_map("bytes that decode to no case", |b| C::from_bytes(&b))
    }

    /// Such cases made to hold `contract` ([`KitCase::within`]).
    pub fn cases_within<C: KitCase>(contract: Contract) -> impl Strategy<Value = C> {
        (bytes(), any::<u64>())
            .prop_filter_map("cases that cannot hold the contract", move |(b, k)| {
                C::from_bytes(&b)?.within(&contract, k)
            })
    }

    /// Cases of stress row `row` ([`KitCase::rows`]), each drawn by a seed and an index as `tetwalk
    /// stress` draws them, made to hold `contract` (the default one too: what the rows promise, as
    /// `tetwalk stress` holds them to it); an error naming the rows where `row` is none.
    pub fn row<C: KitCase>(
        row: &str,
        contract: Contract,
    ) -> Result<impl Strategy<Value = C>, crate::cases::CaseError> {
        C::row_case(row, 0, 0)?;
        let row = row.to_string();
        Ok((any::<u64>(), 0..1_000_000usize).prop_filter_map(
            "cases the oracle cannot judge",
            move |(seed, i)| {
                C::row_case(&row, seed, i)
                    .ok()??
                    .within(&contract, i as u64)
            },
        ))
    }
}

// The entry points, one per family a user's method may belong to (`exit_faces`, `triangles`,
// `cells`): each written in its family's folder (`src/family/NAME/kit.rs`), re-exported from the
// families' list.
crate::families!(__kit_entries);

/// A type's name without its module paths (`Portalez16<Direction>`), made once per type (a fuzz
/// target or property test judges one case a call).
pub(crate) fn short_name<M>() -> &'static str {
    use std::collections::HashMap;
    use std::sync::{Mutex, OnceLock};
    static NAMES: OnceLock<Mutex<HashMap<&'static str, &'static str>>> = OnceLock::new();
    let full = std::any::type_name::<M>();
    let mut names = NAMES
        .get_or_init(Default::default)
        .lock()
        .unwrap_or_else(|e| e.into_inner());
    names.entry(full).or_insert_with(|| shortened(full))
}

/// `full` without its module paths, kept for the run's life.
fn shortened(full: &str) -> &'static str {
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

#[cfg(test)]
mod tests {
    /// `TETWALK_KIT_SCALE` multiplies every group's cases; a value that is not a whole number from 1
    /// to 10,000 is an error naming the variable (no other unit test reads it).
    #[test]
    fn the_scale_variable_scales_every_group_or_is_refused() {
        let s = super::Settings::default();
        // SAFETY: no other thread of this test binary reads or writes the variable.
        unsafe { std::env::set_var(super::SCALE_VARIABLE, "3") };
        let scaled = s.scaled_by_environment().unwrap();
        assert_eq!(
            (scaled.cases, scaled.properties),
            (3 * s.cases, 3 * s.properties)
        );
        for bad in ["0", "x", "10001", "-2"] {
            unsafe { std::env::set_var(super::SCALE_VARIABLE, bad) };
            let e = s.scaled_by_environment().unwrap_err();
            assert!(e.contains(super::SCALE_VARIABLE) && e.contains(bad), "{e}");
        }
        unsafe { std::env::remove_var(super::SCALE_VARIABLE) };
        assert_eq!(s.scaled_by_environment().unwrap().cases, s.cases);
    }
}
