//! An octree cell's exit (seed 001): a closed axis-aligned box and a ray; the answer the face the ray
//! leaves through and the quarter of it (the neighbour among four), judged against every exact one.

#[cfg(feature = "cli")]
pub mod cli;
pub mod engine;
pub mod kit;
#[cfg(feature = "internals")]
mod report;

use super::count::{CountError, Counted, Counts, Prepared, Scene, per_image};
use super::wrong::Class;
use super::{Family, Said, Summed, Verdict, given_fields};
use crate::backend::{Backend, BackendError, OctreeOn, Pending};
use crate::cases::{BoxCase, CaseError, field_error, vec3};
use crate::choice::Choice;
use crate::exact::boxes::{BoxExit, box_exit};
use crate::mesh::surface::{SceneTriangles, both_sides, region_of, scene_triangles};
use crate::octree::cell::{FACE_NAMES, face_named, quarter_signs};
use crate::registry::{ByName, OCTREE_METHODS, OctreeMethod, TriangleMethod};
use crate::scenes::cells::{CellAim, CellPlace, case};
use crate::tet::Ray;
use crate::walk::octree::{OctreeWalk, walk_exact};
use crate::walk::{OutcomeKind, Walk};
use glam::Vec3;
use serde_json::{Map, Value, json};

/// Octree cells.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OctreeCells;

/// An exit face (seed 001's numbering) and the quarter of it as signs `[su, sv]`, or none.
pub(crate) type CellExit = Option<(u8, [i8; 2])>;

/// A stress row of octree cells: where the ray leaves the cell and where the cell is.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct CellRow {
    pub(crate) aim: CellAim,
    pub(crate) place: CellPlace,
}

/// What shapes a stress run of octree cells.
#[derive(Clone, Debug, serde::Serialize)]
pub struct CellRows {
    pub(crate) aims: Vec<CellAim>,
    pub(crate) places: Vec<CellPlace>,
    pub(crate) ulps: i32,
}

impl Default for CellRows {
    fn default() -> Self {
        CellRows {
            aims: CellAim::ALL.to_vec(),
            places: CellPlace::ALL.to_vec(),
            ulps: 4,
        }
    }
}

/// One method's counts on one row.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct CellTally {
    /// Cases whose line crosses the open cell (the others are not judged).
    pub(crate) judged: u64,
    /// A face through which the line does not leave, or the wrong quarter of one it does.
    pub(crate) wrong: u64,
    /// Of those, the right face but a wrong quarter (a wrong neighbour among four).
    pub(crate) wrong_quarter: u64,
    /// No exit face (eq. 8's 7).
    pub(crate) no_exit_face: u64,
}

impl Summed for CellTally {
    fn add(&mut self, o: &Self) {
        self.judged += o.judged;
        self.wrong += o.wrong;
        self.wrong_quarter += o.wrong_quarter;
        self.no_exit_face += o.no_exit_face;
    }
}

