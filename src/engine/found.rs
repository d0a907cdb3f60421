//! Found cases: failures kept as readable JSON lines under `corpora/found/<method>/` and replayed by
//! `cargo test` — a case of the case format (its family's) plus what failed on it: `"method"`,
//! `"backend"`, `"kind"` (the wrong ending, [`OutcomeKind::wrong_key`]) and `"answer"` (the method's
//! wrong answer as its family records it). Also the check that fuzzing, filing and replay share.

use crate::backend::{Backend, BackendError, BackendKind, CPUS};
use crate::cases::{CaseError, object};
use crate::choice::Choice;
use crate::family::{self, Family, Verdict};
use crate::registry::{Named, UnknownMethod};
use crate::walk::OutcomeKind;
use serde_json::{Map, Value};

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
    #[error(
        "TETWALK_FUZZ_METHOD: {0}; or `robust` (every method that makes a claim, held to it) or `ours` (those tetwalk vouches for)"
    )]
    FuzzMethod(UnknownMethod),
    #[error("TETWALK_FUZZ_BACKEND: {0}")]
    FuzzBackend(String),
    /// An octree walk that never ends though every cell's exit it chose was right where judged.
    #[error("endless octree walk: {0}")]
    EndlessWalk(String),
    /// A program outside tetwalk's finding: only the program can answer it again.
    #[error(
        "found for {0}, a program outside tetwalk: tetwalk cannot answer it again without the program (ask it with `tetwalk shrink --answerer CMD`, or `exit --answerer CMD` on the case line)"
    )]
    NeedsProgram(String),
}

/// The backends a finding is checked on when it is filed for the methods that claim: the CPU in
/// every arithmetic model ([`CPUS`]).
pub(crate) fn cpu_backends() -> Vec<&'static Backend> {
    CPUS.iter().collect()
}

/// A failure: which method, on which backend, and what it answered.
#[derive(Clone, Debug, PartialEq)]
pub struct Failure<F: Family> {
    pub method: String,
    pub backend: BackendKind,
    /// The adapter and driver, for a failure found on a GPU.
    pub adapter: Option<String>,
    pub answer: F::Answer,
}

impl<F: Family> Failure<F> {
    /// What `m` answered wrongly where `b` runs it (the reference on the CPU), with the adapter where
    /// that is a GPU.
    pub(crate) fn of(m: &F::Method, b: &Backend, answer: F::Answer) -> Failure<F> {
        let on = b.for_method(m);
        let ran = on.ran();
        Failure {
            method: m.name().to_string(),
            backend: ran.kind,
            adapter: ran.adapter,
            answer,
        }
    }

    /// The kind of wrong ([`OutcomeKind::wrong_key`] is its name in files).
    pub fn kind(&self) -> OutcomeKind {
        F::kind(&self.answer)
    }

    /// Whether it can be run again on `b`: a GPU finding only on the adapter and driver it was found
    /// on (another compiles the methods differently), or why not.
    pub(crate) fn runs_on(&self, b: &Backend) -> Result<(), String> {
        match (&self.adapter, b.ran().adapter) {
            (Some(want), Some(here)) if *want != here => {
                Err(format!("found on {want}; this GPU is {here}"))
            }
            _ => Ok(()),
        }
    }

    /// The backend it was found on, opened here, or why it cannot be.
    pub(crate) fn backend_here(&self) -> Result<Backend, String> {
        let b = Backend::open(self.backend).map_err(|e| e.to_string())?;
        self.runs_on(&b)?;
        Ok(b)
    }
}

/// One line of the case format, with what failed on it when it is a found case.
#[derive(Clone, Debug, PartialEq)]
pub struct Found<F: Family> {
    pub case: F::Case,
    pub failure: Option<Failure<F>>,
    /// The case as it was found, where this one is it shrunk (`crate::engine::shrink`).
    pub original: Option<F::Case>,
}

/// The fields a found case adds to its case.
pub(crate) const FAILURE_FIELDS: [&str; 7] = [
    "method", "backend", "adapter", "kind", "answer", "leak", "original",
];

