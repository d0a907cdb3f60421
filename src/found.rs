//! Found cases: failures kept as readable JSON lines under `corpora/found/<method>/` and replayed by
//! `cargo test` — a case in the one case format ([`crate::cases::Subject`]) plus what failed on it:
//! `"method"`, `"backend"`, `"kind"` (the wrong ending, [`OutcomeKind::wrong_key`]) and `"answer"` (the
//! method's wrong exit face, or its wrong walk). Also the checks that the fuzz targets, import and
//! replay share.

use crate::backend::{Backend, BackendError, BackendKind, CPU, CPU_FMA, CPU_FTZ};
use crate::cases::{BoxCase, CaseError, HitCase, Subject, classify, judge_hit, number, object};
use crate::choice::Choice;
use crate::exact::hit::first_hit;
use crate::methods::Model;
use crate::methods::triangle::nearest_of;
use crate::registry::{
    METHODS, Method, OCTREE_METHODS, OctreeMethod, TRIANGLE_METHODS, TriangleMethod, UnknownMethod,
    by_name, octree_by_name, reference, triangle_by_name,
};
use crate::scenes::from_bytes::WalkCase;
use crate::tet::Tri;
use crate::tet::{Case, Ray};
use crate::walk::{Outcome, OutcomeKind, Walk, default_max_steps, locate, same_result};
use glam::Vec3;
use serde_json::Value;

