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

use crate::backend::{Backend, CPU, CPU_FMA};
use crate::engine::found::Found;
use crate::engine::shrink;
use crate::engine::stress::{StressSettings, judge, row_cases};
use crate::family::{self, ExitFace, Family, OctreeCells, Triangle, Verdict, Walks};
use crate::methods::triangle::HitMethod;
use crate::methods::{CellMethod, ExitMethod};
use crate::registry::{Method, Named, OctreeMethod, TriangleMethod};
use rand::RngExt;
use std::fmt;

/// What a user's crate names: the method traits, the geometry their signatures use, the kit.
pub mod prelude {
    pub use super::{Accept, Failed, Passed, Settings, cells, exit_faces, triangles};
    pub use crate::methods::triangle::{HitMethod, SingleRay};
    pub use crate::methods::{Arith, CellMethod, ExitMethod, Plain};
    pub use crate::octree::cell;
    pub use crate::tet::{FACE_VERTICES, Ray, Tet, Tri};
    pub use glam::Vec3;
}

/// How much a run asks, and which failures the user accepts.
#[derive(Clone, Debug)]
pub struct Settings {
    /// Cases per stress row (a ray–triangle row takes a tenth: there are 75).
    pub cases: usize,
    /// Random inputs of each property campaign (walks take an eighth).
    pub properties: usize,
    pub seed: u64,
    /// Run the method as a GPU compiler may compile it (`a·b + c` fused, [`crate::methods::Fused`]).
    pub fma: bool,
    pub accept: Accept,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            cases: 1000,
            properties: 2000,
            seed: 1,
            fma: false,
            accept: Accept::default(),
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
    pub name: String,
    pub judged: u64,
    pub failed: u64,
}

/// A run that passed: each group, its failures accepted.
#[derive(Clone, Debug, Default)]
pub struct Passed {
    pub groups: Vec<Group>,
}

impl fmt::Display for Passed {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        for g in &self.groups {
            writeln!(
                f,
                "{}: {} judged, {} failures accepted",
                g.name, g.judged, g.failed
            )?;
        }
        Ok(())
    }
}

/// Why a run failed: the group, how often, and its first failure written out exactly.
#[derive(Clone)]
pub struct Failed {
    pub method: String,
    /// The method's family (`exit-face`, `walk`, `triangle`, `octree`).
    pub family: &'static str,
    pub group: String,
    pub judged: u64,
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

/// Judge exit-face method `M` exactly: every stress row of tetrahedron cases, a property campaign
/// through the `exit_face` fuzz target's generator, then walks through the lattice-tie scenes (a cycle
/// or step limit is an endless walk) and a property campaign through the `walk` target's.
pub fn exit_faces<M: ExitMethod>(s: &Settings) -> Result<Passed, Box<Failed>> {
    let m = Method::outside::<M>(short_name::<M>());
    let mut passed = check::<ExitFace>(&m, s)?;
    passed.groups.extend(check::<Walks>(&m, s)?.groups);
    Ok(passed)
}

/// Judge ray–triangle method `M` exactly on closed meshes: every stress row (shapes × aims × places),
/// then a property campaign through the `triangle_hit` fuzz target's generator. A failure is a wrong
/// first hit, or with [`Accept::claim_only`] a leak.
pub fn triangles<M: HitMethod>(s: &Settings) -> Result<Passed, Box<Failed>> {
    check::<Triangle>(&TriangleMethod::outside::<M>(short_name::<M>()), s)
}

/// Judge octree cell method `M` exactly: every stress row of octree cells (aims × places), then a
/// property campaign through the `octree_cell` fuzz target's generator. A failure is an exit face the
/// line does not leave through, or a quarter (neighbour) the exit point is not in.
pub fn cells<M: CellMethod>(s: &Settings) -> Result<Passed, Box<Failed>> {
    check::<OctreeCells>(&OctreeMethod::outside::<M>(short_name::<M>()), s)
}

/// A type's name without its module paths (`Portalez16<Direction>`).
fn short_name<M>() -> &'static str {
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

/// One group's count and its first failure.
struct Tally<F: Family> {
    name: String,
    judged: u64,
    failures: u64,
    first: Option<Found<F>>,
}

impl<F: Family> Tally<F> {
    fn new(name: String) -> Self {
        Tally {
            name,
            judged: 0,
            failures: 0,
            first: None,
        }
    }

    /// Count one answer; a failure unless the settings accept it.
    fn add(
        &mut self,
        s: &Settings,
        (m, on): (&F::Method, &Backend),
        (case, truth, answer): (&F::Case, &F::Truth, &F::Answer),
        verdict: Verdict,
    ) {
        if verdict == Verdict::NotJudged {
            return;
        }
        self.judged += 1;
        let failed = match s.accept.claim_only {
            true => F::refutes_claim(case, truth, answer),
            false => matches!(verdict, Verdict::Wrong(_)),
        };
        if !failed || (s.accept.touch_only && F::touch_only(case)) {
            return;
        }
        self.failures += 1;
        if self.first.is_none() {
            let failure = crate::engine::found::Failure::of(m, on, *answer);
            self.first = Some(Found::of(*case, failure));
        }
    }

