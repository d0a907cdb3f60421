//! The case format: JSON Lines read by `tetwalk exit`, written by `gen-cases`, and embedded by found
//! cases. A line is a one-tetrahedron case `{"tet": [[x,y,z] ×4], "org": [x,y,z], "dir": [x,y,z],
//! "entry": 0..3 or null}` or a walk case `{"mesh": "kuhn"|"jitter"|"fan", "size": N, "offset": X,
//! "org": [x,y,z], "dir": [x,y,z]}`; every number is the nearest f32 to its decimal text (one
//! rounding). Also: judging one answer against the oracle.

use crate::choice::Choice;
use crate::exact::{self, ExactError};
use crate::scenes::Generated;
use crate::scenes::from_bytes::WalkCase;
pub use crate::tet::Case;
use crate::tet::{Ray, SWAP01, Tet, normalize};
use glam::Vec3;
use serde_json::{Map, Value};

/// Why a line is not a case the oracle can judge.
#[derive(Debug, thiserror::Error)]
pub enum CaseError {
    #[error("malformed JSON: {0}")]
    Json(String),
    #[error("expected a JSON object")]
    NotObject,
    #[error("unknown field '{0}'")]
    UnknownField(String),
    #[error("missing field '{0}'")]
    Missing(&'static str),
    #[error("{field}: {why}")]
    Field { field: String, why: String },
    #[error("entry {entry} is not an exact entry face (exact entry faces: {exact:?})")]
    NotAnEntry { entry: u8, exact: Vec<usize> },
    #[error(transparent)]
    Exact(#[from] ExactError),
}

fn field_error(field: impl Into<String>, why: impl Into<String>) -> CaseError {
    CaseError::Field {
        field: field.into(),
        why: why.into(),
    }
}

/// What a line asks about: one tetrahedron, or a walk through a generated mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Subject {
    Exit(Case),
    Walk(WalkCase),
}

/// Largest grid or fan size of a walk case (a Kuhn grid of this size has 6·64³ tetrahedra).
pub const MAX_WALK_SIZE: u32 = 64;

impl Subject {
    /// The case's ray.
    pub fn ray(&self) -> Ray {
        match self {
            Subject::Exit(c) => c.ray(),
            Subject::Walk(w) => w.ray(),
        }
    }

    /// The same case with another ray.
    pub fn with_ray(&self, ray: Ray) -> Subject {
        match *self {
            Subject::Exit(c) => Subject::Exit(Case {
                org: ray.org,
                dir: ray.dir,
                ..c
            }),
            Subject::Walk(w) => Subject::Walk(WalkCase {
                org: ray.org.to_array(),
                dir: ray.dir.to_array(),
                ..w
            }),
        }
    }

    /// Parse one line that holds only a case.
    pub fn parse(line: &str) -> Result<Subject, CaseError> {
        let mut obj = object(line)?;
        let s = Subject::take(&mut obj)?;
        match obj.keys().next() {
            Some(k) => Err(CaseError::UnknownField(k.clone())),
            None => Ok(s),
        }
    }

    /// Take the case's fields out of `obj` (a walk case has `mesh`), leaving the others to the caller.
    pub fn take(obj: &mut Map<String, Value>) -> Result<Subject, CaseError> {
        let walk = obj.contains_key("mesh");
        let mut field = |k: &'static str| obj.remove(k).ok_or(CaseError::Missing(k));
        if walk {
            let mesh = field("mesh")?;
            let mesh = mesh
                .as_str()
                .and_then(Generated::from_name)
                .ok_or_else(|| field_error("mesh", format!("{mesh} is not kuhn, jitter or fan")))?;
            let size = field("size")?;
            let size = size
                .as_u64()
                .filter(|s| (1..=MAX_WALK_SIZE as u64).contains(s))
                .ok_or_else(|| {
                    field_error("size", format!("{size} is not in 1..={MAX_WALK_SIZE}"))
                })? as u32;
            let offset = number(&field("offset")?).map_err(|e| field_error("offset", e))?;
            let org = vec3(&field("org")?).map_err(|e| field_error("org", e))?;
            let dir = vec3(&field("dir")?).map_err(|e| field_error("dir", e))?;
            if dir == Vec3::ZERO {
                return Err(ExactError::ZeroDirection.into());
            }
            return Ok(Subject::Walk(WalkCase {
                mesh,
                size,
                offset,
                org: org.to_array(),
                dir: dir.to_array(),
            }));
        }
        let tet = field("tet")?;
        let tet = tet
            .as_array()
            .filter(|a| a.len() == 4)
            .ok_or_else(|| field_error("tet", "must hold four points"))?;
        let mut t = [Vec3::ZERO; 4];
        for (i, p) in tet.iter().enumerate() {
            t[i] = vec3(p).map_err(|e| field_error(format!("tet[{i}]"), e))?;
        }
        let org = vec3(&field("org")?).map_err(|e| field_error("org", e))?;
        let dir = vec3(&field("dir")?).map_err(|e| field_error("dir", e))?;
        let entry = match field("entry").unwrap_or(Value::Null) {
            Value::Null => None,
            e => Some(
                e.as_u64()
                    .filter(|&f| f < 4)
                    .ok_or_else(|| field_error("entry", format!("must be 0..3 or null, not {e}")))?
                    as u8,
            ),
        };
        Ok(Subject::Exit(Case {
            tet: t,
            org,
            dir,
            entry,
        }))
    }

