//! The case format: JSON Lines read by `tetwalk exit`, written by `gen-cases`, and embedded by found
//! cases. A line is a one-tetrahedron case `{"tet": [[x,y,z] ×4], "org": [x,y,z], "dir": [x,y,z],
//! "entry": 0..3 or null}` or a walk case `{"mesh": "kuhn"|"jitter"|"fan", "size": N, "offset": X,
//! "org": [x,y,z], "dir": [x,y,z]}`; every number is the nearest f32 to its decimal text (one
//! rounding). Also: judging one answer against the oracle.

use crate::choice::Choice;
use crate::exact::{self, ExactError};
use crate::methods::triangle::Tri;
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

/// What a line asks about: one tetrahedron, a walk through a generated mesh, or a ray and triangles.
#[derive(Clone, Copy, Debug, PartialEq)]
#[allow(
    clippy::large_enum_variant,
    reason = "a closed mesh inline (up to 20 triangles) keeps cases Copy; batches hold tens of them"
)]
pub enum Subject {
    Exit(Case),
    Walk(WalkCase),
    Hit(HitCase),
    Box(BoxCase),
}

/// An octree cell case: `{"box": [[lx, ly, lz], [hx, hy, hz]], "org", "dir"}`, a closed axis-aligned
/// box (`lo < hi` on every axis) and a ray whose exit face and quarter are asked (seed 001).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoxCase {
    pub lo: Vec3,
    pub hi: Vec3,
    pub org: Vec3,
    pub dir: Vec3,
}

impl BoxCase {
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
    pub org: Vec3,
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
                            "edge {:?} -> {:?} runs so {same} time(s) and back {back} time(s); a closed mesh runs each edge once each way",
                            a.to_array(),
                            b.to_array()
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

    pub fn tris(&self) -> &[Tri] {
        &self.tris[..self.len as usize]
    }

    pub fn ray(&self) -> Ray {
        Ray {
            org: self.org,
            dir: self.dir,
        }
    }
}

/// How many triangles of `mesh` run the edge `a → b`.
fn edge_uses(mesh: &[Tri], a: Vec3, b: Vec3) -> usize {
    mesh.iter()
        .filter(|t| (0..3).any(|k| t[k] == a && t[(k + 1) % 3] == b))
        .count()
}

/// Largest grid or fan size of a walk case (a Kuhn grid of this size has 6·64³ tetrahedra).
pub const MAX_WALK_SIZE: u32 = 64;