/// Whether `answer` lets the case's ray through a closed mesh's surface (a false miss that is a
/// leak, [`crate::family::Said::leak`]): said beside its kind in a found line.
fn leaks<F: Family>(case: &F::Case, answer: &F::Answer) -> bool {
    F::truth(case).is_ok_and(|x| F::said(case, &x, answer, 0.0).leak)
}

impl<F: Family> Found<F> {
    /// A found case: `case` and what failed on it.
    pub fn of(case: F::Case, failure: Failure<F>) -> Found<F> {
        Found {
            case,
            failure: Some(failure),
            original: None,
        }
    }

    /// Read a line: a case of this family, or a found case.
    pub fn parse(line: &str) -> Result<Found<F>, FoundError> {
        Self::from_object(object(line)?)
    }

    /// Read a line's object ([`family::owner`] says which family's it is).
    pub fn from_object(mut obj: Map<String, Value>) -> Result<Found<F>, FoundError> {
        let case = F::take_case(&mut obj)?;
        if let Some(k) = obj.keys().find(|k| !FAILURE_FIELDS.contains(&k.as_str())) {
            return Err(CaseError::UnknownField(k.clone()).into());
        }
        let original = match obj.remove("original") {
            None => None,
            Some(Value::Object(mut o)) => {
                let c = F::take_case(&mut o).map_err(|e| FoundError::Field {
                    field: "original",
                    why: e.to_string(),
                })?;
                if let Some(k) = o.keys().next() {
                    return Err(FoundError::Field {
                        field: "original",
                        why: format!("holds '{k}', which is not a field of its case"),
                    });
                }
                Some(c)
            }
            Some(v) => {
                return Err(FoundError::Field {
                    field: "original",
                    why: format!("{v} is not the case as it was found"),
                });
            }
        };
        if obj.is_empty() {
            return Ok(Found {
                case,
                failure: None,
                original,
            });
        }
        let adapter = obj.remove("adapter");
        let leak = obj.remove("leak");
        let mut field = |k: &'static str| {
            obj.remove(k).ok_or(FoundError::Field {
                field: k,
                why: "missing (a found case has method, backend, kind and answer)".into(),
            })
        };
        let bad = |field: &'static str, why: String| FoundError::Field { field, why };
        let method = field("method")?;
        let backend = field("backend")?;
        let backend = backend
            .as_str()
            .and_then(BackendKind::from_name)
            .ok_or_else(|| {
                bad(
                    "backend",
                    format!("{backend} is not cpu, cpu-fma, cpu-ftz, gpu or outside"),
                )
            })?;
        // A method of tetwalk's by its registered name; a program outside tetwalk by the name it was
        // judged under.
        let method = match (backend, method.as_str()) {
            (BackendKind::Outside, Some(name)) if !name.is_empty() => name.to_string(),
            (BackendKind::Outside, _) => {
                return Err(bad("method", format!("{method} is not an answerer's name")));
            }
            (_, name) => family::by_name::<F>(name.unwrap_or_default())?
                .name()
                .to_string(),
        };
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
        let answer = F::parse_answer(&field("answer")?, &case).map_err(|e| bad("answer", e))?;
        match leak {
            None => {}
            Some(Value::Bool(true)) if leaks::<F>(&case, &answer) => {}
            Some(v) => {
                return Err(bad(
                    "leak",
                    format!("{v}: the answer lets no ray through a closed mesh's surface here"),
                ));
            }
        }
        if F::kind(&answer) != kind {
            return Err(bad(
                "kind",
                format!(
                    "'{}' does not match the answer, which is a {}",
                    kind.wrong_key(),
                    F::kind(&answer).wrong()
                ),
            ));
        }
        Ok(Found {
            case,
            failure: Some(Failure {
                method,
                backend,
                adapter,
                answer,
            }),
            original,
        })
    }

    /// The line, as kept in `corpora/found/`.
    pub fn to_json(&self) -> String {
        let mut m = F::case_json(&self.case);
        if let Some(f) = &self.failure {
            m.insert("method".into(), f.method.clone().into());
            m.insert("backend".into(), f.backend.name().into());
            if let Some(a) = &f.adapter {
                m.insert("adapter".into(), a.clone().into());
            }
            m.insert("kind".into(), f.kind().wrong_key().into());
            m.insert("answer".into(), F::answer_json(&f.answer));
            if leaks::<F>(&self.case, &f.answer) {
                m.insert("leak".into(), true.into());
            }
        }
        if let Some(o) = &self.original {
            m.insert("original".into(), Value::Object(F::case_json(o)));
        }
        Value::Object(m).to_string()
    }

    /// What failed on it, or an error saying that the line records no failure to `doing`.
    pub(crate) fn failed(&self, doing: &str) -> Result<&Failure<F>, FoundError> {
        self.failure.as_ref().ok_or_else(|| FoundError::Field {
            field: "method",
            why: format!("not a found case (it records no failure to {doing})"),
        })
    }

    /// The case alone, one line of the case format.
    pub fn case_line(&self) -> String {
        Value::Object(F::case_json(&self.case)).to_string()
    }

    /// The same case filed for another failure.
    pub(crate) fn with_failure(&self, f: Failure<F>) -> Found<F> {
        Found {
            failure: Some(f),
            ..self.clone()
        }
    }

    /// This finding, and the same case filed for every method that makes a claim (but the family's
    /// reference) and fails it there too, on the CPU in every arithmetic model: a failure of a claim is
    /// a finding of its own.
    pub fn with_claim_failures(&self) -> Result<Vec<Found<F>>, FoundError> {
        let mut out = vec![self.clone()];
        let mine = self.failure.as_ref().map(|f| f.method.as_str());
        for m in F::methods()
            .iter()
            .filter(|m| m.info().claim.is_some() && !m.is_reference() && Some(m.name()) != mine)
        {
            let held = [(m, Hold::Claim)];
            if let Some((_, f)) =
                check::<F>(std::slice::from_ref(&self.case), &held, &cpu_backends())?
            {
                out.push(self.with_failure(f));
            }
        }
        Ok(out)
    }
}

