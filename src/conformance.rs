//! The conformance kit: judge a traversal method written outside tetwalk from its own `cargo test`,
//! with the oracle, stress families, lattice-tie walks, far-offset scenes and fuzz generators that
//! judge tetwalk's methods.
//!
//! A user implements [`ExitMethod`] (or [`HitMethod`], or [`CellMethod`] for an octree cell test) in
//! their crate and calls one function ([`exit_faces`], [`triangles`], [`cells`]):
//!
//! ```no_run
//! use glam::Vec3;
//! use tetwalk::methods::{Arith, ExitMethod};
//! use tetwalk::tet::{Ray, Tet};
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
//!             let [a, b, c] = tetwalk::tet::FACE_VERTICES[f].map(|i| t[i]);
//!             let s = [side(a, b), side(b, c), side(c, a)];
//!             s.iter().all(|&x| x >= 0.0) && s.iter().any(|&x| x != 0.0)
//!         })
//!     }
//! }
//!
//! #[test]
//! fn my_plucker_conforms() {
//!     tetwalk::conformance::exit_faces::<MyPlucker>(&tetwalk::conformance::Settings::default());
//! }
//! ```
//!
//! Each family is run in turn; the first whose failures exceed what [`Accept`] allows stops the run
//! with a [`Failed`] report: the family, the first failing case written out exactly as a found case
//! (`corpora/found/`'s format, which `tetwalk exit`, `hit` and `judge` read), the method's answer
//! and every right answer. `examples/conformance/` is a complete user crate.

use crate::backend::{Backend, CPU, CPU_FMA};
use crate::cases::{BoxCase, HitCase, Subject, classify, judge_hit, judged, normalized};
use crate::choice::Choice;
use crate::exact::perturbed_exit;
use crate::found::{Answer, Failure, Record};
use crate::methods::Model;
use crate::methods::triangle::{HitMethod, nearest_of};
use crate::methods::{CellMethod, ExitMethod};
use crate::octree::cell::quarter_signs;
use crate::registry::{Method, OctreeMethod, TriangleMethod, reference};
use crate::report::stress::{self, Row};
use crate::report::triangle::{StressSettings, row_cases};
use crate::scenes::closed::{Aim, Place, Shape};
use crate::scenes::{self, Generated, from_bytes};
use crate::walk::{Outcome, Walk, default_max_steps, locate, same_result};
use glam::Vec3;
use rand::RngExt;
use std::fmt;

/// How much a run asks, and which failures the user accepts.
#[derive(Clone, Debug)]
pub struct Settings {
    /// Cases per stress row (exit faces: every [`Row`]; triangles: every shape, aim and place).
    pub cases: usize,
    /// Rays per lattice-tie scene ([`WALK_SCENES`]).
    pub rays: usize,
    /// Random inputs of the property campaign (the fuzz targets' generators).
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
            rays: 1000,
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
    /// Failures per million judged cases each family may have (the property campaign's included).
    pub per_million: f64,
    /// For ray–triangle methods, judge only leaks (a ray through a closed surface that hits none of
    /// it: the watertight claim), not every first hit.
    pub leaks_only: bool,
}

/// The scenes of the lattice-tie walks: mesh, size and offset along (1, 1, 1) (half of each scene's
/// rays aimed exactly through mesh vertices and edges, [`scenes::rays`]).
pub const WALK_SCENES: [(Generated, u32, f32); 5] = [
    (Generated::Kuhn, 8, 0.0),
    (Generated::Kuhn, 8, 1_048_576.0),
    (Generated::Jitter, 8, 0.0),
    (Generated::Jitter, 8, 65536.0),
    (Generated::Fan, 4, 0.0),
];

/// A run that passed: per family, cases judged and failures accepted.
#[derive(Clone, Debug, Default)]
pub struct Passed {
    pub families: Vec<(String, u64, u64)>,
}

impl fmt::Display for Passed {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        for (family, judged, failed) in &self.families {
            writeln!(f, "{family}: {judged} judged, {failed} failures accepted")?;
        }
        Ok(())
    }
}

/// Why a run failed: the family, how often, and its first failure written out exactly: the case
/// (one line of the case format), the answer, the right answers, and the found-case line
/// (`corpora/found/`'s format).
#[derive(Clone, Debug)]
pub struct Failed {
    pub method: String,
    pub family: String,
    pub judged: u64,
    pub failures: u64,
    /// The first failure as a found case (`corpora/found/`'s format).
    pub record: Record,
    /// What was right there, in words.
    pub right: String,
}

