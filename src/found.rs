//! Failures found by fuzzing, kept as readable JSON cases under `corpora/found/<method>/` and replayed
//! by `cargo test`; and the checks the fuzz targets run, so that targets, replay and import agree.

use crate::cases::{Case, answer, classify};
use crate::methods::{METHODS, Method, by_name};
use crate::scenes::from_bytes::WalkCase;
use crate::walk::{Outcome, default_max_steps, locate, same_result};
use glam::Vec3;

/// Which methods a fuzz run holds to exactness, from `TETWALK_FUZZ_METHOD`: `robust` (the default:
/// `exact` and every method whose paper claims robustness), or one method's name (with `exact`).
pub fn required_methods() -> Result<Vec<&'static Method>, String> {
    let choice = std::env::var("TETWALK_FUZZ_METHOD").unwrap_or_else(|_| "robust".into());
    match choice.as_str() {
        "robust" => Ok(METHODS.iter().filter(|m| m.claims_robust).collect()),
        name => {
            let m = by_name(name)
                .ok_or_else(|| format!("TETWALK_FUZZ_METHOD: unknown method '{name}'"))?;
            Ok(METHODS
                .iter()
                .filter(|x| x.name == "exact" || x.name == m.name)
                .collect())
        }
    }
}

/// A failure: which method, plain or `fma`, and what went wrong.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Failure {
    pub method: String,
    pub fma: bool,
    /// `wrong_face` or `no_exit_face` for one tetrahedron; `wrong_hit`, `false_miss`, `no_exit_face`,
    /// `cycle` or `step_limit` for a walk.
    pub kind: String,
}

/// The first of `methods` (plain, then fma) whose exit face is not an exact exit face.
pub fn check_exit(case: &Case, methods: &[&Method]) -> Option<Failure> {
    let c = classify(case).ok()?;
    if !c.meets() {
        return None;
    }
    for m in methods {
        for fma in [false, true] {
            match answer(case, m, fma) {
                Some(f) if c.exit.contains(f) => {}
                face => {
                    let kind = if face.is_some() {
                        "wrong_face"
                    } else {
                        "no_exit_face"
                    };
                    return Some(Failure {
                        method: m.name.into(),
                        fma,
                        kind: kind.into(),
                    });
                }
            }
        }
    }
    None
}

/// The first of `methods` (plain, then fma) whose walk does not end where it should: `exact` against the
/// brute-force first hit, every other method against the `exact` walk.
pub fn check_walk(w: &WalkCase, methods: &[&Method]) -> Option<Failure> {
    let offset = Vec3::splat(w.offset);
    let mesh = crate::scenes::generated_mesh(w.mesh, w.size, offset, 1).ok()?;
    let ray = w.ray();
    let start = locate(&mesh, ray.org, 0).ok()?;
    let max = default_max_steps(&mesh);
    let exact = by_name("exact").expect("registered");
    let reference = exact.walk(false)(&mesh, &ray, start, max);
    for m in methods {
        for fma in [false, true] {
            let got = m.walk(fma)(&mesh, &ray, start, max);
            let right = if m.name == "exact" {
                match (got.outcome, crate::exact::hit::first_hit(&mesh, &ray)) {
                    (Outcome::LeftMesh { .. }, None) => true,
                    (Outcome::Hit { tet, face }, Some((_, faces))) => {
                        faces.contains(&(tet, face)) || same_result(&mesh, &ray, &got, &reference)
                    }
                    _ => false,
                }
            } else {
                same_result(&mesh, &ray, &got, &reference)
            };
            if !right {
                let kind = match got.outcome {
                    Outcome::Hit { .. } => "wrong_hit",
                    Outcome::LeftMesh { .. } => "false_miss",
                    Outcome::NoExitFace { .. } => "no_exit_face",
                    Outcome::Cycle { .. } => "cycle",
                    Outcome::StepLimit { .. } => "step_limit",
                };
                return Some(Failure {
                    method: m.name.into(),
                    fma,
                    kind: kind.into(),
                });
            }
        }
    }
    None
}

/// A found case as kept in `corpora/found/<method>/`, one JSON line: a one-tetrahedron case (the
/// `tetwalk exit` format) or a walk case, with what failed.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
#[serde(untagged)]
pub enum Finding {
    Exit(ExitRecord),
    Walk(WalkRecord),
}

/// A one-tetrahedron finding, flat.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ExitRecord {
    pub tet: [[f32; 3]; 4],
    pub org: [f32; 3],
    pub dir: [f32; 3],
    pub entry: Option<u8>,
    pub method: String,
    pub fma: bool,
    pub kind: String,
    /// The method's wrong answer (the face it gave, none for no exit face), which replay holds it to.
    #[serde(default)]
    pub answer: Option<u8>,
}

