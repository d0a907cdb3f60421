//! A walk through a generated mesh (a Kuhn grid, a jittered grid, an edge fan; near the origin or far
//! from it): an exit-face method steps from tetrahedron to tetrahedron; the answer is how the walk
//! ended, judged against the exact walk, which is itself checked against the brute-force first hit.

#[cfg(feature = "cli")]
pub mod cli;
pub mod engine;
pub mod kit;
#[cfg(feature = "internals")]
mod report;

use super::count::{CountError, Counted, Counts, Prepared, Scene, first_difference, inconsistent};
use super::wrong::Class;
use super::{ExitFace, Family, Scale, Summed, Verdict};
use crate::backend::{Backend, BackendError, CPU, Pending};
use crate::cases::{CaseError, field_error, number, vec3};
use crate::exact::hit::first_hit;
use crate::mesh::Mesh;
use crate::registry::{METHODS, Method, USER_WGSL, reference};
use crate::scenes::Generated;
use crate::scenes::from_bytes::WalkCase;
use crate::tet::Ray;
use crate::walk::{Outcome, OutcomeKind, PerKind, Walk, default_max_steps, locate, same_result};
use glam::Vec3;
use serde_json::{Map, Value};
use std::sync::Arc;

/// Walks through generated meshes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Walks;

/// Largest grid or fan size of a walk case (a Kuhn grid of this size has 6·64³ tetrahedra).
pub(crate) const MAX_WALK_SIZE: u32 = 64;

/// The stress rows of walks: the lattice-tie scenes, each a generated mesh of a size at an offset
/// along (1, 1, 1), half of its rays aimed exactly through vertices and edges.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum WalkScene {
    Kuhn,
    /// The Kuhn grid moved by 2^20.
    Kuhn1048576,
    Jitter,
    /// The jittered grid moved by 2^16.
    Jitter65536,
    Fan,
}

crate::choice!(WalkScene {
    Kuhn => "kuhn",
    Kuhn1048576 => "kuhn-1048576",
    Jitter => "jitter",
    Jitter65536 => "jitter-65536",
    Fan => "fan",
});

impl WalkScene {
    /// Its mesh, size and offset.
    pub(crate) fn mesh(self) -> (Generated, u32, f32) {
        match self {
            WalkScene::Kuhn => (Generated::Kuhn, 8, 0.0),
            WalkScene::Kuhn1048576 => (Generated::Kuhn, 8, 1_048_576.0),
            WalkScene::Jitter => (Generated::Jitter, 8, 0.0),
            WalkScene::Jitter65536 => (Generated::Jitter, 8, 65536.0),
            WalkScene::Fan => (Generated::Fan, 4, 0.0),
        }
    }
}

/// A stress row of walks, as its report's row writes it.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct WalkRow {
    pub(crate) scene: WalkScene,
}

/// Which scenes a stress run of walks walks.
#[derive(Clone, Debug, serde::Serialize)]
pub struct WalkRows {
    pub(crate) scenes: Vec<WalkScene>,
}

impl Default for WalkRows {
    fn default() -> Self {
        WalkRows {
            scenes: <WalkScene as crate::choice::Choice>::ALL.to_vec(),
        }
    }
}

/// One method's walks on one row: judged, and wrong by the kind of their ending.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct WalkTally {
    pub(crate) judged: u64,
    #[serde(flatten)]
    pub(crate) wrong: PerKind<u64>,
}

impl Summed for WalkTally {
    fn add(&mut self, o: &Self) {
        self.judged += o.judged;
        (0..5).for_each(|k| self.wrong.0[k] += o.wrong.0[k]);
    }
}

/// A walk case's mesh with its bounds, built once per thread.
pub(crate) struct GeneratedMesh {
    pub(crate) mesh: Arc<Mesh>,
    pub(crate) bounds: (Vec3, Vec3),
}

type Cached = ((Generated, u32, u32, i32), Arc<GeneratedMesh>);

