//! A ray and triangles (seed 004's question): one triangle, or a closed mesh whose first hit is asked;
//! the answer every hit the method reports (its nearest judged, its misses judged for leaks).

pub mod bins;
#[cfg(feature = "cli")]
pub mod cli;
pub mod engine;
pub mod kit;
#[cfg(feature = "internals")]
mod report;
use super::count::{CountError, Counted, Counts, Prepared, Scene, per_image};
use super::wrong::Class;
use super::{Family, Said, Summed, Verdict, given_fields};
use crate::backend::{Backend, BackendError, Pending, TrianglesOn};
use crate::cases::{CaseError, HitCase, MAX_TRIS, field_error, number, vec3};
use crate::choice::{BackendKind, Choice};
use crate::exact::hit::{HitTruth, Missed, T_ULPS, first_crossing, judge_hit};
use crate::mesh::surface::{SceneTriangles, both_sides, region_of, scene_triangles};
use crate::methods::triangle::nearest_of;
use crate::methods::triangle::{Among, MAX_PACKET, SideError};
use crate::registry::{Named, TRIANGLE_METHODS, TriangleMethod};
use crate::scenes::camera::packet_order;
use crate::scenes::closed::{MeshShape, TriAim, TriPlace, case};
use crate::tet::{Ray, Tri};
use crate::walk::{Outcome, OutcomeKind, Walk};
use glam::Vec3;
use rayon::prelude::*;
use serde_json::{Map, Value, json};
use std::sync::Arc;

/// Rays and triangles.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Triangle;

/// Every hit a method reports on a case (a triangle and its f32 `t`), in triangle order.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hits {
    len: u8,
    at: [(u32, f32); MAX_TRIS],
}

impl Hits {
    pub fn of(hits: &[(u32, f32)]) -> Hits {
        let mut at = [(0, 0.0); MAX_TRIS];
        let len = hits.len().min(MAX_TRIS);
        at[..len].copy_from_slice(&hits[..len]);
        Hits { len: len as u8, at }
    }

    pub(crate) fn all(&self) -> &[(u32, f32)] {
        &self.at[..self.len as usize]
    }

    /// The nearest hit: the first with the smallest `t`.
    pub fn nearest(&self) -> Option<(u32, f32)> {
        nearest_of(self.all())
    }

    /// The triangles hit.
    pub fn ids(&self) -> Vec<u32> {
        self.all().iter().map(|&(i, _)| i).collect()
    }
}

/// A stress row of closed meshes: a shape, an aim and a place.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct TriRow {
    pub(crate) shape: MeshShape,
    pub(crate) aim: TriAim,
    pub(crate) place: TriPlace,
}

/// What shapes a stress run of closed meshes.
#[derive(Clone, Debug, serde::Serialize)]
pub struct TriRows {
    pub(crate) shapes: Vec<MeshShape>,
    pub(crate) aims: Vec<TriAim>,
    pub(crate) places: Vec<TriPlace>,
    pub(crate) flatness: f32,
    pub(crate) ulps: i32,
}

impl Default for TriRows {
    fn default() -> Self {
        TriRows {
            shapes: MeshShape::ALL.to_vec(),
            aims: TriAim::ALL.to_vec(),
            places: TriPlace::ALL.to_vec(),
            flatness: 1e-3,
            ulps: 4,
        }
    }
}

/// What a row of closed meshes reports of its rays.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct TriFacts {
    /// Rays judged.
    pub(crate) rays: u64,
    /// Rays that cross the surface (the others only touch it, or miss).
    pub crossing: u64,
}

impl Summed for TriFacts {
    fn add(&mut self, o: &Self) {
        self.rays += o.rays;
        self.crossing += o.crossing;
    }
}

/// One method's counts on one row.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct HitTally {
    /// Rays that pass through the closed surface ([`Missed::Leak`]).
    pub leaks: u64,
    /// Rays that cross the surface but pass beside the object as the method rounds them
    /// ([`Missed::Beside`]).
    pub(crate) misses_beside: u64,
    /// Rays with a hit on a triangle holding the first crossing point and another on a triangle the
    /// exact ray misses (near a shared edge, both neighbours report it).
    pub(crate) double_hits: u64,
    /// Rays whose nearest hit is on a wrong triangle, or a miss where the ray crosses
    /// ([`HitTruth::right`]).
    pub(crate) wrong_first_hits: u64,
    /// Rays whose nearest hit is on a right triangle at a `t` beyond [`T_ULPS`] ulps of the exact one
    /// (or not in `0 < t < ∞`): wrong by [`HitTruth::judge`] for the `t` alone.
    pub wrong_t: u64,
}