    /// Passed, or failed beyond the budget.
    fn close(self, s: &Settings, m: &F::Method, passed: &mut Passed) -> Result<(), Box<Failed>> {
        let over =
            self.failures > 0 && per_million(self.failures, self.judged) > s.accept.per_million;
        match self.first {
            Some(found) if over => Err(Box::new(failed(
                s,
                m,
                self.name,
                self.judged,
                self.failures,
                found,
            ))),
            _ => {
                passed.groups.push(Group {
                    name: self.name,
                    judged: self.judged,
                    failed: self.failures,
                });
                Ok(())
            }
        }
    }
}

/// The report of a group's first failure, the case read back from its line and judged again.
fn failed<F: Family>(
    s: &Settings,
    m: &F::Method,
    group: String,
    judged: u64,
    failures: u64,
    found: Found<F>,
) -> Failed {
    let original = found.case_line();
    let found = shrink::shrink(m, backend(s), &found.case, &[], shrink::CHECKS)
        .map_or(found.clone(), |x| shrink::shrunk(&found, &x));
    let f = found
        .failure
        .as_ref()
        .expect("a failure records what failed");
    let again = Found::<F>::parse(&found.case_line()).ok().and_then(|back| {
        let truth = F::truth(&back.case).ok()?;
        let now = F::answers(backend(s), m, &[back.case]).ok()?.pop()?;
        let wrong = match s.accept.claim_only {
            true => F::refutes_claim(&back.case, &truth, &now),
            false => matches!(F::verdict(&back.case, &truth, &now), Verdict::Wrong(_)),
        };
        Some(wrong && F::answer_json(&now) == F::answer_json(&f.answer))
    });
    Failed {
        method: m.name().to_string(),
        family: F::NAME,
        group,
        judged,
        failures,
        case: found.case_line(),
        original,
        found: found.to_json(),
        answered: format!(
            "{} (backend {})",
            F::describe(&f.answer),
            crate::choice::Choice::name(f.backend)
        ),
        right: F::truth(&found.case)
            .map_or_else(|e| e.to_string(), |t| F::right_answers(&found.case, &t)),
        reproduced: again == Some(true),
    }
}

fn backend(s: &Settings) -> &'static Backend {
    if s.fma { &CPU_FMA } else { &CPU }
}

/// Judge method `m` of family `F` exactly, group by group: every stress row of the family (the
/// engine's rows and judging, as `tetwalk stress` runs them), then a property campaign of random
/// inputs through the family's fuzz target's generator.
pub fn check<F: Family>(m: &F::Method, s: &Settings) -> Result<Passed, Box<Failed>> {
    let on = backend(s);
    let st = StressSettings::<F> {
        cases: F::kit_row_cases(s.cases),
        rows: F::Rows::default(),
        seed: s.seed,
        backend: on.ran(),
        scale: Default::default(),
    };
    let mut passed = Passed::default();
    for row in F::rows(&st.rows) {
        let mut t = Tally::<F>::new(format!("stress row {}", F::row_name(&row)));
        let cases = row_cases(&st, row).0;
        judge(&st, m, on, &cases, |c, x, a, v| {
            t.add(s, (m, on), (c, x, a), v)
        })
        .expect("the CPU answers every case");
        t.close(s, m, &mut passed)?;
    }
    let mut t = Tally::<F>::new(format!("property campaign ({} generator)", F::FUZZ_TARGET));
    let salt = F::NAME
        .bytes()
        .fold(0xc0f0_4a11u64, |h, b| h.rotate_left(5) ^ b as u64);
    let mut rng = crate::scenes::rng(s.seed ^ salt);
    let mut cases = Vec::new();
    for _ in 0..F::kit_properties(s.properties) {
        let bytes: Vec<u8> = (0..rng.random_range(16..160))
            .map(|_| rng.random())
            .collect();
        if let Some(c) = F::arbitrary(&mut arbitrary::Unstructured::new(&bytes))
            && let Ok(x) = F::truth(&c)
        {
            cases.push((c, x));
        }
    }
    let asked: Vec<F::Case> = cases.iter().map(|(c, _)| *c).collect();
    let answers = F::answers(on, m, &asked).expect("the CPU answers every case");
    for ((c, x), a) in cases.iter().zip(&answers) {
        t.add(s, (m, on), (c, x, a), F::verdict(c, x, a));
    }
    t.close(s, m, &mut passed)?;
    Ok(passed)
}

/// A registered method of family `F` run through the kit, by name (tetwalk's own tests check that
/// the kit fails a method exactly where `tetwalk stress` counts it).
pub fn registered<F: Family>(
    name: &str,
    s: &Settings,
) -> Result<Result<Passed, Box<Failed>>, crate::registry::UnknownMethod> {
    Ok(check::<F>(family::by_name::<F>(name)?, s))
}