/// Why a found case cannot be read or replayed.
#[derive(Debug, thiserror::Error)]
pub enum FoundError {
    #[error(transparent)]
    Case(#[from] CaseError),
    #[error(transparent)]
    Method(#[from] UnknownMethod),
    #[error(transparent)]
    Backend(#[from] BackendError),
    #[error("{field}: {why}")]
    Field { field: &'static str, why: String },
    #[error("the walk case's mesh could not be built: {0}")]
    Mesh(String),
    #[error("the walk case's origin is not inside its mesh: {0}")]
    Outside(String),
    #[error("TETWALK_FUZZ_METHOD: {0}")]
    FuzzMethod(UnknownMethod),
    #[error("TETWALK_FUZZ_BACKEND: {0}")]
    FuzzBackend(String),
    /// An octree walk that never ends though every cell's exit it chose was right where judged.
    #[error("endless octree walk: {0}")]
    EndlessWalk(String),
}

/// The variable naming a user's WGSL exit-face function to fuzz (`--wgsl`'s file, on the GPU).
pub const FUZZ_WGSL: &str = "TETWALK_FUZZ_WGSL";

/// Which methods a fuzz run holds to exactness: with `TETWALK_FUZZ_WGSL=FILE`, the user's WGSL
/// function (method `user`) and the reference; else from `TETWALK_FUZZ_METHOD`: `robust` (every method
/// that claims robustness: the reference, `certified`, and the published ones whose papers claim it),
/// `ours` (tetwalk's own, which must never fail), or one method's name (with the reference). Unset, the
/// default compiled in with `TETWALK_FUZZ_DEFAULT` (ClusterFuzzLite's build uses `ours`), else `robust`.
pub fn required_methods() -> Result<Vec<&'static Method>, FoundError> {
    if std::env::var_os(FUZZ_WGSL).is_some() {
        return Ok(vec![
            crate::registry::reference(),
            &crate::registry::USER_WGSL,
        ]);
    }
    let default = option_env!("TETWALK_FUZZ_DEFAULT").unwrap_or("robust");
    let choice = std::env::var("TETWALK_FUZZ_METHOD").unwrap_or_else(|_| default.into());
    match choice.as_str() {
        "robust" => Ok(METHODS.iter().filter(|m| m.claims_robust).collect()),
        "ours" => Ok(METHODS.iter().filter(|m| !m.published).collect()),
        name => {
            let m = by_name(name).map_err(FoundError::FuzzMethod)?;
            Ok(METHODS
                .iter()
                .filter(|x| x.reference || x.name == m.name)
                .collect())
        }
    }
}

/// The ray–triangle methods a fuzz run holds to exactness, from `TETWALK_FUZZ_METHOD`, and whether to
/// their claim only: `robust` or `ours` (the default) hold the methods that claim watertightness to it
/// (no leak: [`crate::cases::HitTruth::leaks`]); a method's name holds that method to every answer.
pub fn required_triangle_methods() -> Result<(Vec<&'static TriangleMethod>, bool), FoundError> {
    let default = option_env!("TETWALK_FUZZ_DEFAULT").unwrap_or("robust");
    let choice = std::env::var("TETWALK_FUZZ_METHOD").unwrap_or_else(|_| default.into());
    match choice.as_str() {
        "robust" | "ours" => Ok((
            TRIANGLE_METHODS
                .iter()
                .filter(|m| m.claims_watertight)
                .collect(),
            true,
        )),
        name => Ok((
            vec![triangle_by_name(name).map_err(FoundError::FuzzMethod)?],
            false,
        )),
    }
}

/// The octree methods a fuzz run holds to exactness, from `TETWALK_FUZZ_METHOD`: `robust` or `ours`
/// (the default) hold the reference only (no octree method's paper claims robustness); a method's
/// name holds that method to every answer.
pub fn required_octree_methods() -> Result<Vec<&'static OctreeMethod>, FoundError> {
    let default = option_env!("TETWALK_FUZZ_DEFAULT").unwrap_or("robust");
    let choice = std::env::var("TETWALK_FUZZ_METHOD").unwrap_or_else(|_| default.into());
    match choice.as_str() {
        "robust" | "ours" => Ok(OCTREE_METHODS.iter().filter(|m| m.reference).collect()),
        name => Ok(vec![octree_by_name(name).map_err(FoundError::FuzzMethod)?]),
    }
}

/// The backends a fuzz run holds the required methods to: the CPU plain, as a GPU compiles the
/// methods, and as a GPU that flushes subnormals computes them.
pub const FUZZ_BACKENDS: [&Backend; 3] = [&CPU, &CPU_FMA, &CPU_FTZ];

/// The GPU a fuzz run with `TETWALK_FUZZ_BACKEND=gpu` holds the methods to, opened once.
static FUZZ_GPU: std::sync::OnceLock<Result<Backend, String>> = std::sync::OnceLock::new();

/// The backends a fuzz run holds the required methods to, from `TETWALK_FUZZ_BACKEND`: `cpu` (the
/// default: [`FUZZ_BACKENDS`]) or `gpu` (the adapter `WGPU_ADAPTER_NAME` names, or the default one;
/// opened with the `TETWALK_FUZZ_WGSL` function spliced in, when set).
pub fn fuzz_backends() -> Result<Vec<&'static Backend>, FoundError> {
    match std::env::var("TETWALK_FUZZ_BACKEND").as_deref() {
        Err(_) | Ok("cpu") if std::env::var_os(FUZZ_WGSL).is_some() => {
            Err(FoundError::FuzzBackend(format!(
                "{FUZZ_WGSL} fuzzes a WGSL function: set TETWALK_FUZZ_BACKEND=gpu"
            )))
        }
        Err(_) | Ok("cpu") => Ok(FUZZ_BACKENDS.to_vec()),
        Ok("gpu") => FUZZ_GPU
            .get_or_init(|| match std::env::var(FUZZ_WGSL) {
                Ok(path) => std::fs::read_to_string(&path)
                    .map_err(|e| format!("{FUZZ_WGSL}={path}: {e}"))
                    .and_then(|src| Backend::gpu_with_user(&path, &src).map_err(|e| e.to_string())),
                Err(_) => Backend::open(BackendKind::Gpu).map_err(|e| e.to_string()),
            })
            .as_ref()
            .map(|g| vec![g])
            .map_err(|why| FoundError::FuzzBackend(why.clone())),
        Ok(other) => Err(FoundError::FuzzBackend(format!(
            "'{other}' is not cpu or gpu"
        ))),
    }
}

/// What a fuzz run finds on one decoded case, on the methods and backends its environment names
/// ([`required_methods`], [`fuzz_backends`]): on the CPU, the case itself; on a GPU, the case and its
/// [`neighbourhood`] in one batch (one dispatch per method), so that each input does a dispatch's
/// worth of work. The exact judge runs on the CPU.
pub fn fuzz_find(subject: &Subject) -> Result<Option<Record>, FoundError> {
    let backends = fuzz_backends()?;
    let subjects = if backends.iter().any(|b| b.kind() == BackendKind::Gpu) {
        neighbourhood(subject)
    } else {
        vec![*subject]
    };
    let found = if let Subject::Box(_) = subject {
        let cases: Vec<BoxCase> = subjects
            .iter()
            .filter_map(|s| match s {
                Subject::Box(b) => Some(*b),
                _ => None,
            })
            .collect();
        check_boxes(&cases, &required_octree_methods()?, &backends)?
    } else if let Subject::Hit(_) = subject {
        let (methods, leaks_only) = required_triangle_methods()?;
        // The watertight claim is for f32 as written, with gradual underflow: with its products fused,
        // woop-watertight leaks (corpora/results/triangle.md), which campaigns file; the claim's
        // fuzzing leaves cpu-fma and cpu-ftz out.
        let backends: Vec<&Backend> = backends
            .into_iter()
            .filter(|b| !leaks_only || b.kind() == BackendKind::Cpu || b.kind() == BackendKind::Gpu)
            .collect();
        let cases: Vec<HitCase> = subjects
            .iter()
            .filter_map(|s| match s {
                Subject::Hit(h) => Some(*h),
                _ => None,
            })
            .collect();
        check_hits(&cases, &methods, &backends, leaks_only)?
    } else {
        check_batch(&subjects, &required_methods()?, &backends)?
    };
    Ok(found.map(|(i, f)| Record {
        subject: subjects[i],
        failure: Some(f),
    }))
}

/// A fuzz target's check of one decoded case ([`fuzz_find`]); a bad environment stops the run.
pub fn fuzz_check(subject: Subject) -> Option<Record> {
    fuzz_find(&subject).unwrap_or_else(|e| match e {
        FoundError::FuzzMethod(_) | FoundError::FuzzBackend(_) => panic!("{e}"),
        _ => None,
    })
}

/// The octree over a fuzz case's closed mesh: deep and fine, so that rays meet many cells.
pub const FUZZ_OCTREE: crate::octree::Settings = crate::octree::Settings {
    depth: 6,
    capacity: 1,
};

/// What a fuzz run finds walking `ray` through seed 001's octree over `tris` ([`FUZZ_OCTREE`]) with
/// each required octree method ([`required_octree_methods`]) on the CPU, plain and fused, each leaf's
/// triangles tested with `mt`: the first cell whose exit face or quarter the method chose wrongly,
/// filed as that cell's box case (the exact reference's walk lists no choices). A walk that cycles or reaches the step limit without a wrong cell
/// (its wrong choice was where the line only touches a cell, which no answer is judged on) is
/// [`FoundError::EndlessWalk`].
pub fn octree_walk_find(tris: &[Tri], ray: &Ray) -> Result<Option<Record>, FoundError> {
    let o = crate::octree::Octree::build(tris, FUZZ_OCTREE).map_err(|e| FoundError::Field {
        field: "tris",
        why: e.to_string(),
    })?;
    let hit = triangle_by_name("mt")?.hit(Model::Plain);
    let cap = crate::walk::octree::default_max_steps(&o);
    for m in required_octree_methods()? {
        for b in FUZZ_BACKENDS {
            let Backend::Cpu { model } = b else { continue };
            let (w, steps) = m.walk_traced(*model)(&o, tris, hit, ray, cap);
            for (cell, exit) in steps {
                let [lo, hi] = o.boxes[cell as usize];
                let x =
                    crate::exact::boxes::box_exit(lo, hi, ray).map_err(|e| FoundError::Field {
                        field: "ray",
                        why: e.to_string(),
                    })?;
                let signs = exit.map(|(f, q)| (f, crate::octree::cell::quarter_signs(q)));
                if x.right(signs) == Some(false) {
                    let subject = Subject::Box(BoxCase {
                        lo,
                        hi,
                        org: ray.org,
                        dir: ray.dir,
                    });
                    let answer = Answer::Box(signs.map(|(f, q)| (f as u8, q)));
                    return Ok(Some(Record {
                        subject,
                        failure: Some(failure_on(m.name, b, answer)),
                    }));
                }
            }
            if matches!(
                w.end,
                crate::walk::octree::End::Cycle { .. } | crate::walk::octree::End::StepLimit { .. }
            ) {
                return Err(FoundError::EndlessWalk(format!(
                    "{} on {:?}: {:?}",
                    m.name,
                    b.kind(),
                    w.end
                )));
            }
        }
    }
    Ok(None)
}

/// Ulps by which [`neighbourhood`] moves each component.
const NEIGHBOUR_ULPS: [i32; 3] = [-1, 0, 1];

/// The case and its neighbours a few ulps away: its ray's direction, then its origin, moved by -1, 0
/// or +1 ulp in each component (53 cases, the case itself first).
pub fn neighbourhood(subject: &Subject) -> Vec<Subject> {
    let ray = subject.ray();
    let moved = |p: Vec3, k: usize| {
        let d = [k % 3, k / 3 % 3, k / 9].map(|i| NEIGHBOUR_ULPS[i]);
        Vec3::new(
            crate::scenes::tets::ulps(p.x, d[0]),
            crate::scenes::tets::ulps(p.y, d[1]),
            crate::scenes::tets::ulps(p.z, d[2]),
        )
    };
    let mut out = vec![*subject];
    for k in (0..27).filter(|&k| k != 13) {
        out.push(subject.with_ray(Ray {
            org: ray.org,
            dir: moved(ray.dir, k),
        }));
    }
    for k in (0..27).filter(|&k| k != 13) {
        out.push(subject.with_ray(Ray {
            org: moved(ray.org, k),
            dir: ray.dir,
        }));
    }
    out.retain(|s| s.ray().dir != Vec3::ZERO && s.ray().dir.is_finite() && s.ray().org.is_finite());
    out
}

/// What a method answered: an exit face (or none) for one tetrahedron, a walk for a walk case, the
/// nearest hit (a triangle and its f32 `t`, or none) for a triangle case.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Answer {
    Face(Option<u8>),
    Walk(Outcome),
    Hit(Option<(u32, f32)>),
    /// An octree cell's exit face (seed 001's numbering) and quarter signs, or none.
    Box(Option<(u8, [i8; 2])>),
}