impl Summed for HitTally {
    fn add(&mut self, o: &Self) {
        self.leaks += o.leaks;
        self.misses_beside += o.misses_beside;
        self.double_hits += o.double_hits;
        self.wrong_first_hits += o.wrong_first_hits;
        self.wrong_t += o.wrong_t;
    }
}

/// A triangle `[[x, y, z] ×3]` at `at`.
fn tri(v: &Value, at: &str) -> Result<Tri, CaseError> {
    let a = v
        .as_array()
        .filter(|a| a.len() == 3)
        .ok_or_else(|| field_error(at, "must hold three points"))?;
    let mut t = [Vec3::ZERO; 3];
    for (i, p) in a.iter().enumerate() {
        t[i] = vec3(p).map_err(|e| field_error(format!("{at}[{i}]"), e))?;
    }
    Ok(t)
}

/// A hit's `t`: present and a number when there is a hit, absent or null when there is none.
fn hit_t(o: &Map<String, Value>, hit: bool) -> Result<Option<f32>, String> {
    let t = match o.get("t") {
        None | Some(Value::Null) => None,
        Some(x) => Some(number(x).map_err(|e| format!("t: {e}"))?),
    };
    match (hit, t) {
        (true, None) => Err("a hit's answer needs its \"t\"".into()),
        (false, Some(t)) => Err(format!("\"t\": {t} given for a miss")),
        (_, t) => Ok(t),
    }
}

/// The key of a row: its place in the run of every row (shapes, then aims, then places).
fn row_key(row: &TriRow) -> u64 {
    let at = |i: Option<usize>| i.unwrap_or(0) as u64;
    let shape = at(MeshShape::ALL.iter().position(|&s| s == row.shape));
    let aim = at(TriAim::ALL.iter().position(|&a| a == row.aim));
    let place = at(TriPlace::ALL.iter().position(|&p| p == row.place));
    (shape * TriAim::ALL.len() as u64 + aim) * TriPlace::ALL.len() as u64 + place
}

/// A case's triangle corners, each distinct point once, in order of first use.
fn distinct_corners(h: &HitCase) -> Vec<Vec3> {
    let mut out: Vec<Vec3> = Vec::new();
    for &p in h.tris().iter().flatten() {
        if !out.contains(&p) {
            out.push(p);
        }
    }
    out
}

impl Family for Triangle {
    const CLAIM: crate::registry::Claim = crate::registry::Claim::NoLeak;
    const NAME: &'static str = "triangle";
    const FUZZ_TARGET: &'static str = "triangle_hit";
    const STRESS_CASES: usize = 2_000;
    const BYTES_PER_CASE: u128 = 4096;

    type Method = TriangleMethod;
    type Case = HitCase;
    type Truth = HitTruth;
    type Answer = Hits;
    type Rows = TriRows;
    type Row = TriRow;
    type RowFacts = TriFacts;
    type Tally = HitTally;