/// Every case of family `F` in the found corpus `dir` (`corpora/found/`: a folder per method, files of
/// found-case lines), in file order; a line that does not read is an error naming it.
pub(crate) fn corpus<F: Family>(dir: &std::path::Path) -> Result<Vec<F::Case>, FoundError> {
    let read = |p: &std::path::Path| {
        std::fs::read_to_string(p).map_err(|e| FoundError::Field {
            field: "file",
            why: format!("{}: {e}", p.display()),
        })
    };
    let list = |p: &std::path::Path| -> Result<Vec<std::path::PathBuf>, FoundError> {
        let mut v: Vec<_> = std::fs::read_dir(p)
            .map_err(|e| FoundError::Field {
                field: "file",
                why: format!("{}: {e}", p.display()),
            })?
            .flatten()
            .map(|e| e.path())
            .collect();
        v.sort();
        Ok(v)
    };
    let mut out = Vec::new();
    for method in list(dir)?.iter().filter(|p| p.is_dir()) {
        for file in list(method)? {
            for (n, line) in read(&file)?.lines().enumerate() {
                let obj = object(line).map_err(|e| FoundError::Field {
                    field: "file",
                    why: format!("{} line {}: {e}", file.display(), n + 1),
                })?;
                if F::owns(&obj) {
                    out.push(Found::<F>::from_object(obj)?.case);
                }
            }
        }
    }
    Ok(out)
}

/// What a check holds a method to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Hold {
    /// Its family's claim ([`Family::refutes_claim`]): for ray–triangle tests, no leak.
    Claim,
    /// Every answer right.
    Every,
}