impl Answer {
    /// The kind of ending this answer is (an exit face counts as a hit).
    pub fn kind(&self) -> OutcomeKind {
        match self {
            Answer::Face(Some(_)) => OutcomeKind::Hit,
            Answer::Face(None) => OutcomeKind::NoExitFace,
            Answer::Walk(o) => o.kind(),
            Answer::Hit(Some(_)) => OutcomeKind::Hit,
            Answer::Hit(None) => OutcomeKind::LeftMesh,
            Answer::Box(Some(_)) => OutcomeKind::Hit,
            Answer::Box(None) => OutcomeKind::NoExitFace,
        }
    }

    fn to_json(self) -> Value {
        match self {
            Answer::Face(f) => serde_json::json!(f),
            Answer::Walk(o) => serde_json::to_value(o).unwrap_or(Value::Null),
            Answer::Hit(h) => h.map_or(
                Value::Null,
                |(tri, t)| serde_json::json!({"tri": tri, "t": t}),
            ),
            Answer::Box(b) => b.map_or(Value::Null, |(f, q)| {
                serde_json::json!({"face": crate::octree::cell::FACE_NAMES[f as usize], "quarter": q})
            }),
        }
    }
}

/// A failure: which method, on which backend, what it answered, and so what kind of wrong it is.
#[derive(Clone, Debug, PartialEq)]
pub struct Failure {
    pub method: String,
    pub backend: BackendKind,
    /// The adapter and driver, for a failure found on a GPU.
    pub adapter: Option<String>,
    pub answer: Answer,
}