    fn methods() -> &'static [TriangleMethod] {
        TRIANGLE_METHODS
    }

    fn owns(obj: &Map<String, Value>) -> bool {
        obj.contains_key("tri") || obj.contains_key("tris")
    }

    fn take_case(obj: &mut Map<String, Value>) -> Result<HitCase, CaseError> {
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
            return Err(crate::exact::ExactError::ZeroDirection.into());
        }
        for t in case.tris() {
            crate::exact::hit::ray_triangle(*t, &ray)?;
        }
        Ok(case)
    }

    fn case_json(h: &HitCase) -> Map<String, Value> {
        let tris: Vec<_> = h.tris().iter().map(|t| t.map(|p| p.to_array())).collect();
        let (key, tris) = match h.closed {
            true => ("tris", json!(tris)),
            false => ("tri", json!(tris[0])),
        };
        match json!({key: tris, "org": h.org.to_array(), "dir": h.dir.to_array()}) {
            Value::Object(m) => m,
            _ => Map::new(),
        }
    }

    fn ray(h: &HitCase) -> Ray {
        h.ray()
    }

    fn with_ray(h: &HitCase, ray: Ray) -> HitCase {
        h.with_ray(ray)
    }

    const COMMAND: Option<&'static str> = Some("hit");

    /// Each distinct vertex once (a closed mesh's triangles share them), then the origin and
    /// direction.
    fn numbers(h: &HitCase) -> Vec<f32> {
        let corners = distinct_corners(h);
        super::points_numbers(corners.iter().chain([&h.org, &h.dir]))
    }

    fn with_numbers(h: &HitCase, n: &[f32]) -> Option<HitCase> {
        let corners = distinct_corners(h);
        let p = super::numbers_points(n);
        let moved = |v: Vec3| p[corners.iter().position(|&c| c == v).unwrap_or(0)];
        let tris: Vec<Tri> = h.tris().iter().map(|t| t.map(moved)).collect();
        let ray = Ray {
            org: p[corners.len()],
            dir: p[corners.len() + 1],
        };
        if h.closed {
            HitCase::closed(&tris, ray).ok()
        } else {
            Some(HitCase::single(tris[0], ray))
        }
    }

    /// For a closed mesh of more than four triangles, each tetrahedron closing two of its triangles
    /// that share an edge (`abc` and `bad`, closed by `cbd` and `acd`).
    fn smaller(h: &HitCase) -> Vec<HitCase> {
        let tris = h.tris();
        if !h.closed || tris.len() <= 4 {
            return Vec::new();
        }
        let mut out = Vec::new();
        for (i, t) in tris.iter().enumerate() {
            for k in 0..3 {
                let (a, b, c) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
                let Some(d) = tris[i + 1..].iter().find_map(|u| {
                    (0..3).find_map(|j| (u[j] == b && u[(j + 1) % 3] == a).then(|| u[(j + 2) % 3]))
                }) else {
                    continue;
                };
                if let Ok(tet) =
                    HitCase::closed(&[[a, b, c], [b, a, d], [c, b, d], [a, c, d]], h.ray())
                {
                    out.push(tet);
                }
            }
        }
        out
    }

    fn truth(h: &HitCase) -> Result<HitTruth, CaseError> {
        Ok(judge_hit(h.tris(), h.closed, &h.ray())?)
    }

    /// Right when the nearest hit's triangle and, for a hit, its `t` are ([`HitTruth::judge`] with
    /// [`T_ULPS`]): the rule `hit`, `judge`, stress rows, the kit and found cases share.
    fn verdict(_: &HitCase, truth: &HitTruth, hits: &Hits) -> Verdict {
        match truth.judge(hits.nearest(), T_ULPS).right {
            true => Verdict::Right,
            false => Verdict::Wrong(Self::kind(hits)),
        }
    }

    /// The nearest hit judged by [`HitTruth::judge`] within `t_ulps`; on a closed mesh, whether the
    /// answer leaks and what a wrong one is.
    fn said(case: &HitCase, truth: &HitTruth, hits: &Hits, t_ulps: f64) -> Said {
        let g = hits.nearest();
        let judged = truth.judge(g, t_ulps);
        Said {
            correct: Some(judged.right),
            triangle: true,
            leak: case.closed && truth.leaks(&hits.ids()),
            back_face: truth.back_face(),
            t_alone: judged.triangle && !judged.right,
            t_ulps: judged.t.and_then(|t| t.ulps),
            kind: case
                .closed
                .then(|| truth.wrong_kind(&hits.ids(), g.map(|(i, _)| i)))
                .flatten(),
            ..Said::default()
        }
    }

    /// The watertight claim: refuted by a leak ([`HitTruth::leaks`]).
    fn refutes_claim(_: &HitCase, truth: &HitTruth, hits: &Hits) -> bool {
        truth.leaks(&hits.ids())
    }

    fn right_answers(_: &HitCase, truth: &HitTruth) -> String {
        match truth.first() {
            Some(p) => format!(
                "a hit on triangle {:?} at exact t = {} (or, where the ray only touches there, the next crossing)",
                p.holding, p.t
            ),
            None => "no hit".into(),
        }
    }

    fn answers(
        backend: &Backend,
        m: &TriangleMethod,
        cases: &[HitCase],
    ) -> Result<Vec<Hits>, BackendError> {
        Ok(backend
            .triangle_hits(m, cases)?
            .iter()
            .map(|h| Hits::of(h))
            .collect())
    }

    fn wide_answers(m: &TriangleMethod, cases: &[HitCase]) -> Option<Vec<Hits>> {
        let wide = m.wide?;
        Some(
            cases
                .par_iter()
                .map(|c| Hits::of(&(wide.hits)(c.tris(), &c.ray())))
                .collect(),
        )
    }

    fn kind(hits: &Hits) -> OutcomeKind {
        match hits.nearest() {
            Some(_) => OutcomeKind::Hit,
            None => OutcomeKind::LeftMesh,
        }
    }

    fn answer_json(hits: &Hits) -> Value {
        hits.nearest()
            .map_or(Value::Null, |(tri, t)| json!({"tri": tri, "t": t}))
    }

    /// `{"tri": i, "t": t}` (a triangle of the case) or null: the nearest hit.
    fn parse_answer(v: &Value, h: &HitCase) -> Result<Hits, String> {
        if v.is_null() {
            return Ok(Hits::of(&[]));
        }
        let tris = h.tris().len();
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
        Ok(Hits::of(&[(tri as u32, t)]))
    }

    /// `{"tri": i|null, "t"}` for a closed mesh (the nearest hit), `{"hit": true|false, "t"}` for one
    /// triangle.
    fn given(obj: &Map<String, Value>, h: &HitCase) -> Result<Hits, String> {
        let g = if h.closed {
            let o = given_fields(obj, "a closed-mesh case (tris)", &["tri", "t"], &["tri"])?;
            match &o["tri"] {
                Value::Null => hit_t(o, false).map(|_| None)?,
                i => {
                    let len = h.tris().len();
                    let i = i.as_u64().filter(|&i| (i as usize) < len).ok_or_else(|| {
                        match i.as_i64() {
                            Some(..0) => format!(
                                "the answer's tri {i}: a miss is written \"tri\": null, without \"t\""
                            ),
                            _ => format!(
                                "the answer's tri {i} is not a triangle of the case (0..{len})"
                            ),
                        }
                    })?;
                    hit_t(o, true)?.map(|t| (i as u32, t))
                }
            }
        } else {
            let o = given_fields(obj, "a one-triangle case (tri)", &["hit", "t"], &["hit"])?;
            let hit = o["hit"]
                .as_bool()
                .ok_or("the answer's \"hit\" is true or false")?;
            hit_t(o, hit)?.map(|t| (0, t))
        };
        Ok(Hits::of(g.as_slice()))
    }

    /// 752 bytes: the number of triangles n and whether they close a mesh (two u32), the origin and
    /// the direction (6 f32), then 20 triangles' corners (180 f32), the first n used, the rest zero.
    fn case_record(h: &HitCase) -> Option<Vec<u8>> {
        let tris = h.tris();
        let mut b = Vec::with_capacity(752);
        b.extend((tris.len() as u32).to_le_bytes());
        b.extend((h.closed as u32).to_le_bytes());
        let mut numbers: Vec<f32> = [h.org, h.dir].iter().flat_map(|v| v.to_array()).collect();
        numbers.extend(tris.iter().flatten().flat_map(|v| v.to_array()));
        numbers.resize(6 + 9 * MAX_TRIS, 0.0);
        b.extend(numbers.iter().flat_map(|x| x.to_le_bytes()));
        Some(b)
    }

    /// 8 bytes: the triangle hit first (i32: its index, -1 for none; 0 for a one-triangle case's hit)
    /// and its `t` (f32; anything for none).
    const ANSWER_RECORD: usize = 8;

    fn answer_record(b: &[u8], h: &HitCase) -> Result<Hits, String> {
        let tri = i32::from_le_bytes([b[0], b[1], b[2], b[3]]);
        let t = f32::from_le_bytes([b[4], b[5], b[6], b[7]]);
        let len = h.tris().len() as i32;
        match tri {
            -1 => Ok(Hits::of(&[])),
            i if (0..len).contains(&i) => Ok(Hits::of(&[(i as u32, t)])),
            _ => Err(format!(
                "answered triangle {tri}, not one of the case's (0..{len}) or -1 (none)"
            )),
        }
    }

    fn describe(hits: &Hits) -> String {
        match hits.nearest() {
            Some((tri, t)) => format!("triangle {tri} at t = {t:e}"),
            None => "no hit".into(),
        }
    }

    fn rows(r: &TriRows) -> Vec<TriRow> {
        let mut out = Vec::new();
        for &shape in &r.shapes {
            for &aim in &r.aims {
                for &place in &r.places {
                    out.push(TriRow { shape, aim, place });
                }
            }
        }
        out
    }

    fn row_name(r: &TriRow) -> String {
        format!("{}-{}-{}", r.shape.name(), r.aim.name(), r.place.name())
    }

    fn case(r: &TriRows, row: TriRow, seed: u64, i: usize) -> Option<(HitCase, HitTruth)> {
        let mut rng = crate::scenes::row_rng(seed, row_key(&row), i);
        let (mesh, ray) = case(row.shape, row.aim, row.place, r.flatness, r.ulps, &mut rng);
        let c = HitCase::closed(&mesh, ray).ok()?;
        let truth = Self::truth(&c).ok()?;
        Some((c, truth))
    }

    fn row_facts(cases: &[(HitCase, HitTruth)]) -> TriFacts {
        TriFacts {
            rays: cases.len() as u64,
            crossing: cases
                .iter()
                .filter(|(_, t)| t.first_crossing().is_some())
                .count() as u64,
        }
    }

    fn tally(t: &mut HitTally, _: &HitCase, truth: &HitTruth, hits: &Hits) {
        let crossing = truth.first_crossing();
        let holding: &[u32] = crossing.map_or(&[], |p| &p.holding);
        match truth.missed(&hits.ids()) {
            Some(Missed::Leak) => t.leaks += 1,
            Some(Missed::Beside) => t.misses_beside += 1,
            None => {}
        }
        let all = hits.all();
        let false_hit = all.iter().any(|&(i, _)| !truth.each[i as usize].hit);
        t.double_hits += (false_hit && all.iter().any(|&(i, _)| holding.contains(&i))) as u64;
        let judged = truth.judge(hits.nearest(), T_ULPS);
        t.wrong_first_hits += !judged.triangle as u64;
        t.wrong_t += (judged.triangle && !judged.right) as u64;
    }

    fn judged(facts: &TriFacts, _: &HitTally) -> u64 {
        facts.rays
    }

    /// Wrong by [`Triangle::verdict`]'s rule: a wrong first hit, or a right triangle at a wrong `t`.
    fn wrong(t: &HitTally) -> u64 {
        t.wrong_first_hits + t.wrong_t
    }

    fn refuted(t: &HitTally) -> u64 {
        t.leaks
    }

    fn arbitrary(u: &mut arbitrary::Unstructured) -> Option<HitCase> {
        let (mesh, ray) = crate::scenes::from_bytes::hit_case(u).ok()?;
        HitCase::closed(&mesh, ray).ok()
    }

    /// Seventy-five rows: a tenth of the cases each.
    fn kit_row_cases(cases: usize) -> usize {
        (cases / 10).max(1)
    }
}