impl Subject {
    /// The case's ray.
    pub fn ray(&self) -> Ray {
        match self {
            Subject::Exit(c) => c.ray(),
            Subject::Walk(w) => w.ray(),
            Subject::Hit(h) => h.ray(),
            Subject::Box(b) => b.ray(),
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
            Subject::Hit(h) => Subject::Hit(HitCase {
                org: ray.org,
                dir: ray.dir,
                ..h
            }),
            Subject::Box(b) => Subject::Box(BoxCase {
                org: ray.org,
                dir: ray.dir,
                ..b
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
        if obj.contains_key("tri") || obj.contains_key("tris") {
            return take_hit(obj).map(Subject::Hit);
        }
        if obj.contains_key("box") {
            return take_box(obj).map(Subject::Box);
        }
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
            Subject::Hit(h) => {
                let tris: Vec<_> = h.tris().iter().map(|t| t.map(|p| p.to_array())).collect();
                let key = if h.closed { "tris" } else { "tri" };
                let tris = if h.closed {
                    serde_json::json!(tris)
                } else {
                    serde_json::json!(tris[0])
                };
                serde_json::json!({key: tris, "org": h.org.to_array(), "dir": h.dir.to_array()})
            }
            Subject::Box(b) => serde_json::json!({
                "box": [b.lo.to_array(), b.hi.to_array()],
                "org": b.org.to_array(),
                "dir": b.dir.to_array(),
            }),
        };
        match v {
            Value::Object(m) => m,
            _ => Map::new(),
        }
    }
}

/// Take a triangle case's fields (`tri` or `tris`, `org`, `dir`) out of `obj`.
fn take_hit(obj: &mut Map<String, Value>) -> Result<HitCase, CaseError> {
    let tri = |v: &Value, at: &str| -> Result<Tri, CaseError> {
        let a = v
            .as_array()
            .filter(|a| a.len() == 3)
            .ok_or_else(|| field_error(at, "must hold three points"))?;
        let mut t = [Vec3::ZERO; 3];
        for (i, p) in a.iter().enumerate() {
            t[i] = vec3(p).map_err(|e| field_error(format!("{at}[{i}]"), e))?;
        }
        Ok(t)
    };
    let single = obj.remove("tri");
    let mesh = obj.remove("tris");
    let mut field = |k: &'static str| obj.remove(k).ok_or(CaseError::Missing(k));
    let org = vec3(&field("org")?).map_err(|e| field_error("org", e))?;
    let dir = vec3(&field("dir")?).map_err(|e| field_error("dir", e))?;
    let ray = Ray { org, dir };
    let case = match (single, mesh) {
        (Some(_), Some(_)) => return Err(field_error("tris", "give tri or tris, not both")),
        (Some(t), None) => HitCase::single(tri(&t, "tri")?, ray),
        (None, Some(m)) => {
            let m = m
                .as_array()
                .ok_or_else(|| field_error("tris", "must be a list of triangles"))?;
            if m.len() > MAX_TRIS {
                return Err(field_error(
                    "tris",
                    format!("holds {} triangles, more than {MAX_TRIS}", m.len()),
                ));
            }
            let m = m
                .iter()
                .enumerate()
                .map(|(i, t)| tri(t, &format!("tris[{i}]")))
                .collect::<Result<Vec<Tri>, _>>()?;
            HitCase::closed(&m, ray)?
        }
        (None, None) => return Err(CaseError::Missing("tri")),
    };
    if dir == Vec3::ZERO {
        return Err(ExactError::ZeroDirection.into());
    }
    for t in case.tris() {
        exact::hit::ray_triangle(*t, &ray)?;
    }
    Ok(case)
}

/// Take a box case's fields (`box`, `org`, `dir`) out of `obj`; the box must be closed and not flat.
fn take_box(obj: &mut Map<String, Value>) -> Result<BoxCase, CaseError> {
    let mut field = |k: &'static str| obj.remove(k).ok_or(CaseError::Missing(k));
    let b = field("box")?;
    let corners = b
        .as_array()
        .filter(|a| a.len() == 2)
        .ok_or_else(|| field_error("box", "must hold two corners, [[lx, ly, lz], [hx, hy, hz]]"))?;
    let lo = vec3(&corners[0]).map_err(|e| field_error("box[0]", e))?;
    let hi = vec3(&corners[1]).map_err(|e| field_error("box[1]", e))?;
    let org = vec3(&field("org")?).map_err(|e| field_error("org", e))?;
    let dir = vec3(&field("dir")?).map_err(|e| field_error("dir", e))?;
    if let Some(a) = (0..3).find(|&a| lo[a] >= hi[a]) {
        return Err(field_error(
            "box",
            format!(
                "the lower corner's {} ({}) is not below the upper one's ({})",
                ["x", "y", "z"][a],
                lo[a],
                hi[a]
            ),
        ));
    }
    if dir == Vec3::ZERO {
        return Err(ExactError::ZeroDirection.into());
    }
    Ok(BoxCase { lo, hi, org, dir })
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

/// One point where a ray meets a triangle case's surface, exactly.
#[derive(Clone, Debug, PartialEq)]
pub struct HitPoint {
    pub t: rug::Rational,
    /// The triangles holding the point.
    pub holding: Vec<u32>,
    /// Whether the ray crosses the surface there: every triangle holding the point faces the same way
    /// along the ray (`n·d` of one sign) and none whose plane holds the ray shares the point. Otherwise
    /// it only touches it (an edge or vertex on the silhouette, or runs along a triangle) — or crosses
    /// a saddle, which this test does not tell apart.
    pub crosses: bool,
    /// The triangles around the point that face the way the ray crosses there: those sharing a vertex
    /// with a triangle holding it, with `n·d` of the same sign. A ray that crosses the surface and hits none of them passes through: a leak, unless a silhouette is near ([`HitPoint::silhouette`]).
    pub around: Vec<u32>,
    /// Whether the point lies so near a silhouette that a miss may be rounding carrying the ray off it
    /// rather than through a crack: a triangle around it is seen within 2^-10 radians of edge-on, or,
    /// for a point inside one triangle, the triangle across its nearest edge faces the other way (or
    /// is parallel to the ray), or the point is within 1/1000 of that edge's length from a vertex around
    /// which a triangle does. Measured in f64: it sorts misses into leaks and misses beside the
    /// object, and decides no answer.
    pub silhouette: bool,
}

/// How a method misses where a ray crosses a closed surface ([`HitTruth::missed`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Missed {
    /// Through the surface: a crack at a shared edge or vertex, or between triangles.
    Leak,
    /// Beside the object as the method rounds the ray: near a silhouette, or no hit on it at all.
    Beside,
}

/// The exact answer to a triangle case.
#[derive(Clone, Debug, PartialEq)]
pub struct HitTruth {
    /// Per triangle, whether the ray hits it and on its boundary ([`exact::hit::ray_triangle`]).
    pub each: Vec<exact::hit::RayHit>,
    /// Where the ray meets the surface, nearest first.
    pub points: Vec<HitPoint>,
    pub closed: bool,
}

impl HitTruth {
    /// The first point the ray meets.
    pub fn first(&self) -> Option<&HitPoint> {
        self.points.first()
    }

    /// The first point where the ray crosses the surface.
    pub fn first_crossing(&self) -> Option<&HitPoint> {
        self.points.iter().find(|p| p.crosses)
    }

    /// How a method whose hits (any `t`) are `hits` misses where the ray crosses the surface: `None`
    /// when it hits a triangle around the first crossing that faces the ray's way. A leak where the
    /// crossing is at a shared edge or vertex, or where the method sees the surface elsewhere along the
    /// ray (it passed through); [`Missed::Beside`] where rounding may have carried the ray off the
    /// object: a silhouette near ([`HitPoint::silhouette`]), a chord inside the object shorter than
    /// 2^-10 of the way to it (the ray only clips a corner), or, inside a triangle, no hit at all.
    pub fn missed(&self, hits: &[u32]) -> Option<Missed> {
        let k = self.points.iter().position(|p| p.crosses)?;
        let p = &self.points[k];
        if p.around.is_empty() || hits.iter().any(|i| p.around.contains(i)) {
            return None;
        }
        let at_edge =
            p.holding.len() > 1 || p.holding.iter().any(|&h| self.each[h as usize].on_boundary);
        let thin = self
            .points
            .get(k + 1)
            .is_some_and(|q| rug::Rational::from(&q.t - &p.t) * rug::Rational::from(1024) < p.t);
        Some(if !p.silhouette && !thin && (at_edge || !hits.is_empty()) {
            Missed::Leak
        } else {
            Missed::Beside
        })
    }

    /// Whether the method leaks ([`HitTruth::missed`]).
    pub fn leaks(&self, hits: &[u32]) -> bool {
        self.missed(hits) == Some(Missed::Leak)
    }

    /// Whether a method's nearest hit (a triangle, or none) is right. One triangle: a hit on its
    /// boundary may be answered either way, otherwise hit or miss must match. A closed mesh: a
    /// triangle holding the first point the ray crosses the surface at, or one holding a point before
    /// it where the ray only touches the surface; a miss when the ray never crosses it.
    pub fn right(&self, answer: Option<u32>) -> bool {
        if !self.closed {
            return self.each[0].on_boundary || answer.is_some() == self.each[0].hit;
        }
        let upto = self
            .points
            .iter()
            .position(|p| p.crosses)
            .map_or(self.points.len(), |k| k + 1);
        match answer {
            None => self.first_crossing().is_none(),
            Some(i) => self.points[..upto].iter().any(|p| p.holding.contains(&i)),
        }
    }
}

/// How far an f32 `t` lies from the exact `t`, in ulps of the f32 nearest the exact one (2^-149 below
/// the normal range; the largest f32's ulp beyond it).
pub fn ulps_from(t: f32, exact: &rug::Rational) -> f64 {
    let near = exact.to_f32().abs().min(f32::MAX);
    let ulp = if near < f32::MIN_POSITIVE {
        2f64.powi(-149)
    } else {
        2f64.powi(near.log2().floor() as i32 - 23)
    };
    let off = rug::Rational::from_f32(t).map(|q| (q - exact).abs());
    off.map_or(f64::INFINITY, |d| {
        (d / rug::Rational::from_f64(ulp).expect("a power of two")).to_f64()
    })
}

/// A hit's `t` judged: the README's rule (a hit has `0 < t < ∞`) and its distance from the exact
/// `t` of the point the answer names, within `bound` ulps ([`ulps_from`]).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct TJudged {
    /// `None` when the answer names no exact hit point (a wrong triangle, or a hit where there is
    /// none).
    pub ulps: Option<f64>,
    pub right: bool,
}

impl HitTruth {
    /// The exact `t` of the hit on triangle `tri` this answer may name: the one-triangle case's hit,
    /// or the closed mesh's point holding `tri` at which [`HitTruth::right`] accepts it.
    pub fn exact_t(&self, tri: u32) -> Option<&rug::Rational> {
        if !self.closed {
            return match self.each[0].hit {
                true => self.points.first().map(|p| &p.t),
                false => None,
            };
        }
        let upto = self
            .points
            .iter()
            .position(|p| p.crosses)
            .map_or(self.points.len(), |k| k + 1);
        self.points[..upto]
            .iter()
            .find(|p| p.holding.contains(&tri))
            .map(|p| &p.t)
    }