impl Failure {
    /// The kind of wrong ([`OutcomeKind::wrong_key`] is its name in files).
    pub fn kind(&self) -> OutcomeKind {
        self.answer.kind()
    }
}

/// One line of the case format, with what failed on it when it is a found case.
#[derive(Clone, Debug, PartialEq)]
pub struct Record {
    pub subject: Subject,
    pub failure: Option<Failure>,
}

/// The fields a found case adds to its case.
const FAILURE_FIELDS: [&str; 5] = ["method", "backend", "adapter", "kind", "answer"];

impl Record {
    /// Read a line: a case, or a found case.
    pub fn parse(line: &str) -> Result<Record, FoundError> {
        let mut obj = object(line)?;
        let subject = Subject::take(&mut obj)?;
        if let Some(k) = obj.keys().find(|k| !FAILURE_FIELDS.contains(&k.as_str())) {
            return Err(CaseError::UnknownField(k.clone()).into());
        }
        if obj.is_empty() {
            return Ok(Record {
                subject,
                failure: None,
            });
        }
        let adapter = obj.remove("adapter");
        let mut field = |k: &'static str| {
            obj.remove(k).ok_or(FoundError::Field {
                field: k,
                why: "missing (a found case has method, backend, kind and answer)".into(),
            })
        };
        let bad = |field: &'static str, why: String| FoundError::Field { field, why };
        let method = field("method")?;
        let method = method.as_str().unwrap_or_default();
        let method = match subject {
            Subject::Hit(_) => triangle_by_name(method)?.name,
            Subject::Box(_) => octree_by_name(method)?.name,
            _ => by_name(method)?.name,
        }
        .to_string();
        let backend = field("backend")?;
        let backend = backend
            .as_str()
            .and_then(BackendKind::from_name)
            .ok_or_else(|| {
                bad(
                    "backend",
                    format!("{backend} is not cpu, cpu-fma, cpu-ftz or gpu"),
                )
            })?;
        let adapter = match adapter {
            None => None,
            Some(Value::String(a)) if backend == BackendKind::Gpu => Some(a),
            Some(v) => {
                return Err(bad(
                    "adapter",
                    format!("{v} is not the name of the GPU a gpu finding was made on"),
                ));
            }
        };
        let kind = field("kind")?;
        let kind = kind
            .as_str()
            .and_then(OutcomeKind::from_wrong_key)
            .ok_or_else(|| bad("kind", format!("{kind} is not a kind of wrong ending")))?;
        let answer = field("answer")?;
        let answer = match subject {
            Subject::Exit(_) => Answer::Face(match &answer {
                Value::Null => None,
                v => Some(
                    v.as_u64()
                        .filter(|&f| f < 4)
                        .ok_or_else(|| bad("answer", format!("{v} is not a face 0..3 or null")))?
                        as u8,
                ),
            }),
            Subject::Walk(_) => Answer::Walk(
                serde_json::from_value(answer).map_err(|e| bad("answer", e.to_string()))?,
            ),
            Subject::Hit(h) => {
                Answer::Hit(hit_answer(&answer, h.tris().len()).map_err(|e| bad("answer", e))?)
            }
            Subject::Box(_) => Answer::Box(box_answer(&answer).map_err(|e| bad("answer", e))?),
        };
        if answer.kind() != kind {
            return Err(bad(
                "kind",
                format!(
                    "'{}' does not match the answer, which is a {}",
                    kind.wrong_key(),
                    answer.kind().wrong()
                ),
            ));
        }
        Ok(Record {
            subject,
            failure: Some(Failure {
                method,
                backend,
                adapter,
                answer,
            }),
        })
    }

    /// The line, as kept in `corpora/found/`.
    pub fn to_json(&self) -> String {
        let mut m = self.subject.to_json();
        if let Some(f) = &self.failure {
            m.insert("method".into(), f.method.clone().into());
            m.insert("backend".into(), f.backend.name().into());
            if let Some(a) = &f.adapter {
                m.insert("adapter".into(), a.clone().into());
            }
            m.insert("kind".into(), f.kind().wrong_key().into());
            m.insert("answer".into(), f.answer.to_json());
        }
        Value::Object(m).to_string()
    }

    /// What identifies the case, whatever failed on it.
    pub fn key(&self) -> String {
        Value::Object(self.subject.to_json()).to_string()
    }

    /// The same case filed for another failure.
    pub fn with_failure(&self, f: Failure) -> Record {
        Record {
            subject: self.subject,
            failure: Some(f),
        }
    }

    /// This finding, and the same case filed for every method that claims robustness and fails on it
    /// too (on the CPU, plain and as a GPU compiles it): a failure of a claim is a finding of its own.
    pub fn with_robust_failures(&self) -> Result<Vec<Record>, FoundError> {
        let mut out = vec![self.clone()];
        let mine = self.failure.as_ref().map(|f| f.method.clone());
        // No octree method's paper claims robustness.
        if let Subject::Box(_) = &self.subject {
            return Ok(out);
        }
        if let Subject::Hit(h) = &self.subject {
            for m in TRIANGLE_METHODS
                .iter()
                .filter(|m| m.claims_watertight && Some(m.name.to_string()) != mine)
            {
                if let Some((_, f)) =
                    check_hits(std::slice::from_ref(h), &[m], &FUZZ_BACKENDS, true)?
                {
                    out.push(self.with_failure(f));
                }
            }
            return Ok(out);
        }
        for m in METHODS
            .iter()
            .filter(|m| m.claims_robust && !m.reference && Some(m.name.to_string()) != mine)
        {
            if let Some(f) = check(&self.subject, &[m], &FUZZ_BACKENDS)? {
                out.push(self.with_failure(f));
            }
        }
        Ok(out)
    }
}