/// One ray–triangle method's counts over a count's views.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct TriangleCount {
    /// Rays whose nearest hit is not on a triangle holding the exact first hit point.
    pub(crate) wrong_triangle: u64,
    /// Rays the reference sees hit the surface that the method sees miss every triangle.
    pub(crate) false_miss: u64,
    /// Wrong rays per image, averaged over the views counted.
    pub(crate) wrong_per_image: f64,
}

impl Counts for TriangleCount {
    fn kinds(&self) -> [u64; 5] {
        let mut k = [0; 5];
        k[OutcomeKind::Hit.code() as usize] = self.wrong_triangle;
        k[OutcomeKind::LeftMesh.code() as usize] = self.false_miss;
        k
    }

    fn add_wrong(&mut self, kind: OutcomeKind, _: Option<Class>) {
        match kind {
            OutcomeKind::LeftMesh => self.false_miss += 1,
            _ => self.wrong_triangle += 1,
        }
    }

    fn add(&mut self, o: &Self) {
        self.wrong_triangle += o.wrong_triangle;
        self.false_miss += o.false_miss;
    }

    fn finish(&mut self, views: usize) {
        self.wrong_per_image = self.wrong_total() as f64 / views.max(1) as f64;
    }

    fn check(&self, at: &str, views: usize) -> Result<(), (String, String)> {
        per_image(at, self.wrong_per_image, self.wrong_total(), views)
    }
}

