//! The case format: JSON Lines read by `tetwalk exit`, `hit`, `box-exit` and `judge`, written by
//! `gen-cases`, and embedded by found cases. Each family reads and writes its own cases
//! (`crate::family`: a one-tetrahedron case `{"tet", "org", "dir", "entry"}`, a walk case `{"mesh",
//! "size", "offset", "org", "dir"}`, a ray–triangle case `{"tri" | "tris", "org", "dir"}`, an octree
//! cell case `{"box", "org", "dir"}`), and the keys a line holds name its family; every number is the
//! nearest f32 to its decimal text (one rounding). Here: the case types the backend answers, the JSON
//! helpers every family's reader shares, and their errors.
#![warn(missing_docs)]

use crate::exact::{self, ExactError};
use crate::methods::triangle::Tri;
pub use crate::scenes::from_bytes::WalkCase;
pub use crate::tet::Case;
use crate::tet::{Ray, SWAP01, Tet, normalize};
use glam::Vec3;
use serde_json::{Map, Value};

/// Why a line is not a case the oracle can judge.
#[derive(Debug, thiserror::Error)]
pub enum CaseError {
    /// A line that is not JSON (the parser's message).
    #[error("malformed JSON: {0}")]
    Json(String),
    /// A line that is JSON but not an object.
    #[error("expected a JSON object")]
    NotObject,
    /// A key no case of the family holds.
    #[error("unknown field '{0}'")]
    UnknownField(String),
    /// A key the case needs is absent.
    #[error("missing field '{0}'")]
    Missing(&'static str),
    /// A field whose value is not what it must be: which, and why.
    #[error("{field}: {why}")]
    Field {
        /// The field, as the line names it.
        field: String,
        /// What is wrong with its value.
        why: String,
    },
    /// The given entry face is not one the line exactly enters through.
    #[error("entry {entry} is not an exact entry face (exact entry faces: {exact:?})")]
    NotAnEntry {
        /// The face the line gives.
        entry: u8,
        /// The faces the line exactly enters through.
        exact: Vec<usize>,
    },
    /// The oracle cannot judge the geometry (flat, zero direction, not finite).
    #[error(transparent)]
    Exact(#[from] ExactError),
    /// A walk case's generated mesh cannot be built.
    #[error("the walk case's mesh could not be built: {0}")]
    Mesh(String),
    /// A walk case's origin lies in no tetrahedron of its mesh.
    #[error("the walk case's origin is not inside its mesh: {0}")]
    Outside(String),
}

/// A [`CaseError::Field`] for `field`, saying `why`.
pub fn field_error(field: impl Into<String>, why: impl Into<String>) -> CaseError {
    CaseError::Field {
        field: field.into(),
        why: why.into(),
    }
}

/// An octree cell case: `{"box": [[lx, ly, lz], [hx, hy, hz]], "org", "dir"}`, a closed axis-aligned
/// box (`lo < hi` on every axis) and a ray whose exit face and quarter are asked (seed 001).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoxCase {
    /// The lower corner.
    pub lo: Vec3,
    /// The upper corner.
    pub hi: Vec3,
    /// The ray's origin.
    pub org: Vec3,
    /// The ray's direction (any length but zero).
    pub dir: Vec3,
}

impl BoxCase {
    /// The case's ray.
    pub fn ray(&self) -> Ray {
        Ray {
            org: self.org,
            dir: self.dir,
        }
    }
}

/// Most triangles of a triangle case (an icosahedron's).
pub const MAX_TRIS: usize = 20;

/// A ray–triangle case: `{"tri": [[x,y,z] ×3], "org", "dir"}`, one triangle, or `{"tris": [[[x,y,z]
/// ×3] …], "org", "dir"}`, a closed mesh (every edge shared by exactly two triangles, which run it in
/// opposite directions) of 4 to [`MAX_TRIS`] triangles, whose first hit is asked.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HitCase {
    tris: [Tri; MAX_TRIS],
    len: u8,
    /// Written as `tris`: a closed mesh.
    pub closed: bool,
    /// The ray's origin.
    pub org: Vec3,
    /// The ray's direction (any length but zero).
    pub dir: Vec3,
}