/// A cell's answer: `{"face": "-x"|"+x"|…, "quarter": [su, sv]}` (signs −1 or +1) or null.
pub(crate) fn cell_answer(v: &Value) -> Result<CellExit, String> {
    if v.is_null() {
        return Ok(None);
    }
    let face = v
        .get("face")
        .and_then(Value::as_str)
        .and_then(face_named)
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

/// The answer as [`BoxExit::right`] takes it.
fn as_judged(a: &CellExit) -> Option<(usize, [i8; 2])> {
    a.map(|(f, q)| (f as usize, q))
}

impl Family for OctreeCells {
    const NAME: &'static str = "octree";
    const FUZZ_TARGET: &'static str = "octree_cell";
    const BYTES_PER_CASE: u128 = 1024;

    type Method = OctreeMethod;
    type Case = BoxCase;
    type Truth = BoxExit;
    type Answer = CellExit;
    type Rows = CellRows;
    type Row = CellRow;
    type RowFacts = ();
    type Tally = CellTally;

    fn methods() -> &'static [OctreeMethod] {
        OCTREE_METHODS
    }

    fn owns(obj: &Map<String, Value>) -> bool {
        obj.contains_key("box")
    }

    /// `box` must be closed and not flat.
    fn take_case(obj: &mut Map<String, Value>) -> Result<BoxCase, CaseError> {
        let mut field = |k: &'static str| obj.remove(k).ok_or(CaseError::Missing(k));
        let b = field("box")?;
        let corners = b.as_array().filter(|a| a.len() == 2).ok_or_else(|| {
            field_error("box", "must hold two corners, [[lx, ly, lz], [hx, hy, hz]]")
        })?;
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
            return Err(crate::exact::ExactError::ZeroDirection.into());
        }
        Ok(BoxCase { lo, hi, org, dir })
    }

    fn case_json(b: &BoxCase) -> Map<String, Value> {
        match json!({
            "box": [b.lo.to_array(), b.hi.to_array()],
            "org": b.org.to_array(),
            "dir": b.dir.to_array(),
        }) {
            Value::Object(m) => m,
            _ => Map::new(),
        }
    }

    fn ray(b: &BoxCase) -> Ray {
        b.ray()
    }

    fn with_ray(b: &BoxCase, ray: Ray) -> BoxCase {
        BoxCase {
            org: ray.org,
            dir: ray.dir,
            ..*b
        }
    }

    const COMMAND: Option<&'static str> = Some("box-exit");

    /// The box's corners, then the origin and direction.
    fn numbers(b: &BoxCase) -> Vec<f32> {
        super::points_numbers([&b.lo, &b.hi, &b.org, &b.dir])
    }

    fn with_numbers(_: &BoxCase, n: &[f32]) -> Option<BoxCase> {
        let p = super::numbers_points(n);
        Some(BoxCase {
            lo: p[0],
            hi: p[1],
            org: p[2],
            dir: p[3],
        })
    }

    fn truth(b: &BoxCase) -> Result<BoxExit, CaseError> {
        Ok(box_exit(b.lo, b.hi, &b.ray())?)
    }

    fn verdict(_: &BoxCase, x: &BoxExit, a: &CellExit) -> Verdict {
        match x.right(as_judged(a)) {
            None => Verdict::NotJudged,
            Some(true) => Verdict::Right,
            Some(false) => Verdict::Wrong(Self::kind(a)),
        }
    }

    /// A cell's case: its line may miss the cell.
    fn said(c: &BoxCase, x: &BoxExit, a: &CellExit, _: f64) -> Said {
        Said {
            correct: Self::verdict(c, x, a).correct(),
            cell: true,
            ..Said::default()
        }
    }

    fn right_answers(_: &BoxCase, x: &BoxExit) -> String {
        x.faces
            .iter()
            .zip(&x.quarters)
            .map(|(f, q)| format!("exit face {} quarters {q:?}", FACE_NAMES[*f]))
            .collect::<Vec<_>>()
            .join("; ")
    }

    fn answers(
        backend: &Backend,
        m: &OctreeMethod,
        cases: &[BoxCase],
    ) -> Result<Vec<CellExit>, BackendError> {
        Ok(backend
            .box_exits(m, cases)?
            .into_iter()
            .map(|a| a.map(|(f, q)| (f as u8, quarter_signs(q))))
            .collect())
    }

    fn kind(a: &CellExit) -> OutcomeKind {
        match a {
            Some(_) => OutcomeKind::Hit,
            None => OutcomeKind::NoExitFace,
        }
    }

    fn answer_json(a: &CellExit) -> Value {
        a.map_or(
            Value::Null,
            |(f, q)| json!({"face": FACE_NAMES[f as usize], "quarter": q}),
        )
    }

    fn parse_answer(v: &Value, _: &BoxCase) -> Result<CellExit, String> {
        cell_answer(v)
    }

    /// `{"face": "-x"|…|null, "quarter": [su, sv]}`.
    fn given(obj: &Map<String, Value>, _: &BoxCase) -> Result<CellExit, String> {
        let o = given_fields(
            obj,
            "an octree cell case (box)",
            &["face", "quarter"],
            &["face"],
        )?;
        let quarter = o.get("quarter").cloned().unwrap_or(Value::Null);
        match &o["face"] {
            Value::Null if quarter.is_null() => Ok(None),
            Value::Null => Err("\"quarter\" given without a face".into()),
            f => cell_answer(&json!({"face": f, "quarter": quarter})),
        }
    }

    /// 48 bytes: the lower and upper corners, the origin and the direction (12 f32).
    fn case_record(c: &BoxCase) -> Option<Vec<u8>> {
        Some(
            [c.lo, c.hi, c.org, c.dir]
                .iter()
                .flat_map(|v| v.to_array())
                .flat_map(f32::to_le_bytes)
                .collect(),
        )
    }

    /// 12 bytes: the exit face (i32: 0..5 for +y, +x, -y, -x, +z, -z, or -1 for none) and the
    /// quarter (two i32, each -1 or 1; anything for none).
    const ANSWER_RECORD: usize = 12;

    fn answer_record(b: &[u8], _: &BoxCase) -> Result<CellExit, String> {
        let i = |k: usize| i32::from_le_bytes([b[4 * k], b[4 * k + 1], b[4 * k + 2], b[4 * k + 3]]);
        match (i(0), i(1), i(2)) {
            (-1, _, _) => Ok(None),
            (f @ 0..=5, u @ (-1 | 1), v @ (-1 | 1)) => Ok(Some((f as u8, [u as i8, v as i8]))),
            (f @ 0..=5, u, v) => Err(format!(
                "answered face {f} with quarter [{u}, {v}], not each -1 or 1"
            )),
            (f, _, _) => Err(format!("answered face {f}, not 0..5 or -1 (none)")),
        }
    }

    fn describe(a: &CellExit) -> String {
        match a {
            Some((f, q)) => format!("exit face {} quarter {q:?}", FACE_NAMES[*f as usize]),
            None => "no exit face".into(),
        }
    }

    fn rows(r: &CellRows) -> Vec<CellRow> {
        let mut out = Vec::new();
        for &aim in &r.aims {
            for &place in &r.places {
                out.push(CellRow { aim, place });
            }
        }
        out
    }

    fn row_name(r: &CellRow) -> String {
        format!("{}-{}", r.aim.name(), r.place.name())
    }

    fn case(r: &CellRows, row: CellRow, seed: u64, i: usize) -> Option<(BoxCase, BoxExit)> {
        let key = (row.aim as u64) << 8 | row.place as u64;
        let mut rng = crate::scenes::row_rng(seed, key, i);
        let (lo, hi, ray) = case(row.aim, row.place, r.ulps, &mut rng);
        let c = BoxCase {
            lo,
            hi,
            org: ray.org,
            dir: ray.dir,
        };
        let x = box_exit(lo, hi, &ray).ok()?;
        Some((c, x))
    }

    fn tally(t: &mut CellTally, _: &BoxCase, x: &BoxExit, a: &CellExit) {
        let Some(right) = x.right(as_judged(a)) else {
            return;
        };
        t.judged += 1;
        if right {
            return;
        }
        t.wrong += 1;
        t.no_exit_face += a.is_none() as u64;
        t.wrong_quarter += a.is_some_and(|(f, _)| x.faces.contains(&(f as usize))) as u64;
    }

    fn judged(_: &(), t: &CellTally) -> u64 {
        t.judged
    }

    fn wrong(t: &CellTally) -> u64 {
        t.wrong
    }

    fn arbitrary(u: &mut arbitrary::Unstructured) -> Option<BoxCase> {
        let (lo, hi, ray) = crate::scenes::from_bytes::cell_case(u).ok()?;
        Some(BoxCase {
            lo,
            hi,
            org: ray.org,
            dir: ray.dir,
        })
    }
}