/// What a ray–triangle count sets: the packets of primary rays, and how candidates are found.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct TriCountSettings {
    /// Primary rays per packet side: packets of `packet × packet` pixels sharing the camera's origin.
    pub packet: u32,
    /// Every triangle tested per ray, instead of each tile's candidates ([`bins`]).
    #[serde(default)]
    pub brute_force: bool,
}

/// Whether a count with `settings` on a backend of `kind` tests each tile's candidates ([`bins`])
/// for the methods that obey the bins' lemma: on a CPU backend, unless `--brute-force`.
pub(crate) fn binned_on(settings: &TriCountSettings, kind: BackendKind) -> bool {
    !settings.brute_force && kind.model().is_some()
}

/// What a ray–triangle count's report says of its scene.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct TriangleFacts {
    /// The scene's triangles: its constrained faces, once each.
    pub(crate) triangles: usize,
}

/// The scene's triangles facing a camera's region, with the region, and the last view's candidates
/// (its index, tile side, error scale and bins, shared by the view's methods of that scale).
pub struct Facing {
    region: Vec<bool>,
    triangles: SceneTriangles,
    /// The triangles made ready where hits are compared with the reference walk.
    on: TrianglesOn,
    binned: std::sync::Mutex<Vec<ViewBins>>,
}