/// The first of `held`'s methods (each on each of `backends` in turn; the reference on the CPU, once)
/// that answers a case wrongly as it is held, by index, with what it answered. A case the oracle
/// cannot judge is left out, but for the first, whose error is returned.
pub fn check<F: Family>(
    cases: &[F::Case],
    held: &[(&F::Method, Hold)],
    backends: &[&Backend],
) -> Result<Option<(usize, Failure<F>)>, FoundError> {
    let mut judged = Vec::with_capacity(cases.len());
    for (i, c) in cases.iter().enumerate() {
        match F::truth(c) {
            Ok(t) => judged.push((i, t)),
            Err(e) if i == 0 => return Err(e.into()),
            Err(_) => {}
        }
    }
    if judged.is_empty() {
        return Ok(None);
    }
    let asked: Vec<F::Case> = judged.iter().map(|&(i, _)| cases[i]).collect();
    let mut done = Vec::new();
    for &(m, hold) in held {
        for b in backends {
            // The reference runs on the CPU whatever the backend: answer it once.
            let key = (m.name(), b.for_method(m).ran().kind);
            if done.contains(&key) {
                continue;
            }
            done.push(key);
            let answers = F::answers(b, m, &asked)?;
            for (a, (i, truth)) in answers.iter().zip(&judged) {
                let c = &cases[*i];
                let wrong = match hold {
                    Hold::Every => matches!(F::verdict(c, truth, a), Verdict::Wrong(_)),
                    Hold::Claim => F::refutes_claim(c, truth, a),
                };
                if wrong {
                    return Ok(Some((*i, Failure::of(m, b, *a))));
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
    /// Still wrong, but with another answer than the recorded one (as found cases write it).
    OtherAnswer(Value),
    /// The method is now right on it.
    Right,
    /// Recorded on a backend that cannot be opened here (why).
    Skipped(String),
}

/// A found case of any family, as a line's JSON object, replayed ([`replay`]): how it replays now,
/// and the method that failed on it.
pub(crate) fn replay_object(
    obj: Map<String, Value>,
) -> Result<(Replay, Option<String>), FoundError> {
    crate::with_family!(family::owner(&obj), F => {
        let r = Found::<F>::from_object(obj)?;
        Ok((replay(&r)?, r.failure.map(|f| f.method)))
    })
}

/// What a replay found: lines replayed, failing again the same way, changed, skipped (their backend
/// is not here).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub(crate) struct ReplayTally {
    pub(crate) lines: u64,
    pub(crate) same: u64,
    pub(crate) changed: u64,
    pub(crate) skipped: u64,
}

impl ReplayTally {
    /// Count a line that failed again the same way (`same`), changed, or was skipped.
    pub(crate) fn add(&mut self, same: Option<bool>) {
        self.lines += 1;
        match same {
            Some(true) => self.same += 1,
            Some(false) => self.changed += 1,
            None => self.skipped += 1,
        }
    }
}

impl Replay {
    /// Whether it fails again the same way; none when skipped.
    pub(crate) fn same(&self) -> Option<bool> {
        match self {
            Replay::Holds => Some(true),
            Replay::Skipped(_) => None,
            Replay::Right | Replay::OtherAnswer(_) => Some(false),
        }
    }
}

/// Replay a found case: its method on its backend, its answer compared with the recorded one as found
/// cases record it.
pub fn replay<F: Family>(found: &Found<F>) -> Result<Replay, FoundError> {
    let f = found.failed("replay")?;
    if f.backend == BackendKind::Outside {
        return Err(FoundError::NeedsProgram(f.method.clone()));
    }
    let backend = match f.backend_here() {
        Ok(b) => b,
        Err(why) => return Ok(Replay::Skipped(why)),
    };
    let m = family::by_name::<F>(&f.method)?;
    let now = check::<F>(
        std::slice::from_ref(&found.case),
        &[(m, Hold::Every)],
        &[&backend],
    )?;
    Ok(match now {
        None => Replay::Right,
        Some((_, now)) if F::answer_json(&now.answer) == F::answer_json(&f.answer) => Replay::Holds,
        Some((_, now)) => Replay::OtherAnswer(F::answer_json(&now.answer)),
    })
}