/// One octree method's counts over a count's views.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct OctreeCount {
    pub wrong_total: u64,
    /// Wrong rays by the kind of their ending ([`OutcomeKind::ALL`] order): wrong triangle, false
    /// miss, no exit face, cycle, step limit.
    pub wrong: [u64; 5],
    pub(crate) wrong_per_image: f64,
    /// Cells visited, summed over rays (Φ).
    pub cells: u64,
}

impl Counts for OctreeCount {
    fn kinds(&self) -> [u64; 5] {
        self.wrong
    }

    fn wrong_total(&self) -> u64 {
        self.wrong_total
    }

    fn add_wrong(&mut self, kind: OutcomeKind, _: Option<Class>) {
        self.wrong_total += 1;
        self.wrong[kind.code() as usize] += 1;
    }

    fn add_steps(&mut self, cells: u64) {
        self.cells += cells;
    }

    fn add(&mut self, o: &Self) {
        self.wrong_total += o.wrong_total;
        (0..5).for_each(|k| self.wrong[k] += o.wrong[k]);
        self.cells += o.cells;
    }

    fn finish(&mut self, views: usize) {
        self.wrong_per_image = self.wrong_total as f64 / views.max(1) as f64;
    }

    fn check(&self, at: &str, views: usize) -> Result<(), (String, String)> {
        per_image(at, self.wrong_per_image, self.wrong_total, views)
    }
}