thread_local! {
    /// Generated meshes by (kind, size, offset): walk cases (fuzz inputs above all) use few of them.
    static MESHES: std::cell::RefCell<Vec<Cached>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// A walk case's mesh (kind, size, offset, then scaled by 2^`scale`), built once per thread and
/// kept (the last 64).
pub(crate) fn generated(
    mesh: Generated,
    size: u32,
    offset: f32,
    scale: i32,
) -> Result<Arc<GeneratedMesh>, CaseError> {
    let key = (mesh, size, offset.to_bits(), scale);
    if let Some(m) = MESHES.with(|c| {
        c.borrow()
            .iter()
            .find(|(k, _)| *k == key)
            .map(|(_, m)| m.clone())
    }) {
        return Ok(m);
    }
    let built = crate::scenes::generated_mesh(mesh, size, Vec3::splat(offset), 1)
        .and_then(|m| if scale == 0 { Ok(m) } else { m.scaled(scale) })
        .map_err(|e| CaseError::Mesh(e.to_string()))?;
    let bounds = crate::mesh::bounds(&built.points);
    let m = Arc::new(GeneratedMesh {
        mesh: Arc::new(built),
        bounds,
    });
    MESHES.with(|c| {
        let mut c = c.borrow_mut();
        if c.len() == 64 {
            c.remove(0);
        }
        c.push((key, m.clone()));
    });
    Ok(m)
}

/// A walk case's mesh and the tetrahedron holding its origin.
fn placed(w: &WalkCase) -> Result<(Arc<Mesh>, u32), CaseError> {
    let m = generated(w.mesh, w.size, w.offset, w.scale)?;
    let start = locate(&m.mesh, w.ray().org, 0).map_err(|e| CaseError::Outside(e.to_string()))?;
    Ok((m.mesh.clone(), start))
}

/// The exact answer to a walk case.
pub struct WalkTruth {
    pub(crate) mesh: Arc<Mesh>,
    /// The `exact` walk.
    pub(crate) exact: Walk,
    /// Whether the exact walk agrees with the brute-force first hit: it stops on a constrained face
    /// where the ray (perturbed as the walk perturbs it) crosses one, and leaves the mesh where it
    /// crosses none.
    pub(crate) consistent: bool,
}

impl Family for Walks {
    const NAME: &'static str = "walk";
    const FUZZ_TARGET: &'static str = "walk";
    const STRESS_CASES: usize = 10_000;
    const BYTES_PER_CASE: u128 = 384;

    type Method = Method;
    type Case = WalkCase;
    type Truth = WalkTruth;
    type Answer = Walk;
    type Rows = WalkRows;
    type Row = WalkRow;
    type RowFacts = ();
    type Tally = WalkTally;

    fn methods() -> &'static [Method] {
        METHODS
    }

    fn owns(obj: &Map<String, Value>) -> bool {
        obj.contains_key("mesh")
    }

    fn take_case(obj: &mut Map<String, Value>) -> Result<WalkCase, CaseError> {
        let mut field = |k: &'static str| obj.remove(k).ok_or(CaseError::Missing(k));
        let mesh = field("mesh")?;
        let mesh = mesh
            .as_str()
            .and_then(<Generated as crate::choice::Choice>::from_name)
            .ok_or_else(|| field_error("mesh", format!("{mesh} is not kuhn, jitter or fan")))?;
        let size = field("size")?;
        let size = size
            .as_u64()
            .filter(|s| (1..=MAX_WALK_SIZE as u64).contains(s))
            .ok_or_else(|| field_error("size", format!("{size} is not in 1..={MAX_WALK_SIZE}")))?
            as u32;
        let offset = number(&field("offset")?).map_err(|e| field_error("offset", e))?;
        let org = vec3(&field("org")?).map_err(|e| field_error("org", e))?;
        let dir = vec3(&field("dir")?).map_err(|e| field_error("dir", e))?;
        let scale = match obj.remove("scale") {
            None => 0,
            Some(e) => e
                .as_i64()
                .filter(|e| (-300..=300).contains(e))
                .ok_or_else(|| {
                    field_error(
                        "scale",
                        format!("{e} is not a power-of-two exponent in -300..=300"),
                    )
                })? as i32,
        };
        if dir == Vec3::ZERO {
            return Err(crate::exact::ExactError::ZeroDirection.into());
        }
        Ok(WalkCase {
            mesh,
            size,
            offset,
            scale,
            org: org.to_array(),
            dir: dir.to_array(),
        })
    }

    fn case_json(w: &WalkCase) -> Map<String, Value> {
        match serde_json::to_value(w) {
            Ok(Value::Object(m)) => m,
            _ => Map::new(),
        }
    }

    fn ray(w: &WalkCase) -> Ray {
        w.ray()
    }

    fn with_ray(w: &WalkCase, ray: Ray) -> WalkCase {
        WalkCase {
            org: ray.org.to_array(),
            dir: ray.dir.to_array(),
            ..*w
        }
    }

    const COMMAND: Option<&'static str> = Some("exit");

    /// The mesh's points times 2^`s.points` (its `scale`), the origin too, the direction at
    /// 2^`s.direction`; `None` where a point or the ray would round.
    fn scaled(w: &WalkCase, s: Scale) -> Option<WalkCase> {
        let exact = crate::tet::times_two_to;
        let org = w.org.map(|x| exact(x, s.points));
        let dir = w.dir.map(|x| exact(x, s.direction));
        Some(WalkCase {
            scale: w.scale.checked_add(s.points)?,
            org: [org[0]?, org[1]?, org[2]?],
            dir: [dir[0]?, dir[1]?, dir[2]?],
            ..*w
        })
    }

    /// The mesh's offset, then the origin and direction.
    fn numbers(w: &WalkCase) -> Vec<f32> {
        [&[w.offset][..], &w.org, &w.dir].concat()
    }

    fn with_numbers(w: &WalkCase, n: &[f32]) -> Option<WalkCase> {
        Some(WalkCase {
            offset: n[0],
            org: [n[1], n[2], n[3]],
            dir: [n[4], n[5], n[6]],
            ..*w
        })
    }

    /// The same mesh, smaller (the generators' smallest is 3 for grids, 1 for the fan).
    fn smaller(w: &WalkCase) -> Vec<WalkCase> {
        (1..w.size).map(|size| WalkCase { size, ..*w }).collect()
    }

    fn truth(w: &WalkCase) -> Result<WalkTruth, CaseError> {
        let (mesh, start) = placed(w)?;
        let exact = CPU
            .walks(
                reference(),
                &CPU.mesh(&mesh),
                &[w.ray()],
                start,
                default_max_steps(&mesh),
            )
            .map_err(|e| CaseError::Mesh(e.to_string()))?[0];
        let consistent = matches!(
            (exact.outcome, first_hit(&mesh, &w.ray())),
            (Outcome::LeftMesh { .. }, None) | (Outcome::Hit { .. }, Some(_))
        );
        Ok(WalkTruth {
            mesh,
            exact,
            consistent,
        })
    }

    /// Right where the walk ends where the exact walk does ([`same_result`]), and the exact walk agrees
    /// with the brute-force first hit.
    fn verdict(w: &WalkCase, t: &WalkTruth, got: &Walk) -> Verdict {
        if t.consistent && same_result(&t.mesh, &w.ray(), got, &t.exact) {
            Verdict::Right
        } else {
            Verdict::Wrong(got.outcome.kind())
        }
    }

    fn right_answers(_: &WalkCase, t: &WalkTruth) -> String {
        format!("the exact walk {}", Self::describe(&t.exact))
    }

    /// Each case's mesh built once per batch; the walks of one mesh in one call.
    fn answers(
        backend: &Backend,
        m: &Method,
        cases: &[WalkCase],
    ) -> Result<Vec<Walk>, BackendError> {
        let mut out: Vec<Option<Walk>> = vec![None; cases.len()];
        let mut left: Vec<usize> = (0..cases.len()).collect();
        while let Some(&first) = left.first() {
            let key = |w: &WalkCase| (w.mesh, w.size, w.offset.to_bits(), w.scale);
            let (same, rest): (Vec<usize>, Vec<usize>) = left
                .iter()
                .partition(|&&i| key(&cases[i]) == key(&cases[first]));
            left = rest;
            let w = &cases[first];
            let m3 = generated(w.mesh, w.size, w.offset, w.scale)
                .map_err(|e| BackendError::Case(e.to_string()))?;
            let mesh = &m3.mesh;
            let rays = same
                .iter()
                .map(|&i| {
                    let r = cases[i].ray();
                    let start =
                        locate(mesh, r.org, 0).map_err(|e| BackendError::Case(e.to_string()))?;
                    Ok((r, start))
                })
                .collect::<Result<Vec<_>, BackendError>>()?;
            let walks = backend
                .walks_from(m, &backend.mesh(mesh), &rays, default_max_steps(mesh))?
                .walks;
            for (i, walk) in same.into_iter().zip(walks) {
                out[i] = Some(walk);
            }
        }
        Ok(out.into_iter().flatten().collect())
    }

    fn kind(w: &Walk) -> OutcomeKind {
        w.outcome.kind()
    }

    fn answer_json(w: &Walk) -> Value {
        serde_json::to_value(w.outcome).unwrap_or(Value::Null)
    }

    fn parse_answer(v: &Value, _: &WalkCase) -> Result<Walk, String> {
        let outcome: Outcome = serde_json::from_value(v.clone()).map_err(|e| e.to_string())?;
        Ok(Walk { outcome, steps: 0 })
    }

    const GIVEN: bool = false;
    fn given(_: &Map<String, Value>, _: &WalkCase) -> Result<Walk, String> {
        Err("judge answers tetrahedron, triangle and octree cell cases, not walk cases".into())
    }

    fn describe(w: &Walk) -> String {
        match w.outcome {
            Outcome::Hit { tet, face } => {
                format!("stops on constrained face {face} of tetrahedron {tet}")
            }
            Outcome::LeftMesh { tet, face } => {
                format!("leaves the mesh through face {face} of tetrahedron {tet}")
            }
            Outcome::NoExitFace { tet } => format!("finds no exit face in tetrahedron {tet}"),
            Outcome::Cycle { tet, period } => {
                format!("endless walk: a cycle of period {period} through tetrahedron {tet}")
            }
            Outcome::StepLimit { tet } => {
                format!("endless walk: step limit reached in tetrahedron {tet}")
            }
        }
    }

    fn user_wgsl() -> Option<&'static Method> {
        Some(&USER_WGSL)
    }

    fn rows(rows: &WalkRows) -> Vec<WalkRow> {
        rows.scenes.iter().map(|&scene| WalkRow { scene }).collect()
    }

    fn row_name(row: &WalkRow) -> String {
        crate::choice::Choice::name(row.scene).to_string()
    }

    /// Ray `i` of the scene's rays ([`crate::scenes::ray`]: odd ones aimed exactly through vertices
    /// and edges); `None` where its origin is outside the mesh.
    fn case(_: &WalkRows, row: WalkRow, seed: u64, i: usize) -> Option<(WalkCase, WalkTruth)> {
        let (mesh, size, offset) = row.scene.mesh();
        let m = generated(mesh, size, offset, 0).ok()?;
        let mut r = crate::scenes::row_rng(seed, row.scene as u64, i);
        let ray = crate::scenes::ray(mesh, m.bounds, Vec3::splat(offset), i % 2 == 1, &mut r);
        let w = WalkCase {
            mesh,
            size,
            offset,
            scale: 0,
            org: ray.org.to_array(),
            dir: ray.dir.to_array(),
        };
        let t = Self::truth(&w).ok()?;
        Some((w, t))
    }

    fn tally(t: &mut WalkTally, w: &WalkCase, truth: &WalkTruth, got: &Walk) {
        t.judged += 1;
        if let Verdict::Wrong(k) = Self::verdict(w, truth, got) {
            t.wrong.0[k.code() as usize] += 1;
        }
    }

    fn judged(_: &(), t: &WalkTally) -> u64 {
        t.judged
    }

    fn wrong(t: &WalkTally) -> u64 {
        t.wrong.0.iter().sum()
    }

    fn arbitrary(u: &mut arbitrary::Unstructured) -> Option<WalkCase> {
        crate::scenes::from_bytes::walk_case(u).ok()
    }

    /// Walks cost more than single cases: an eighth of the property campaign's inputs.
    fn kit_properties(properties: usize) -> usize {
        properties / 8
    }

    /// A walk is many steps, each an exit face: a fifth of a row's cases.
    fn kit_row_cases(cases: usize) -> usize {
        (cases / 5).max(1)
    }
}