    /// A hit on `tri` at `t` judged for its `t` ([`TJudged`]).
    pub fn judge_t(&self, tri: u32, t: f32, bound: f64) -> TJudged {
        let ulps = self.exact_t(tri).map(|e| ulps_from(t, e));
        let rule = t > 0.0 && t.is_finite();
        TJudged {
            ulps,
            right: rule && ulps.is_some_and(|u| u <= bound),
        }
    }
}

/// The oracle's answer to a triangle case.
pub fn judge_hit(case: &HitCase) -> Result<HitTruth, CaseError> {
    let ray = case.ray();
    let mut each = Vec::with_capacity(case.tris().len());
    let mut points: Vec<HitPoint> = Vec::new();
    for (i, tri) in case.tris().iter().enumerate() {
        let h = exact::hit::ray_triangle(*tri, &ray)?;
        each.push(h);
        let Some(t) = exact::hit::ray_triangle_t(*tri, &ray)? else {
            continue;
        };
        match points.iter_mut().find(|p| p.t == t) {
            Some(p) => p.holding.push(i as u32),
            None => points.push(HitPoint {
                t,
                holding: vec![i as u32],
                crosses: true,
                around: Vec::new(),
                silhouette: false,
            }),
        }
    }
    points.sort_by(|a, b| a.t.cmp(&b.t));
    let tris = case.tris();
    let facing: Vec<i8> = tris
        .iter()
        .map(|[a, b, c]| exact::normal_dot(*a, *b, *c, ray.dir))
        .collect();
    for p in &mut points {
        let way = facing[p.holding[0] as usize];
        p.crosses = p.holding.iter().all(|&i| facing[i as usize] == way)
            && !lies_in_at(tris, &facing, &p.holding, &ray);
        let touches = |j: usize| {
            p.holding
                .iter()
                .any(|&i| tris[i as usize].iter().any(|v| tris[j].contains(v)))
        };
        p.around = (0..tris.len())
            .filter(|&j| facing[j] == way && touches(j))
            .map(|j| j as u32)
            .collect();
        // A triangle around the point seen within 2^-10 radians of edge-on: rounding may turn it.
        let edge_on = (0..tris.len()).any(|j| touches(j) && edge_on(&tris[j], ray.dir));
        p.silhouette = edge_on
            || matches!(p.holding[..], [h] if near_silhouette(tris, &facing, h as usize, way, &ray, &p.t));
    }
    Ok(HitTruth {
        each,
        points,
        closed: case.closed,
    })
}

/// Whether a triangle whose plane holds the ray shares the edge or vertex of the holding triangles the
/// point lies on (an edge of a holder the line meets, `side = 0`; a vertex where two meet): the ray
/// then runs along the surface there instead of crossing it.
fn lies_in_at(tris: &[Tri], facing: &[i8], holding: &[u32], ray: &Ray) -> bool {
    let mut edges: Vec<[Vec3; 2]> = Vec::new();
    let mut vertices: Vec<Vec3> = Vec::new();
    for &h in holding {
        let t = tris[h as usize];
        let zero: Vec<usize> = (0..3)
            .filter(|&k| exact::side(t[k], t[(k + 1) % 3], ray) == 0)
            .collect();
        for &k in &zero {
            edges.push([t[k], t[(k + 1) % 3]]);
        }
        if zero.len() >= 2 {
            // Two edges meet at the vertex between them: the point is that vertex.
            let (k0, k1) = (zero[0], zero[1]);
            vertices.push(if (k0 + 1) % 3 == k1 { t[k1] } else { t[k0] });
        }
    }
    tris.iter().zip(facing).any(|(t, &f)| {
        f == 0
            && crate::tet::orientation(&[t[0], t[1], t[2], ray.org]) == 0
            && (vertices.iter().any(|v| t.contains(v))
                || edges.iter().any(|[a, b]| t.contains(a) && t.contains(b)))
    })
}

/// Whether the ray sees the triangle within 2^-10 radians of edge-on (in f64: it only sorts misses).
fn edge_on(t: &Tri, d: Vec3) -> bool {
    let w = |v: Vec3| glam::DVec3::new(v.x as f64, v.y as f64, v.z as f64);
    let n = (w(t[1]) - w(t[0])).cross(w(t[2]) - w(t[0]));
    n.dot(w(d)).abs() <= n.length() * w(d).length() * 2f64.powi(-10)
}

/// [`HitPoint::silhouette`] for a point `o + t·d` inside triangle `h`, which faces `way`.
fn near_silhouette(
    tris: &[Tri],
    facing: &[i8],
    h: usize,
    way: i8,
    ray: &Ray,
    t: &rug::Rational,
) -> bool {
    let w = |v: Vec3| glam::DVec3::new(v.x as f64, v.y as f64, v.z as f64);
    let p = w(ray.org) + w(ray.dir) * t.to_f64();
    let tri = tris[h].map(w);
    // The nearest edge, by distance from p to the edge's segment.
    let dist = |a: glam::DVec3, b: glam::DVec3| {
        let s = ((p - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
        (a + (b - a) * s - p).length()
    };
    let k = (0..3)
        .min_by(|&i, &j| dist(tri[i], tri[(i + 1) % 3]).total_cmp(&dist(tri[j], tri[(j + 1) % 3])))
        .unwrap_or(0);
    let (a, b) = (tris[h][k], tris[h][(k + 1) % 3]);
    let away = |j: usize| facing[j] != way;
    let across = (0..tris.len()).find(|&j| j != h && tris[j].contains(&a) && tris[j].contains(&b));
    if across.is_none_or(away) {
        return true;
    }
    let len = (w(b) - w(a)).length();
    [a, b].iter().any(|&v| {
        (w(v) - p).length() < len * 1e-3 && (0..tris.len()).any(|j| tris[j].contains(&v) && away(j))
    })
}