/// The first of `methods` (on each of `backends` in turn) that answers `subject` wrongly, with what it
/// answered; `None` when all are right or the case cannot be judged (a line missing the tetrahedron).
pub fn check(
    subject: &Subject,
    methods: &[&Method],
    backends: &[&Backend],
) -> Result<Option<Failure>, FoundError> {
    Ok(check_batch(std::slice::from_ref(subject), methods, backends)?.map(|(_, f)| f))
}

/// [`check`] over a batch of cases answered together (one call per method and backend): the first
/// wrong one, by index. The cases after the first share its kind, and walk cases its mesh; those of
/// them that cannot be judged (an entry face the moved ray does not enter by, an origin outside the
/// mesh) are left out.
pub fn check_batch(
    subjects: &[Subject],
    methods: &[&Method],
    backends: &[&Backend],
) -> Result<Option<(usize, Failure)>, FoundError> {
    let Some(first) = subjects.first() else {
        return Ok(None);
    };
    let mesh = |s: &Subject| match s {
        Subject::Walk(w) => Some((w.mesh, w.size, w.offset.to_bits())),
        _ => None,
    };
    // The subjects of the first one's kind (and mesh), each with its index in `subjects`.
    let found = match first {
        Subject::Exit(_) => {
            let (index, cases): (Vec<usize>, Vec<Case>) = subjects
                .iter()
                .enumerate()
                .filter_map(|(i, s)| match s {
                    Subject::Exit(c) => Some((i, *c)),
                    _ => None,
                })
                .unzip();
            check_exits(&cases, methods, backends)?.map(|(i, f)| (index[i], f))
        }
        Subject::Walk(_) => {
            let (index, walks): (Vec<usize>, Vec<WalkCase>) = subjects
                .iter()
                .enumerate()
                .filter_map(|(i, s)| match s {
                    Subject::Walk(w) if mesh(s) == mesh(first) => Some((i, *w)),
                    _ => None,
                })
                .unzip();
            check_walks(&walks, methods, backends)?.map(|(i, f)| (index[i], f))
        }
        Subject::Hit(_) => {
            return Err(FoundError::Field {
                field: "method",
                why: "a ray-triangle case is judged by ray-triangle methods (check_hits)".into(),
            });
        }
        Subject::Box(_) => {
            return Err(FoundError::Field {
                field: "method",
                why: "an octree cell case is judged by octree methods (check_boxes)".into(),
            });
        }
    };
    Ok(found)
}