impl fmt::Display for Failed {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        writeln!(
            f,
            "tetwalk conformance: method `{}` fails family `{}`: {} of {} judged cases ({:.0} per million)",
            self.method,
            self.family,
            self.failures,
            self.judged,
            stress::Tally::per_million(self.failures, self.judged)
        )?;
        writeln!(f, "  case:     {}", self.case())?;
        if let Some(x) = &self.record.failure {
            writeln!(
                f,
                "  answered: {} (backend {})",
                describe(&x.answer),
                x.backend.name()
            )?;
        }
        writeln!(f, "  right:    {}", self.right)?;
        write!(f, "  found:    {}", self.record.to_json())
    }
}

impl Failed {
    /// The failing case alone, one line of the case format (`tetwalk exit`, `hit`, `judge` and
    /// `gen-cases` use it).
    pub fn case(&self) -> String {
        serde_json::Value::Object(self.record.subject.to_json()).to_string()
    }
}

/// An answer in words.
fn describe(a: &Answer) -> String {
    match a {
        Answer::Face(Some(f)) => format!("exit face {f}"),
        Answer::Face(None) => "no exit face".into(),
        Answer::Walk(o) => outcome(o),
        Answer::Hit(Some((tri, t))) => format!("triangle {tri} at t = {t:e}"),
        Answer::Hit(None) => "no hit".into(),
        Answer::Box(Some((f, q))) => format!(
            "exit face {} quarter {q:?}",
            crate::octree::cell::FACE_NAMES[*f as usize]
        ),
        Answer::Box(None) => "no exit face".into(),
    }
}

fn outcome(o: &Outcome) -> String {
    match *o {
        Outcome::Hit { tet, face } => {
            format!("stops on constrained face {face} of tetrahedron {tet}")
        }
        Outcome::LeftMesh { tet, face } => {
            format!("leaves the mesh through face {face} of tetrahedron {tet}")
        }
        Outcome::NoExitFace { tet } => format!("finds no exit face in tetrahedron {tet}"),
        Outcome::Cycle { tet, period } => {
            format!("endless walk: a cycle of period {period} through tetrahedron {tet}")
        }
        Outcome::StepLimit { tet } => {
            format!("endless walk: step limit reached in tetrahedron {tet}")
        }
    }
}

/// One family's count and its first failure.
struct Family {
    name: String,
    judged: u64,
    failures: u64,
    first: Option<(Record, String)>,
}

impl Family {
    fn new(name: impl Into<String>) -> Family {
        Family {
            name: name.into(),
            judged: 0,
            failures: 0,
            first: None,
        }
    }

    fn fail(&mut self, record: impl FnOnce() -> (Record, String)) {
        self.failures += 1;
        if self.first.is_none() {
            self.first = Some(record());
        }
    }

    /// Passed, or failed beyond the budget.
    fn close(self, method: &str, accept: &Accept, passed: &mut Passed) -> Result<(), Box<Failed>> {
        let over = self.failures > 0
            && stress::Tally::per_million(self.failures, self.judged) > accept.per_million;
        match self.first {
            Some((record, right)) if over => Err(Box::new(Failed {
                method: method.into(),
                family: self.name,
                judged: self.judged,
                failures: self.failures,
                record,
                right,
            })),
            _ => {
                passed
                    .families
                    .push((self.name, self.judged, self.failures));
                Ok(())
            }
        }
    }
}

fn backend(s: &Settings) -> &'static Backend {
    if s.fma { &CPU_FMA } else { &CPU }
}

fn record(m: &str, s: &Settings, subject: Subject, answer: Answer) -> Record {
    let b = backend(s);
    Record {
        subject,
        failure: Some(Failure {
            method: m.into(),
            backend: b.kind(),
            adapter: None,
            answer,
        }),
    }
}

/// Judge exit-face method `M` ([`check_exit_faces`]); panics with the report when it fails, for a
/// user's `cargo test`.
pub fn exit_faces<M: ExitMethod>(s: &Settings) -> Passed {
    check_exit_faces::<M>(std::any::type_name::<M>(), s).unwrap_or_else(|f| panic!("{f}"))
}