/// One method's numbers per image: the totals over the views counted.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct PerImage {
    pub wrong: f64,
    pub(crate) by_kind: PerKind<f64>,
    pub(crate) wrong_face_adjacent: f64,
    pub(crate) wrong_face_elsewhere: f64,
    /// Tetrahedra traversed per image (Φ).
    pub(crate) tetrahedra: f64,
}

/// One method's counts over a count's views (seed 000 Table 4's row).
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct MethodCount {
    /// Wrong rays, summed over views.
    pub wrong_total: u64,
    /// Wrong rays by the kind of their ending, summed over views.
    pub wrong: PerKind<u64>,
    /// Wrong faces whose triangle touches a triangle holding the exact hit point.
    pub wrong_face_adjacent: u64,
    /// Wrong faces elsewhere.
    pub wrong_face_elsewhere: u64,
    /// Tetrahedra traversed, summed over views.
    pub steps: u64,
    /// The same numbers per image.
    pub per_image: PerImage,
}

impl Counts for MethodCount {
    fn kinds(&self) -> [u64; 5] {
        self.wrong.0
    }

    fn wrong_total(&self) -> u64 {
        self.wrong_total
    }

    fn add_wrong(&mut self, kind: OutcomeKind, class: Option<Class>) {
        self.wrong.0[kind.code() as usize] += 1;
        self.wrong_total += 1;
        match class {
            Some(Class::Adjacent) => self.wrong_face_adjacent += 1,
            Some(Class::Elsewhere) => self.wrong_face_elsewhere += 1,
            None => {}
        }
    }