/// What an octree count sets: the octree, and the ray–triangle method testing each leaf's triangles.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct OctreeCountSettings {
    pub(crate) octree: crate::octree::Settings,
    pub(crate) triangle_method: ByName<TriangleMethod>,
}

/// What an octree count's report says of its scene.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct OctreeFacts {
    /// The scene's triangles (its constrained faces facing the cameras).
    pub(crate) triangles: usize,
    pub(crate) leaves: usize,
    pub(crate) unconstrained_leaves: usize,
}

/// The scene's triangles facing a camera's region, their octree, made ready on the backend, and the
/// cells a walk of it may visit at most.
pub struct Built {
    region: Vec<bool>,
    triangles: SceneTriangles,
    octree: crate::octree::Octree,
    on: OctreeOn,
    cap: u32,
}

/// An octree walk's ending in the mesh's terms (a hit on the face its triangle came from).
fn walked(w: &OctreeWalk, from: &[(u32, u8)]) -> Walk {
    Walk {
        outcome: w.end.outcome(from),
        steps: w.cells,
    }
}

impl Counted for OctreeCells {
    type CountSettings = OctreeCountSettings;
    type Ready = Built;
    type SceneFacts = OctreeFacts;
    type Counts = OctreeCount;
    const EXACT: &'static str = "the exact octree walk";
    const DEFAULT_VIEWS: (usize, &'static str) = (16, "256x256");

    fn check(s: &OctreeCountSettings) -> Result<(), String> {
        s.octree.check().map_err(|e| {
            format!(
                "--depth {} --capacity {}: {e}",
                s.octree.depth, s.octree.capacity
            )
        })
    }

    fn prepare(
        scene: &Scene,
        s: &OctreeCountSettings,
        backend: &Backend,
        located: u32,
    ) -> Result<Built, CountError> {
        let region = region_of(&scene.loaded.mesh, located);
        let triangles = scene_triangles(&scene.loaded.mesh, &region);
        let octree = crate::octree::Octree::build(&triangles.0, s.octree)
            .map_err(|e| CountError::Octree(e.to_string()))?;
        let sides = both_sides(&scene.loaded.mesh, &triangles.1);
        let on = backend.octree(&octree, &triangles.0, &sides);
        Ok(Built {
            region,
            cap: crate::walk::octree::default_max_steps(&octree),
            triangles,
            octree,
            on,
        })
    }

    fn serves(ready: &Built, located: u32) -> bool {
        ready.region[located as usize]
    }

    fn facts(_: &Scene, ready: Option<&Built>) -> OctreeFacts {
        OctreeFacts {
            triangles: ready.map_or(0, |r| r.triangles.0.len()),
            leaves: ready.map_or(0, |r| r.octree.leaves.len()),
            unconstrained_leaves: ready.map_or(0, |r| r.octree.unconstrained_leaves),
        }
    }

    fn answer_rays(
        at: &Prepared<Self>,
        m: &OctreeMethod,
        rays: &[Ray],
    ) -> Result<Vec<Walk>, CountError> {
        let tri = at.settings.triangle_method.method();
        let ready = at.ready;
        let (tris, from) = &ready.triangles;
        let ends =
            at.backend
                .octree_walks(m, tri, &ready.octree, tris, &ready.on, rays, ready.cap)?;
        Ok(ends.iter().map(|w| walked(w, from)).collect())
    }

    fn answer_against<'a>(
        at: &'a Prepared<Self>,
        m: &'a OctreeMethod,
        rays: &'a [Ray],
    ) -> Result<Option<Pending<'a>>, CountError> {
        let ready = at.ready;
        let tri = at.settings.triangle_method.method();
        let pending = at.backend.octree_walks_against(
            m,
            tri,
            &ready.octree,
            &ready.on,
            rays,
            at.located,
            ready.cap,
        )?;
        Ok(pending.map(|p| p.map(|w| walked(&w, &ready.triangles.1))))
    }

    fn audit(at: &Prepared<Self>, rays: &[Ray]) -> Result<Vec<Walk>, CountError> {
        let ready = at.ready;
        let (tris, from) = &ready.triangles;
        Ok(rays
            .iter()
            .map(|r| walked(&walk_exact(&ready.octree, tris, r, ready.cap), from))
            .collect())
    }
}