fn check_exits(
    cases: &[Case],
    methods: &[&Method],
    backends: &[&Backend],
) -> Result<Option<(usize, Failure)>, FoundError> {
    let mut judged = Vec::with_capacity(cases.len());
    for (i, case) in cases.iter().enumerate() {
        match classify(case) {
            Ok(c) if c.meets() => judged.push((i, c.exit)),
            Ok(_) => {}
            Err(e) if i == 0 => return Err(e.into()),
            Err(_) => {}
        }
    }
    if judged.is_empty() {
        return Ok(None);
    }
    let asked: Vec<Case> = judged.iter().map(|&(i, _)| cases[i]).collect();
    for m in methods {
        for b in backends {
            let faces = b.exit_faces(m, &asked)?;
            for (face, &(i, exit)) in faces.iter().zip(&judged) {
                if !face.is_some_and(|f| exit.contains(f)) {
                    return Ok(Some((
                        i,
                        failure(m, b, Answer::Face(face.map(|f| f as u8))),
                    )));
                }
            }
        }
    }
    Ok(None)
}

/// What `m` answered wrongly on `b`, recorded with the adapter where `b` is a GPU.
fn failure(m: &Method, b: &Backend, answer: Answer) -> Failure {
    failure_on(m.name, b.for_method(m), answer)
}

/// What method `name` answered wrongly on `on`, with the adapter where `on` is a GPU.
fn failure_on(name: &str, on: &Backend, answer: Answer) -> Failure {
    Failure {
        method: name.into(),
        backend: on.kind(),
        adapter: on.adapter(),
        answer,
    }
}

/// A box case's answer: `{"face": "-x"|"+x"|…, "quarter": [su, sv]}` (signs −1 or +1) or null.
pub fn box_answer(v: &Value) -> Result<Option<(u8, [i8; 2])>, String> {
    if v.is_null() {
        return Ok(None);
    }
    let face = v
        .get("face")
        .and_then(Value::as_str)
        .and_then(crate::octree::cell::face_named)
        .ok_or_else(|| format!("{v}: face must be one of -x, +x, -y, +y, -z, +z"))?;
    let quarter = v
        .get("quarter")
        .and_then(|q| serde_json::from_value::<[i8; 2]>(q.clone()).ok())
        .filter(|q| q.iter().all(|s| s.abs() == 1))
        .ok_or_else(|| format!("{v}: quarter must be [su, sv], each -1 or 1"))?;
    if v.as_object().is_some_and(|o| o.len() != 2) {
        return Err(format!("{v}: holds more than face and quarter"));
    }
    Ok(Some((face as u8, quarter)))
}

/// The first of `methods` (on each of `backends` in turn; the reference on the CPU) whose exit face and
/// quarter of a box case is not an exact one, by index, with its answer.
pub fn check_boxes(
    cases: &[BoxCase],
    methods: &[&OctreeMethod],
    backends: &[&Backend],
) -> Result<Option<(usize, Failure)>, FoundError> {
    let truths = cases
        .iter()
        .map(|c| crate::exact::boxes::box_exit(c.lo, c.hi, &c.ray()))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| FoundError::Field {
            field: "box",
            why: e.to_string(),
        })?;
    for m in methods {
        for b in backends {
            let on = b.for_method(*m);
            for (i, (got, truth)) in b.box_exits(m, cases)?.into_iter().zip(&truths).enumerate() {
                let signs = got.map(|(f, q)| (f, crate::octree::cell::quarter_signs(q)));
                if truth.right(signs) == Some(false) {
                    let answer = Answer::Box(signs.map(|(f, q)| (f as u8, q)));
                    return Ok(Some((i, failure_on(m.name, on, answer))));
                }
            }
        }
    }
    Ok(None)
}