    /// The case's fields as JSON (numbers written so that they read back as the same f32).
    pub fn to_json(&self) -> Map<String, Value> {
        let v = match self {
            Subject::Exit(c) => serde_json::json!({
                "tet": c.tet.map(|p| p.to_array()),
                "org": c.org.to_array(),
                "dir": c.dir.to_array(),
                "entry": c.entry,
            }),
            Subject::Walk(w) => serde_json::to_value(w).unwrap_or(Value::Null),
        };
        match v {
            Value::Object(m) => m,
            _ => Map::new(),
        }
    }
}

/// A line as a JSON object.
pub fn object(line: &str) -> Result<Map<String, Value>, CaseError> {
    match serde_json::from_str(line).map_err(|e| CaseError::Json(e.to_string()))? {
        Value::Object(m) => Ok(m),
        _ => Err(CaseError::NotObject),
    }
}

/// The nearest f32 to a JSON number's decimal text; an error when it is not finite in f32.
fn number(x: &Value) -> Result<f32, String> {
    let Value::Number(n) = x else {
        return Err(format!("{x} is not a number"));
    };
    let f: f32 = n
        .to_string()
        .parse()
        .map_err(|_| format!("{n} is not a number"))?;
    if !f.is_finite() {
        return Err(format!("{n} is not finite in f32"));
    }
    Ok(f)
}

fn vec3(v: &Value) -> Result<Vec3, String> {
    let a = v
        .as_array()
        .filter(|a| a.len() == 3)
        .ok_or("expected [x, y, z]")?;
    let mut out = [0f32; 3];
    for (i, x) in a.iter().enumerate() {
        out[i] = number(x)?;
    }
    Ok(Vec3::from(out))
}

/// A method's answer on a case, beside the exact one.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Judged {
    pub face: Option<u8>,
    pub exact_exit: Vec<usize>,
    pub exact_entry: Vec<usize>,
    /// Whether `face` is an exact exit face; `None` when the line misses the tetrahedron.
    pub correct: Option<bool>,
}

/// The oracle's answer for a case, checking its entry face; an error names what is wrong with it.
pub fn classify(case: &Case) -> Result<exact::Classification, CaseError> {
    let c = exact::classify(&case.tet, &case.ray())?;
    if let Some(e) = case.entry
        && !c.entry.contains(e as usize)
    {
        return Err(CaseError::NotAnEntry {
            entry: e,
            exact: c.entry.to_vec(),
        });
    }
    Ok(c)
}

/// The case as methods see it: the tetrahedron positively oriented ([`normalize`]) and the entry face
/// renumbered to match, with the map from its face numbers back to the case's.
pub fn normalized(case: &Case) -> (Tet, Option<usize>, [usize; 4]) {
    let (tet, swapped) = normalize(&case.tet);
    let map = if swapped { SWAP01 } else { [0, 1, 2, 3] };
    (tet, case.entry.map(|e| map[e as usize]), map)
}

/// A face (in the case's numbering) beside the exact answer.
pub fn judged(c: &exact::Classification, face: Option<usize>) -> Judged {
    Judged {
        face: face.map(|f| f as u8),
        exact_exit: c.exit.to_vec(),
        exact_entry: c.entry.to_vec(),
        correct: c.meets().then(|| face.is_some_and(|f| c.exit.contains(f))),
    }
}