/// Judge exit-face method `M` (reported as `name`) exactly: every stress row of `tetwalk stress`,
/// walks through [`WALK_SCENES`] (a cycle or step limit is an endless walk), then a property campaign
/// of random inputs through the `exit_face` and `walk` fuzz targets' generators.
pub fn check_exit_faces<M: ExitMethod>(
    name: &'static str,
    s: &Settings,
) -> Result<Passed, Box<Failed>> {
    let m = Method::outside::<M>(name);
    let mut passed = Passed::default();
    let st = stress::Settings {
        cases: s.cases,
        rows: Row::ALL.to_vec(),
        seed: s.seed,
        backend: backend(s).kind().name().into(),
        flatness: 1e-3,
        ulps: 4,
        relabel: [0, 1, 2, 3],
    };
    // Rows are generated in parallel but judged in order, so the first failure is the same each run.
    for &row in Row::ALL {
        let mut fam = Family::new(format!("stress row {}", row.name()));
        let one = stress::Settings {
            rows: vec![row],
            ..st.clone()
        };
        let report = stress::run(&one, &[&m], backend(s), &|_| {}, &mut |_, _, c, f| {
            let Ok(x) = classify(c) else { return };
            if s.accept.touch_only && touch_only(c) {
                return;
            }
            fam.fail(|| {
                (
                    record(name, s, Subject::Exit(*c), Answer::Face(f.map(|f| f as u8))),
                    format!(
                        "exit faces {:?} (entry faces {:?})",
                        x.exit.to_vec(),
                        x.entry.to_vec()
                    ),
                )
            });
        })
        .expect("the CPU answers every case");
        fam.judged = report.rows[0].tallies[0].judged;
        fam.close(name, &s.accept, &mut passed)?;
    }
    for (kind, size, offset) in WALK_SCENES {
        let mut fam = Family::new(format!(
            "lattice-tie walks {} size {size} offset {offset}",
            kind.name()
        ));
        walk_scene(&m, s, (kind, size, offset), &mut fam);
        fam.close(name, &s.accept, &mut passed)?;
    }
    let mut fam = Family::new("property campaign (exit_face and walk generators)");
    let mut rng = scenes::rng(s.seed ^ 0xc0f0_4a11);
    for i in 0..s.properties {
        let bytes: Vec<u8> = (0..rng.random_range(16..160))
            .map(|_| rng.random())
            .collect();
        let mut u = arbitrary::Unstructured::new(&bytes);
        if i % 8 == 7 {
            let Ok(w) = from_bytes::walk_case(&mut u) else {
                continue;
            };
            let Ok(mesh) = scenes::generated_mesh(w.mesh, w.size, Vec3::splat(w.offset), 1) else {
                continue;
            };
            judge_walks(&m, s, &mesh, &[(w, w.ray())], &mut fam);
        } else {
            let Ok(Some(c)) = from_bytes::exit_case(&mut u) else {
                continue;
            };
            let Ok(x) = classify(&c) else { continue };
            if !x.meets() {
                continue;
            }
            fam.judged += 1;
            let f = backend(s)
                .exit_face(&m, &c)
                .expect("the CPU answers every case");
            let j = judged(&x, f);
            if j.correct == Some(false) && !(s.accept.touch_only && touch_only(&c)) {
                fam.fail(|| {
                    (
                        record(name, s, Subject::Exit(c), Answer::Face(j.face)),
                        format!(
                            "exit faces {:?} (entry faces {:?})",
                            j.exact_exit, j.exact_entry
                        ),
                    )
                });
            }
        }
    }
    fam.close(name, &s.accept, &mut passed)?;
    Ok(passed)
}

/// Whether the case's line only touches its tetrahedron ([`Accept::touch_only`]).
fn touch_only(c: &crate::tet::Case) -> bool {
    let (tet, _, _) = normalized(c);
    perturbed_exit(&tet, &c.ray()).is_ok_and(|(face, x)| face.is_none() && x.meets())
}

/// `m`'s walks of one scene's rays, each judged against the exact walk.
fn walk_scene(
    m: &Method,
    s: &Settings,
    (kind, size, offset): (Generated, u32, f32),
    fam: &mut Family,
) {
    let at = Vec3::splat(offset);
    let mesh = scenes::generated_mesh(kind, size, at, 1).expect("the kit's scenes are valid");
    let rays: Vec<_> = scenes::rays(kind, &mesh, at, s.rays, s.seed)
        .into_iter()
        .map(|r| {
            let w = from_bytes::WalkCase {
                mesh: kind,
                size,
                offset,
                org: r.org.to_array(),
                dir: r.dir.to_array(),
            };
            (w, r)
        })
        .collect();
    judge_walks(m, s, &mesh, &rays, fam);
}