/// A triangle case's recorded answer: `{"tri": i, "t": t}` (a triangle of the case) or null.
fn hit_answer(v: &Value, tris: usize) -> Result<Option<(u32, f32)>, String> {
    if v.is_null() {
        return Ok(None);
    }
    let tri = v
        .get("tri")
        .and_then(Value::as_u64)
        .filter(|&i| (i as usize) < tris)
        .ok_or_else(|| format!("{v}: tri must be a triangle of the case (0..{tris})"))?;
    // The decimal text rounded once to f32, as every number of the case format is.
    let t = v
        .get("t")
        .ok_or_else(|| format!("{v}: t must be a number"))
        .and_then(|t| number(t).map_err(|e| format!("{v}: t: {e}")))?;
    if v.as_object().is_some_and(|o| o.len() != 2) {
        return Err(format!("{v}: holds more than tri and t"));
    }
    Ok(Some((tri as u32, t)))
}

/// The first of `methods` (on each of `backends` in turn) whose nearest hit on a triangle case is
/// wrong ([`crate::cases::HitTruth::right`]), or with `leaks_only` that leaks
/// ([`crate::cases::HitTruth::leaks`]), by index, with its nearest hit.
pub fn check_hits(
    cases: &[HitCase],
    methods: &[&TriangleMethod],
    backends: &[&Backend],
    leaks_only: bool,
) -> Result<Option<(usize, Failure)>, FoundError> {
    let truths = cases.iter().map(judge_hit).collect::<Result<Vec<_>, _>>()?;
    for m in methods {
        for b in backends {
            let hits = b.triangle_hits(m, cases)?;
            for (i, (h, truth)) in hits.iter().zip(&truths).enumerate() {
                let nearest = nearest_of(h);
                let wrong = if leaks_only {
                    truth.leaks(&h.iter().map(|&(i, _)| i).collect::<Vec<_>>())
                } else {
                    !truth.right(nearest.map(|(tri, _)| tri))
                };
                if wrong {
                    let f = Failure {
                        method: m.name.into(),
                        backend: b.kind(),
                        adapter: b.adapter(),
                        answer: Answer::Hit(nearest),
                    };
                    return Ok(Some((i, f)));
                }
            }
        }
    }
    Ok(None)
}

/// A walk case's mesh, start and ray.
pub struct WalkSetup {
    pub mesh: std::sync::Arc<crate::mesh::Mesh>,
    pub start: u32,
    pub max_steps: u32,
}

impl WalkSetup {
    pub fn new(w: &WalkCase) -> Result<WalkSetup, FoundError> {
        let mesh = generated(w)?;
        let start =
            locate(&mesh, w.ray().org, 0).map_err(|e| FoundError::Outside(e.to_string()))?;
        let max_steps = default_max_steps(&mesh);
        Ok(WalkSetup {
            mesh,
            start,
            max_steps,
        })
    }

    /// `m`'s walk on `backend`.
    pub fn walk(&self, m: &Method, backend: &Backend, w: &WalkCase) -> Result<Walk, FoundError> {
        Ok(self.walks(m, backend, &[(w.ray(), self.start)])?[0])
    }

    /// `m`'s walks of rays through this mesh, each from its start, on `backend`.
    pub fn walks(
        &self,
        m: &Method,
        backend: &Backend,
        rays: &[(Ray, u32)],
    ) -> Result<Vec<Walk>, FoundError> {
        let on = backend.mesh(&self.mesh);
        Ok(backend.walks_from(m, &on, rays, self.max_steps)?.walks)
    }

    /// Whether `got` ends rightly for `ray`: the reference against the brute-force first hit, every
    /// other method against the reference walk `exact`.
    pub fn right(&self, m: &Method, ray: &Ray, got: &Walk, exact: &Walk) -> bool {
        if !m.reference {
            return same_result(&self.mesh, ray, got, exact);
        }
        match (got.outcome, first_hit(&self.mesh, ray)) {
            (Outcome::LeftMesh { .. }, None) => true,
            (Outcome::Hit { tet, face }, Some((_, faces))) => {
                faces.contains(&(tet, face)) || same_result(&self.mesh, ray, got, exact)
            }
            _ => false,
        }
    }
}

