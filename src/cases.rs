//! (tetrahedron, ray) cases as JSON Lines, and judging a method's answer on one against the oracle.

use crate::exact::{self, ExactError};
use crate::methods::Method;
use crate::tet::{Ray, SWAP01, Tet, normalize};
use glam::Vec3;
use serde_json::Value;

/// One case: `{"tet": [[x,y,z] ×4], "org": [x,y,z], "dir": [x,y,z], "entry": 0..3 or null}`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Case {
    #[serde(serialize_with = "ser_tet")]
    pub tet: Tet,
    #[serde(serialize_with = "ser_vec")]
    pub org: Vec3,
    #[serde(serialize_with = "ser_vec")]
    pub dir: Vec3,
    pub entry: Option<u8>,
}

fn ser_vec<S: serde::Serializer>(v: &Vec3, s: S) -> Result<S::Ok, S::Error> {
    serde::Serialize::serialize(&v.to_array(), s)
}

fn ser_tet<S: serde::Serializer>(t: &Tet, s: S) -> Result<S::Ok, S::Error> {
    serde::Serialize::serialize(&t.map(|v| v.to_array()), s)
}

impl Case {
    pub fn ray(&self) -> Ray {
        Ray {
            org: self.org,
            dir: self.dir,
        }
    }

    /// Parse one line. Every number is taken as the nearest f32 to its decimal text (one rounding).
    pub fn parse(line: &str) -> Result<Case, String> {
        let v: Value = serde_json::from_str(line).map_err(|e| format!("malformed JSON: {e}"))?;
        let obj = v.as_object().ok_or("expected a JSON object")?;
        // Found cases (corpora/found/) carry what failed; those fields are read past.
        let known = ["tet", "org", "dir", "entry", "method", "fma", "kind"];
        if let Some(k) = obj.keys().find(|k| !known.contains(&k.as_str())) {
            return Err(format!("unknown field '{k}'"));
        }
        let field = |k: &str| obj.get(k).ok_or_else(|| format!("missing field '{k}'"));
        let tet = field("tet")?
            .as_array()
            .filter(|a| a.len() == 4)
            .ok_or("'tet' must hold four points")?;
        let mut t = [Vec3::ZERO; 4];
        for (i, p) in tet.iter().enumerate() {
            t[i] = vec3(p).map_err(|e| format!("tet[{i}]: {e}"))?;
        }
        let org = vec3(field("org")?).map_err(|e| format!("org: {e}"))?;
        let dir = vec3(field("dir")?).map_err(|e| format!("dir: {e}"))?;
        let entry = match obj.get("entry") {
            None | Some(Value::Null) => None,
            Some(e) => Some(
                e.as_u64()
                    .filter(|&f| f < 4)
                    .ok_or_else(|| format!("entry must be 0..3 or null, not {e}"))?
                    as u8,
            ),
        };
        Ok(Case {
            tet: t,
            org,
            dir,
            entry,
        })
    }
}

fn vec3(v: &Value) -> Result<Vec3, String> {
    let a = v
        .as_array()
        .filter(|a| a.len() == 3)
        .ok_or("expected [x, y, z]")?;
    let mut out = [0f32; 3];
    for (i, x) in a.iter().enumerate() {
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
        out[i] = f;
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
pub fn classify(case: &Case) -> Result<exact::Classification, String> {
    let c = exact::classify(&case.tet, &case.ray()).map_err(|e: ExactError| e.to_string())?;
    if let Some(e) = case.entry
        && !c.entry.contains(e as usize)
    {
        return Err(format!(
            "entry {e} is not an exact entry face (exact entry faces: {:?})",
            c.entry.to_vec()
        ));
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

/// `method`'s exit face for a case on the CPU, in the case's own numbering.
pub fn answer(case: &Case, method: &Method, fma: bool) -> Option<usize> {
    let (tet, entry, map) = normalized(case);
    method.exit(fma)(&tet, &case.ray(), entry).map(|f| map[f])
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

/// Run `method` on a case on the CPU and judge it.
pub fn judge(case: &Case, c: &exact::Classification, method: &Method, fma: bool) -> Judged {
    judged(c, answer(case, method, fma))
}

/// Each case's exit face by `method` on the GPU, in the cases' own numbering.
pub fn answers_gpu(
    gpu: &crate::gpu::Gpu,
    cases: &[Case],
    method: &Method,
) -> Result<Vec<Option<usize>>, String> {
    let prepared: Vec<_> = cases.iter().map(normalized).collect();
    let input: Vec<_> = cases
        .iter()
        .zip(&prepared)
        .map(|(c, (tet, entry, _))| crate::gpu::GpuCase::new(tet, &c.ray(), *entry))
        .collect();
    let faces = gpu
        .exit_faces(method.name, &input)
        .map_err(|e| e.to_string())?;
    Ok(faces
        .into_iter()
        .zip(&prepared)
        .map(|(f, (_, _, map))| f.map(|f| map[f]))
        .collect())
}