/// Walk each ray that starts inside `mesh` with `m` and with the reference, judging the ending
/// ([`same_result`]).
fn judge_walks(
    m: &Method,
    s: &Settings,
    mesh: &crate::mesh::Mesh,
    rays: &[(from_bytes::WalkCase, crate::tet::Ray)],
    fam: &mut Family,
) {
    let max = default_max_steps(mesh);
    let started: Vec<_> = rays
        .iter()
        .filter_map(|(w, r)| Some((*w, *r, locate(mesh, r.org, 0).ok()?)))
        .collect();
    let asked: Vec<_> = started.iter().map(|(_, r, t)| (*r, *t)).collect();
    let walk = |m: &Method, b: &Backend| -> Vec<Walk> {
        b.walks_from(m, &b.mesh(mesh), &asked, max)
            .expect("the CPU answers every case")
            .walks
    };
    let got = walk(m, backend(s));
    let exact = walk(reference(), &CPU);
    for (((w, r, _), g), e) in started.iter().zip(&got).zip(&exact) {
        fam.judged += 1;
        if !same_result(mesh, r, g, e) {
            fam.fail(|| {
                (
                    record(m.name, s, Subject::Walk(*w), Answer::Walk(g.outcome)),
                    format!("the exact walk {}", outcome(&e.outcome)),
                )
            });
        }
    }
}

/// Judge octree cell method `M` ([`check_cells`]); panics with the report when it fails.
pub fn cells<M: CellMethod>(s: &Settings) -> Passed {
    check_cells::<M>(std::any::type_name::<M>(), s).unwrap_or_else(|f| panic!("{f}"))
}

/// Judge octree cell method `M` (reported as `name`) exactly: every row of `tetwalk stress --family
/// octree` (27 rows: aims × places, `cases` cells and rays each), then a property campaign through the
/// `octree_cell` fuzz target's generator. A failure is an exit face the line does not leave through,
/// or a quarter (neighbour) the exit point is not in.
pub fn check_cells<M: CellMethod>(name: &'static str, s: &Settings) -> Result<Passed, Box<Failed>> {
    use crate::scenes::cells;
    let m = OctreeMethod::outside::<M>(name);
    let mut passed = Passed::default();
    for &aim in cells::Aim::ALL {
        for &place in cells::Place::ALL {
            let st = crate::report::octree::StressSettings {
                cases: s.cases,
                aims: vec![aim],
                places: vec![place],
                seed: s.seed,
                backend: backend(s).kind().name().into(),
                ulps: 4,
            };
            let mut fam = Family::new(format!("stress row {}-{}", aim.name(), place.name()));
            let report = crate::report::octree::stress(&st, &[&m], backend(s), &mut |_, r| {
                fam.fail(|| {
                    let right = cell_truth(&r.subject);
                    (r, right)
                })
            })
            .expect("the CPU answers every case");
            fam.judged = report.rows[0].tallies[0].judged;
            fam.close(name, &s.accept, &mut passed)?;
        }
    }
    let mut fam = Family::new("property campaign (octree_cell generator)");
    let mut rng = scenes::rng(s.seed ^ 0x0c7e_e11a);
    for _ in 0..s.properties {
        let bytes: Vec<u8> = (0..rng.random_range(16..64))
            .map(|_| rng.random())
            .collect();
        let mut u = arbitrary::Unstructured::new(&bytes);
        let Ok((lo, hi, ray)) = from_bytes::cell_case(&mut u) else {
            continue;
        };
        let c = BoxCase {
            lo,
            hi,
            org: ray.org,
            dir: ray.dir,
        };
        let Ok(x) = crate::exact::boxes::box_exit(lo, hi, &ray) else {
            continue;
        };
        let got = m.exit(if s.fma { Model::Fused } else { Model::Plain })(lo, hi, &ray)
            .map(|(f, q)| (f, quarter_signs(q)));
        let Some(right) = x.right(got) else { continue };
        fam.judged += 1;
        if !right {
            fam.fail(|| {
                let subject = Subject::Box(c);
                let answer = Answer::Box(got.map(|(f, q)| (f as u8, q)));
                (record(name, s, subject, answer), cell_truth(&subject))
            });
        }
    }
    fam.close(name, &s.accept, &mut passed)?;
    Ok(passed)
}