/// A generated mesh's key (kind, size, offset bits) and the mesh.
type CachedMesh = (
    (crate::scenes::Generated, u32, u32),
    std::sync::Arc<crate::mesh::Mesh>,
);

thread_local! {
    /// Generated meshes by (kind, size, offset): walk cases (fuzz inputs above all) use few of them.
    static MESHES: std::cell::RefCell<Vec<CachedMesh>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// A walk case's mesh, built once per thread and kept (the last 64).
fn generated(w: &WalkCase) -> Result<std::sync::Arc<crate::mesh::Mesh>, FoundError> {
    let key = (w.mesh, w.size, w.offset.to_bits());
    if let Some(m) = MESHES.with(|c| {
        c.borrow()
            .iter()
            .find(|(k, _)| *k == key)
            .map(|(_, m)| m.clone())
    }) {
        return Ok(m);
    }
    let mesh = std::sync::Arc::new(
        crate::scenes::generated_mesh(w.mesh, w.size, Vec3::splat(w.offset), 1)
            .map_err(|e| FoundError::Mesh(e.to_string()))?,
    );
    MESHES.with(|c| {
        let mut c = c.borrow_mut();
        if c.len() == 64 {
            c.remove(0);
        }
        c.push((key, mesh.clone()));
    });
    Ok(mesh)
}

fn check_walks(
    ws: &[WalkCase],
    methods: &[&Method],
    backends: &[&Backend],
) -> Result<Option<(usize, Failure)>, FoundError> {
    // A case whose mesh cannot be built or whose origin is outside it judges nothing.
    let Some(Ok(setup)) = ws.first().map(WalkSetup::new) else {
        return Ok(None);
    };
    let judged: Vec<(usize, (Ray, u32))> = ws
        .iter()
        .enumerate()
        .filter_map(|(i, w)| {
            let start = locate(&setup.mesh, w.ray().org, setup.start).ok()?;
            Some((i, (w.ray(), start)))
        })
        .collect();
    let rays: Vec<(Ray, u32)> = judged.iter().map(|(_, r)| *r).collect();
    let exact = setup.walks(reference(), &CPU, &rays)?;
    let mut done = Vec::new();
    for m in methods {
        for b in backends {
            // The reference runs on the CPU whatever the backend: walk it once.
            let key = (m.name, b.for_method(*m).kind());
            if done.contains(&key) {
                continue;
            }
            done.push(key);
            let got = if m.reference {
                exact.clone()
            } else {
                setup.walks(m, b, &rays)?
            };
            for ((i, (ray, _)), (got, exact)) in judged.iter().zip(got.iter().zip(&exact)) {
                if !setup.right(m, ray, got, exact) {
                    return Ok(Some((*i, failure(m, b, Answer::Walk(got.outcome)))));
                }
            }
        }
    }
    Ok(None)
}

/// How a found case replays now.
#[derive(Debug, PartialEq)]
pub enum Replay {
    /// Still wrong, with the recorded answer.
    Holds,
    /// Still wrong, but with another answer than the recorded one.
    OtherAnswer(Answer),
    /// The method is now right on it.
    Right,
    /// Recorded on a backend that cannot be opened here (why).
    Skipped(String),
}

/// Replay a found case: its method on its backend, compared with the recorded answer.
pub fn replay(record: &Record) -> Result<Replay, FoundError> {
    let Some(f) = &record.failure else {
        return Err(FoundError::Field {
            field: "method",
            why: "not a found case (it records no failure)".into(),
        });
    };
    let backend = match Backend::open(f.backend) {
        Ok(b) => b,
        Err(e) => return Ok(Replay::Skipped(e.to_string())),
    };
    // A GPU finding replays on the adapter and driver it was found on; another compiles differently.
    if let (Some(want), Some(here)) = (&f.adapter, backend.adapter())
        && *want != here
    {
        return Ok(Replay::Skipped(format!(
            "found on {want}; this GPU is {here}"
        )));
    }
    let now = match &record.subject {
        Subject::Hit(h) => {
            let m = triangle_by_name(&f.method)?;
            check_hits(std::slice::from_ref(h), &[m], &[&backend], false)?.map(|(_, f)| f)
        }
        Subject::Box(c) => {
            let m = octree_by_name(&f.method)?;
            check_boxes(std::slice::from_ref(c), &[m], &[&backend])?.map(|(_, f)| f)
        }
        s => check(s, &[by_name(&f.method)?], &[&backend])?,
    };
    Ok(match now {
        None => Replay::Right,
        Some(now) if now.answer == f.answer => Replay::Holds,
        Some(now) => Replay::OtherAnswer(now.answer),
    })
}