/// A walk finding, flat.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct WalkRecord {
    pub mesh: crate::scenes::Generated,
    pub size: u32,
    pub offset: f32,
    pub org: [f32; 3],
    pub dir: [f32; 3],
    pub method: String,
    pub fma: bool,
    pub kind: String,
}

impl Finding {
    pub fn exit(case: &Case, f: Failure) -> Finding {
        let answer = by_name(&f.method)
            .and_then(|m| crate::cases::answer(case, m, f.fma))
            .map(|x| x as u8);
        Finding::Exit(ExitRecord {
            tet: case.tet.map(|v| v.to_array()),
            org: case.org.to_array(),
            dir: case.dir.to_array(),
            entry: case.entry,
            method: f.method,
            fma: f.fma,
            kind: f.kind,
            answer,
        })
    }

    pub fn walk(w: &WalkCase, f: Failure) -> Finding {
        Finding::Walk(WalkRecord {
            mesh: w.mesh,
            size: w.size,
            offset: w.offset,
            org: w.org,
            dir: w.dir,
            method: f.method,
            fma: f.fma,
            kind: f.kind,
        })
    }

    /// Read a finding (a walk finding has `mesh`, a one-tetrahedron one `tet`).
    pub fn from_json(text: &str) -> Result<Finding, String> {
        let v: serde_json::Value = serde_json::from_str(text).map_err(|e| e.to_string())?;
        if v.get("mesh").is_some() {
            serde_json::from_value(v)
                .map(Finding::Walk)
                .map_err(|e| e.to_string())
        } else {
            serde_json::from_value(v)
                .map(Finding::Exit)
                .map_err(|e| e.to_string())
        }
    }

    pub fn failure(&self) -> Failure {
        let (method, fma, kind) = match self {
            Finding::Exit(r) => (&r.method, r.fma, &r.kind),
            Finding::Walk(r) => (&r.method, r.fma, &r.kind),
        };
        Failure {
            method: method.clone(),
            fma,
            kind: kind.clone(),
        }
    }

    /// The one-tetrahedron case, for exit findings.
    pub fn case(&self) -> Option<Case> {
        match self {
            Finding::Exit(r) => Some(Case {
                tet: r.tet.map(Vec3::from),
                org: Vec3::from(r.org),
                dir: Vec3::from(r.dir),
                entry: r.entry,
            }),
            Finding::Walk(_) => None,
        }
    }

    /// The same case filed for another failure.
    pub fn with_failure(&self, f: Failure) -> Finding {
        let mut out = self.clone();
        let (m, fma, kind) = match &mut out {
            Finding::Exit(r) => (&mut r.method, &mut r.fma, &mut r.kind),
            Finding::Walk(r) => (&mut r.method, &mut r.fma, &mut r.kind),
        };
        (*m, *fma, *kind) = (f.method, f.fma, f.kind);
        if let Finding::Exit(r) = &mut out {
            let case = self.case().expect("an exit finding has a case");
            r.answer = by_name(&r.method)
                .and_then(|m| crate::cases::answer(&case, m, r.fma))
                .map(|x| x as u8);
        }
        out
    }

    /// What identifies the case, whatever failed on it.
    pub fn key(&self) -> String {
        let blank = Failure {
            method: String::new(),
            fma: false,
            kind: String::new(),
        };
        serde_json::to_string(&self.with_failure(blank)).unwrap_or_default()
    }

    /// This finding, and the same case filed for every method that claims robustness and fails on it
    /// too: a failure of a claim is a finding of its own.
    pub fn with_robust_failures(&self) -> Vec<Finding> {
        let mut out = vec![self.with_failure(self.failure())];
        let mine = self.failure().method;
        for m in METHODS
            .iter()
            .filter(|m| m.claims_robust && m.name != "exact" && m.name != mine)
        {
            if let Some(f) = self.check(&[m]) {
                out.push(self.with_failure(f));
            }
        }
        out
    }

    /// Run the check again for `methods`.
    pub fn check(&self, methods: &[&Method]) -> Option<Failure> {
        match self {
            Finding::Exit(_) => check_exit(&self.case()?, methods),
            Finding::Walk(r) => {
                let w = WalkCase {
                    mesh: r.mesh,
                    size: r.size,
                    offset: r.offset,
                    org: r.org,
                    dir: r.dir,
                };
                check_walk(&w, methods)
            }
        }
    }
}