/// The exact exit faces and quarters of a box case, in words.
fn cell_truth(subject: &Subject) -> String {
    let Subject::Box(c) = subject else {
        return String::new();
    };
    match crate::exact::boxes::box_exit(c.lo, c.hi, &c.ray()) {
        Ok(x) => x
            .faces
            .iter()
            .zip(&x.quarters)
            .map(|(f, q)| {
                format!(
                    "exit face {} quarters {q:?}",
                    crate::octree::cell::FACE_NAMES[*f]
                )
            })
            .collect::<Vec<_>>()
            .join("; "),
        Err(e) => e.to_string(),
    }
}

/// Judge ray–triangle method `M` ([`check_triangles`]); panics with the report when it fails.
pub fn triangles<M: HitMethod>(s: &Settings) -> Passed {
    check_triangles::<M>(std::any::type_name::<M>(), s).unwrap_or_else(|f| panic!("{f}"))
}

/// Judge ray–triangle method `M` (reported as `name`) exactly on closed meshes: every row of `tetwalk
/// stress --family triangle` (75 rows: shapes × aims × places, `cases / 10` rays each), then a
/// property campaign through the `triangle_hit` fuzz target's generator. A failure is a wrong first
/// hit, or with [`Accept::leaks_only`] a leak.
pub fn check_triangles<M: HitMethod>(
    name: &'static str,
    s: &Settings,
) -> Result<Passed, Box<Failed>> {
    let m = TriangleMethod::outside::<M>(name);
    let mut passed = Passed::default();
    let st = StressSettings {
        cases: (s.cases / 10).max(1),
        shapes: Shape::ALL.to_vec(),
        aims: Aim::ALL.to_vec(),
        places: Place::ALL.to_vec(),
        seed: s.seed,
        backend: backend(s).kind().name().into(),
        flatness: 1e-3,
        ulps: 4,
    };
    let mut row = 0;
    for &shape in Shape::ALL {
        for &aim in Aim::ALL {
            for &place in Place::ALL {
                let mut fam = Family::new(format!(
                    "stress row {}-{}-{}",
                    shape.name(),
                    aim.name(),
                    place.name()
                ));
                let cases = row_cases(&st, (shape, aim, place), row);
                row += 1;
                judge_hits(&m, s, &cases, &mut fam);
                fam.close(name, &s.accept, &mut passed)?;
            }
        }
    }
    let mut fam = Family::new("property campaign (triangle_hit generator)");
    let mut rng = scenes::rng(s.seed ^ 0x7a1a_6e1e);
    let mut cases = Vec::new();
    for _ in 0..s.properties {
        let bytes: Vec<u8> = (0..rng.random_range(16..96))
            .map(|_| rng.random())
            .collect();
        let mut u = arbitrary::Unstructured::new(&bytes);
        let Ok((tris, ray)) = from_bytes::hit_case(&mut u) else {
            continue;
        };
        let Ok(c) = HitCase::closed(&tris, ray) else {
            continue;
        };
        if let Ok(t) = judge_hit(&c) {
            cases.push((c, t));
        }
    }
    judge_hits(&m, s, &cases, &mut fam);
    fam.close(name, &s.accept, &mut passed)?;
    Ok(passed)
}

fn judge_hits(
    m: &TriangleMethod,
    s: &Settings,
    cases: &[(HitCase, crate::cases::HitTruth)],
    fam: &mut Family,
) {
    let asked: Vec<HitCase> = cases.iter().map(|(c, _)| *c).collect();
    let hits = backend(s)
        .triangle_hits(m, &asked)
        .expect("the CPU answers every case");
    for ((c, truth), h) in cases.iter().zip(&hits) {
        fam.judged += 1;
        let nearest = nearest_of(h);
        let wrong = if s.accept.leaks_only {
            truth.leaks(&h.iter().map(|&(i, _)| i).collect::<Vec<_>>())
        } else {
            !truth.right(nearest.map(|(i, _)| i))
        };
        if wrong {
            fam.fail(|| {
                let right = match truth.first() {
                    Some(p) => format!(
                        "a hit on triangle {:?} at exact t = {} (or, where the ray only touches there, the next crossing)",
                        p.holding, p.t
                    ),
                    None => "no hit".into(),
                };
                (
                    record(m.name, s, Subject::Hit(*c), Answer::Hit(nearest)),
                    right,
                )
            });
        }
    }
}