impl HitCase {
    /// A one-triangle case.
    pub fn single(tri: Tri, ray: Ray) -> HitCase {
        let mut tris = [[Vec3::ZERO; 3]; MAX_TRIS];
        tris[0] = tri;
        HitCase {
            tris,
            len: 1,
            closed: false,
            org: ray.org,
            dir: ray.dir,
        }
    }

    /// A closed-mesh case; an error names the edge that is not shared rightly, or a count out of range.
    pub fn closed(mesh: &[Tri], ray: Ray) -> Result<HitCase, CaseError> {
        if !(4..=MAX_TRIS).contains(&mesh.len()) {
            return Err(field_error(
                "tris",
                format!("holds {} triangles, not 4 to {MAX_TRIS}", mesh.len()),
            ));
        }
        for (i, t) in mesh.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                let same = edge_uses(mesh, a, b);
                let back = edge_uses(mesh, b, a);
                if same != 1 || back != 1 {
                    return Err(field_error(
                        format!("tris[{i}]"),
                        format!(
                            "edge {:?} -> {:?} is run {} this way and {} the other way; a closed mesh runs each edge once each way",
                            a.to_array(),
                            b.to_array(),
                            times(same),
                            times(back)
                        ),
                    ));
                }
            }
        }
        let mut tris = [[Vec3::ZERO; 3]; MAX_TRIS];
        tris[..mesh.len()].copy_from_slice(mesh);
        Ok(HitCase {
            tris,
            len: mesh.len() as u8,
            closed: true,
            org: ray.org,
            dir: ray.dir,
        })
    }

    /// The case's triangles (one, or the closed mesh's).
    pub fn tris(&self) -> &[Tri] {
        &self.tris[..self.len as usize]
    }

    /// The same triangles with another ray.
    pub fn with_ray(&self, ray: Ray) -> HitCase {
        HitCase {
            org: ray.org,
            dir: ray.dir,
            ..*self
        }
    }

    /// The case's ray.
    pub fn ray(&self) -> Ray {
        Ray {
            org: self.org,
            dir: self.dir,
        }
    }
}

/// "once", or "N times".
fn times(n: usize) -> String {
    match n {
        1 => "once".into(),
        n => format!("{n} times"),
    }
}

/// How many triangles of `mesh` run the edge `a → b`.
fn edge_uses(mesh: &[Tri], a: Vec3, b: Vec3) -> usize {
    mesh.iter()
        .filter(|t| (0..3).any(|k| t[k] == a && t[(k + 1) % 3] == b))
        .count()
}

/// A line as a JSON object.
pub fn object(line: &str) -> Result<Map<String, Value>, CaseError> {
    match serde_json::from_str(line).map_err(|e| CaseError::Json(e.to_string()))? {
        Value::Object(m) => Ok(m),
        _ => Err(CaseError::NotObject),
    }
}

/// The nearest f32 to a JSON number's decimal text; an error when it is not finite in f32.
pub fn number(x: &Value) -> Result<f32, String> {
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

/// A point `[x, y, z]`, each the nearest f32 to its decimal text.
pub fn vec3(v: &Value) -> Result<Vec3, String> {
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

/// A tetrahedron's case as its line holds it (`tet`, `org`, `dir`, `entry`): the exit-face family's
/// fields, and a wrong walk's first wrong step.
pub fn tet_case_json(c: &Case) -> Map<String, Value> {
    let v = serde_json::json!({
        "tet": c.tet.map(|p| p.to_array()),
        "org": c.org.to_array(),
        "dir": c.dir.to_array(),
        "entry": c.entry,
    });
    match v {
        Value::Object(m) => m,
        _ => Map::new(),
    }
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