/// One view's candidates: its index, the tile side, the error scale, the bins.
type ViewBins = (usize, u32, SideError, Arc<Among>);

/// A nearest hit as a walk's ending: on the constrained face its triangle came from, or the mesh left.
fn ending(hit: Option<u32>, from: &[(u32, u8)]) -> Walk {
    let outcome = match hit {
        Some(i) => {
            let (tet, face) = from[i as usize];
            Outcome::Hit { tet, face }
        }
        None => Outcome::LeftMesh { tet: 0, face: 0 },
    };
    Walk { outcome, steps: 0 }
}

impl Counted for Triangle {
    type CountSettings = TriCountSettings;
    type Ready = Facing;
    type SceneFacts = TriangleFacts;
    type Counts = TriangleCount;
    const EXACT: &'static str = "the exact first hit among the triangles";
    const DEFAULT_VIEWS: (usize, &'static str) = (16, "128x128");

    fn check(s: &TriCountSettings) -> Result<(), String> {
        match s.packet {
            1 | 2 | 4 | 8 => Ok(()),
            p => Err(format!("packet {p} is not 1, 2, 4 or 8")),
        }
    }

    fn prepare(
        scene: &Scene,
        _: &TriCountSettings,
        backend: &Backend,
        located: u32,
    ) -> Result<Facing, CountError> {
        let region = region_of(&scene.loaded.mesh, located);
        let triangles = scene_triangles(&scene.loaded.mesh, &region);
        Ok(Facing {
            region,
            on: backend.triangles(&triangles.0, &both_sides(&scene.loaded.mesh, &triangles.1)),
            triangles,
            binned: Default::default(),
        })
    }

    fn serves(ready: &Facing, located: u32) -> bool {
        ready.region[located as usize]
    }

    fn facts(_: &Scene, ready: Option<&Facing>) -> TriangleFacts {
        TriangleFacts {
            triangles: ready.map_or(0, |r| r.triangles.0.len()),
        }
    }

    /// On the CPU, each tile's candidate triangles ([`bins`]) tested per ray in ascending order,
    /// the nearest hit the brute-force one (the audited rays are answered both ways and must agree);
    /// on the GPU, for a method written outside tetwalk, or with `--brute-force`, every triangle. Rays
    /// in packets of `packet × packet` pixels.
    fn answer_rays(
        at: &Prepared<Self>,
        m: &TriangleMethod,
        rays: &[Ray],
    ) -> Result<Vec<Walk>, CountError> {
        let (views, packet) = (at.scene.views, at.settings.packet);
        let tile = packet.max(bins::MIN_TILE);
        let order = packet_order(views.width, views.height, packet, tile);
        let packed: Vec<Ray> = order.iter().map(|&i| rays[i]).collect();
        let (tris, from) = &at.ready.triangles;
        let binned = m
            .side_error
            .filter(|_| binned_on(at.settings, at.backend.ran().kind));
        let among = match binned {
            Some(scale) => view_bins(at, tile, scale),
            None => Arc::new(Among::all(
                tris.len(),
                packed.len(),
                (packet * packet) as usize * 256,
            )),
        };
        let hits =
            at.backend
                .trace_triangles(m, tris, &packed, (packet * packet) as usize, &among)?;
        let mut nearest = vec![None; rays.len()];
        for (&i, hit) in order.iter().zip(&hits) {
            nearest[i] = *hit;
        }
        if binned.is_some() && !at.audited.is_empty() {
            let picked: Vec<Ray> = at.audited.iter().map(|&i| rays[i]).collect();
            // A run per thread, each preparing the triangles once; its rays (all from the view's
            // camera) in packets, which answer each ray as it alone would.
            let run = picked.len().div_ceil(rayon::current_num_threads());
            let all = Among::all(tris.len(), picked.len(), run);
            let brute = at
                .backend
                .trace_triangles(m, tris, &picked, run.min(MAX_PACKET), &all)?;
            for (&i, b) in at.audited.iter().zip(brute) {
                let same = |x: Option<(u32, f32)>| x.map(|(t, h)| (t, h.to_bits()));
                if same(nearest[i]) != same(b) {
                    return Err(CountError::Bins {
                        method: m.name().to_string(),
                        view: at.view,
                        pixel: [i as u32 % views.width, i as u32 / views.width],
                        binned: nearest[i],
                        brute: b,
                    });
                }
            }
        }
        Ok(nearest
            .into_iter()
            .map(|h| ending(h.map(|(t, _)| t), from))
            .collect())
    }

    /// Where the reference walk is kept (a GPU, which tries every triangle per ray: no bins), the
    /// rays read there in pixel order (a GPU thread answers a ray as it alone would), each nearest
    /// hit compared there.
    fn answer_against<'a>(
        at: &'a Prepared<Self>,
        m: &'a TriangleMethod,
        rays: &'a [Ray],
    ) -> Result<Option<Pending<'a>>, CountError> {
        let from = &at.ready.triangles.1;
        let pending = at
            .backend
            .triangles_against(m, &at.ready.on, rays, at.located)?;
        Ok(pending.map(|p| p.map(|h| ending(h.map(|(t, _)| t), from))))
    }

    /// The exact first crossing of each audited ray among its tile's edge-scaled candidates (an exact
    /// crossing has its side products of one sign exactly, inside every bound of [`bins`], so
    /// none is left out: were one, the reference walk would disagree and the audit stop the count), or
    /// among every triangle with `--brute-force`.
    fn audit(at: &Prepared<Self>, rays: &[Ray]) -> Result<Vec<Walk>, CountError> {
        let (tris, from) = &at.ready.triangles;
        let (views, tile) = (at.scene.views, at.settings.packet.max(bins::MIN_TILE));
        let among = (!at.settings.brute_force).then(|| view_bins(at, tile, SideError::EdgeScaled));
        Ok(rays
            .par_iter()
            .zip(at.audited)
            .map(|(r, &pixel)| {
                let first = match &among {
                    Some(among) => {
                        let (x, y) = (pixel as u32 % views.width, pixel as u32 / views.width);
                        let named = &among.ids[among.groups
                            [bins::tile_of(x, y, views.width, tile)]
                        .1
                        .clone()];
                        first_crossing(named.iter().map(|&i| (i, tris[i as usize])), r)
                    }
                    None => first_crossing((0..tris.len() as u32).zip(tris.iter().copied()), r),
                };
                ending(first.map(|(_, at)| at[0]), from)
            })
            .collect())
    }
}

/// The view's candidates for tiles of `tile` and error scale `scale`, made once per view for both
/// scales and shared by its methods and its audit.
fn view_bins(at: &Prepared<Triangle>, tile: u32, scale: SideError) -> Arc<Among> {
    let mut made = at.ready.binned.lock().unwrap_or_else(|e| e.into_inner());
    made.retain(|b| b.0 == at.view);
    if !made.iter().any(|b| b.1 == tile) {
        let (w, h) = (at.scene.views.width, at.scene.views.height);
        let (tris, _) = &at.ready.triangles;
        for (s, among) in bins::bins(at.camera, w, h, tile, tris)
            .among(w, h)
            .into_pairs()
        {
            made.push((at.view, tile, s, Arc::new(among)));
        }
    }
    made.iter()
        .find(|b| (b.1, b.2) == (tile, scale))
        .expect("made above")
        .3
        .clone()
}