    fn add_steps(&mut self, steps: u64) {
        self.steps += steps;
    }

    fn add(&mut self, m: &Self) {
        self.wrong_total += m.wrong_total;
        (0..5).for_each(|k| self.wrong.0[k] += m.wrong.0[k]);
        self.wrong_face_adjacent += m.wrong_face_adjacent;
        self.wrong_face_elsewhere += m.wrong_face_elsewhere;
        self.steps += m.steps;
    }

    fn finish(&mut self, views: usize) {
        let v = views.max(1) as f64;
        self.per_image = PerImage {
            wrong: self.wrong_total as f64 / v,
            by_kind: PerKind(self.wrong.0.map(|n| n as f64 / v)),
            wrong_face_adjacent: self.wrong_face_adjacent as f64 / v,
            wrong_face_elsewhere: self.wrong_face_elsewhere as f64 / v,
            tetrahedra: self.steps as f64 / v,
        };
    }

    fn check(&self, at: &str, views: usize) -> Result<(), (String, String)> {
        let faces = self.wrong.0[OutcomeKind::Hit.code() as usize];
        if self.wrong_face_adjacent as u128 + self.wrong_face_elsewhere as u128 != faces as u128 {
            return inconsistent(
                format!("{at}.wrong_face_adjacent"),
                format!(
                    "{} adjacent and {} elsewhere, but {faces} wrong faces",
                    self.wrong_face_adjacent, self.wrong_face_elsewhere
                ),
            );
        }
        // The per-image figures are the totals' over the views, as `finish` makes them.
        let mut derived = self.clone();
        derived.finish(views);
        let got = serde_json::json!(self.per_image);
        let want = serde_json::json!(derived.per_image);
        if let Some((field, got, want)) = first_difference(&got, &want) {
            return inconsistent(
                format!("{at}.per_image.{field}"),
                format!("{got}, not {want}, its total over {views} views"),
            );
        }
        Ok(())
    }
}

