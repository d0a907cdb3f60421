//! Found cases: failures kept as readable JSON lines under `corpora/found/<method>/` and replayed by
//! `cargo test` — a case in the one case format ([`crate::cases::Subject`]) plus what failed on it:
//! `"method"`, `"backend"`, `"kind"` (the wrong ending, [`OutcomeKind::wrong_key`]) and `"answer"` (the
//! method's wrong exit face, or its wrong walk). Also the checks that the fuzz targets, import and
//! replay share.

use crate::backend::{Backend, BackendError, BackendKind, CPU, CPU_FMA};
use crate::cases::{CaseError, Subject, classify, object};
use crate::choice::Choice;
use crate::exact::hit::first_hit;
use crate::registry::{METHODS, Method, UnknownMethod, by_name, reference};
use crate::scenes::from_bytes::WalkCase;
use crate::tet::Case;
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
}

/// Which methods a fuzz run holds to exactness, from `TETWALK_FUZZ_METHOD`: `robust` (every method
/// that claims robustness: the reference, `certified`, and the published ones whose papers claim it),
/// `ours` (tetwalk's own, which must never fail), or one method's name (with the reference). Unset, the
/// default compiled in with `TETWALK_FUZZ_DEFAULT` (ClusterFuzzLite's build uses `ours`), else `robust`.
pub fn required_methods() -> Result<Vec<&'static Method>, FoundError> {
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

/// The backends a fuzz run holds the required methods to: the CPU, plain and as a GPU compiles them.
pub const FUZZ_BACKENDS: [&Backend; 2] = [&CPU, &CPU_FMA];

/// A fuzz target's check of one decoded case: the found case, when a required method
/// ([`required_methods`]) answers wrongly on a [`FUZZ_BACKENDS`] backend.
pub fn fuzz_check(subject: Subject) -> Option<Record> {
    let methods = required_methods().expect("TETWALK_FUZZ_METHOD names a method");
    let failure = check(&subject, &methods, &FUZZ_BACKENDS).ok()??;
    Some(Record {
        subject,
        failure: Some(failure),
    })
}

/// What a method answered: an exit face (or none) for one tetrahedron, a walk for a walk case.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Answer {
    Face(Option<u8>),
    Walk(Outcome),
}

impl Answer {
    /// The kind of ending this answer is (an exit face counts as a hit).
    pub fn kind(&self) -> OutcomeKind {
        match self {
            Answer::Face(Some(_)) => OutcomeKind::Hit,
            Answer::Face(None) => OutcomeKind::NoExitFace,
            Answer::Walk(o) => o.kind(),
        }
    }

    fn to_json(self) -> Value {
        match self {
            Answer::Face(f) => serde_json::json!(f),
            Answer::Walk(o) => serde_json::to_value(o).unwrap_or(Value::Null),
        }
    }
}

/// A failure: which method, on which backend, what it answered, and so what kind of wrong it is.
#[derive(Clone, Debug, PartialEq)]
pub struct Failure {
    pub method: String,
    pub backend: BackendKind,
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
const FAILURE_FIELDS: [&str; 4] = ["method", "backend", "kind", "answer"];

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
        let mut field = |k: &'static str| {
            obj.remove(k).ok_or(FoundError::Field {
                field: k,
                why: "missing (a found case has method, backend, kind and answer)".into(),
            })
        };
        let bad = |field: &'static str, why: String| FoundError::Field { field, why };
        let method = field("method")?;
        let method = by_name(method.as_str().unwrap_or_default())?
            .name
            .to_string();
        let backend = field("backend")?;
        let backend = backend
            .as_str()
            .and_then(BackendKind::from_name)
            .ok_or_else(|| bad("backend", format!("{backend} is not cpu, cpu-fma or gpu")))?;
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
    match subject {
        Subject::Exit(case) => check_exit(case, methods, backends),
        Subject::Walk(w) => check_walk(w, methods, backends),
    }
}

fn check_exit(
    case: &Case,
    methods: &[&Method],
    backends: &[&Backend],
) -> Result<Option<Failure>, FoundError> {
    let c = classify(case)?;
    if !c.meets() {
        return Ok(None);
    }
    for m in methods {
        for b in backends {
            let face = b.exit_face(m, case)?;
            if !face.is_some_and(|f| c.exit.contains(f)) {
                return Ok(Some(Failure {
                    method: m.name.into(),
                    backend: b.for_method(m).kind(),
                    answer: Answer::Face(face.map(|f| f as u8)),
                }));
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
        let on = backend.mesh(&self.mesh);
        Ok(backend.walks(m, &on, &[w.ray()], self.start, self.max_steps)?[0])
    }

    /// Whether `got` ends rightly: the reference against the brute-force first hit, every other
    /// method against the reference walk `exact`.
    pub fn right(&self, m: &Method, w: &WalkCase, got: &Walk, exact: &Walk) -> bool {
        let ray = w.ray();
        if !m.reference {
            return same_result(&self.mesh, &ray, got, exact);
        }
        match (got.outcome, first_hit(&self.mesh, &ray)) {
            (Outcome::LeftMesh { .. }, None) => true,
            (Outcome::Hit { tet, face }, Some((_, faces))) => {
                faces.contains(&(tet, face)) || same_result(&self.mesh, &ray, got, exact)
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

fn check_walk(
    w: &WalkCase,
    methods: &[&Method],
    backends: &[&Backend],
) -> Result<Option<Failure>, FoundError> {
    // A case whose mesh cannot be built or whose origin is outside it judges nothing.
    let Ok(setup) = WalkSetup::new(w) else {
        return Ok(None);
    };
    let exact = setup.walk(reference(), &CPU, w)?;
    let mut done = Vec::new();
    for m in methods {
        for b in backends {
            // The reference runs on the CPU whatever the backend: walk it once.
            let key = (m.name, b.for_method(m).kind());
            if done.contains(&key) {
                continue;
            }
            done.push(key);
            let got = if m.reference {
                exact
            } else {
                setup.walk(m, b, w)?
            };
            if !setup.right(m, w, &got, &exact) {
                return Ok(Some(Failure {
                    method: m.name.into(),
                    backend: b.for_method(m).kind(),
                    answer: Answer::Walk(got.outcome),
                }));
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
    let m = by_name(&f.method)?;
    let backend = match Backend::open(f.backend) {
        Ok(b) => b,
        Err(e) => return Ok(Replay::Skipped(e.to_string())),
    };
    Ok(match check(&record.subject, &[m], &[&backend])? {
        None => Replay::Right,
        Some(now) if now.answer == f.answer => Replay::Holds,
        Some(now) => Replay::OtherAnswer(now.answer),
    })
}