/// What a walk count's report says of its scene.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct WalkFacts {
    pub(crate) tetrahedra: usize,
}

impl Counted for Walks {
    type CountSettings = ();
    type Ready = ();
    type SceneFacts = WalkFacts;
    type Counts = MethodCount;
    const EXACT: &'static str = "the exact walk";
    const DEFAULT_VIEWS: (usize, &'static str) = (160, "256x256");
    const COUNT_ALIASES: &'static [&'static str] = &[<ExitFace as Family>::NAME];

    fn reference_row() -> bool {
        true
    }

    fn prepare(_: &Scene, _: &(), _: &Backend, _: u32) -> Result<(), CountError> {
        Ok(())
    }

    fn facts(scene: &Scene, _: Option<&()>) -> WalkFacts {
        WalkFacts {
            tetrahedra: scene.loaded.mesh.tets.len(),
        }
    }

    fn answer_rays(at: &Prepared<Self>, m: &Method, rays: &[Ray]) -> Result<Vec<Walk>, CountError> {
        let scene = at.scene;
        Ok(at
            .backend
            .walks(m, &scene.on, rays, at.located, scene.max_steps)?)
    }

    fn answer_against<'a>(
        at: &'a Prepared<Self>,
        m: &'a Method,
        rays: &'a [Ray],
    ) -> Result<Option<Pending<'a>>, CountError> {
        let scene = at.scene;
        Ok(at
            .backend
            .walks_against(m, &scene.on, rays, at.located, scene.max_steps)?)
    }

    /// The full `exact` walk, which the reference (`certified`) follows step for step.
    fn audit(at: &Prepared<Self>, rays: &[Ray]) -> Result<Vec<Walk>, CountError> {
        Self::answer_rays(at, reference(), rays)
    }

    /// The same walk, step for step.
    fn agrees(_: &Mesh, _: &Ray, exact: &Walk, walked: &Walk) -> bool {
        exact == walked
    }

    fn walker(m: &Method) -> Option<&Method> {
        Some(m)
    }
}
