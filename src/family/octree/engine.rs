//! The octree family's engine beyond its `Family` (a file of the engine's layer in the family's
//! folder): the fuzz target that walks seed 001's octree (`octree_walk`), and what it finds; the
//! cells a scene's view visits per pixel (`render octree-heat`).

use super::OctreeCells;
use crate::engine::found::{Failure, Found, FoundError, cpu_backends};
use crate::engine::fuzz::held;
use crate::engine::view::{ViewError, located_view};
use crate::family::{Family, Triangle, Verdict};
use crate::mesh::Mesh;
use crate::methods::Model;
use crate::registry::{HitFn, Named, OctreeMethod};
use crate::scenes::camera::Views;
use crate::tet::{Ray, Tri};
use rayon::prelude::*;

/// The `octree_walk` fuzz target's finding on the bytes it was given: [`octree_walk_find`] on the
/// closed mesh and ray they decode to (nothing where they decode to none).
pub fn octree_walk(bytes: &[u8]) -> Result<Option<Found<OctreeCells>>, FoundError> {
    match crate::scenes::from_bytes::hit_case(&mut arbitrary::Unstructured::new(bytes)) {
        Ok((mesh, ray)) => octree_walk_find(&mesh, &ray),
        Err(_) => Ok(None),
    }
}

/// The octree over a fuzz case's closed mesh: deep and fine, so that rays meet many cells.
pub(crate) const FUZZ_OCTREE: crate::octree::Settings = crate::octree::Settings {
    depth: 6,
    capacity: 1,
};

/// What a fuzz run finds walking `ray` through seed 001's octree over `tris` ([`FUZZ_OCTREE`]) with
/// each octree method [`held`] on the CPU, plain, fused and flushed, each leaf's triangles tested with `mt`: the
/// first cell whose exit face or quarter the method chose wrongly, filed as that cell's box case (the
/// exact reference's walk lists no choices). A walk that cycles or reaches the step limit without a
/// wrong cell (its wrong choice was where the line only touches a cell, which no answer is judged on)
/// is [`FoundError::EndlessWalk`].
pub(crate) fn octree_walk_find(
    tris: &[Tri],
    ray: &Ray,
) -> Result<Option<Found<OctreeCells>>, FoundError> {
    use crate::cases::BoxCase;
    use crate::octree::cell::quarter_signs;
    use crate::walk::octree::End;
    let o = crate::octree::Octree::build(tris, FUZZ_OCTREE).map_err(|e| FoundError::Field {
        field: "tris",
        why: e.to_string(),
    })?;
    let hit = crate::family::by_name::<Triangle>("mt")?.hit(crate::methods::Model::Plain);
    let cap = crate::walk::octree::default_max_steps(&o);
    for (m, _) in held::<OctreeCells>()? {
        for b in cpu_backends() {
            let Some(model) = b.kind().model() else {
                continue;
            };
            let (w, steps) = m.walk_traced(model)(&o, tris, hit, ray, cap);
            for (cell, exit) in steps {
                let [lo, hi] = o.boxes[cell as usize];
                let case = BoxCase {
                    lo,
                    hi,
                    org: ray.org,
                    dir: ray.dir,
                };
                let x = OctreeCells::truth(&case)?;
                let answer = exit.map(|(f, q)| (f as u8, quarter_signs(q)));
                if let Verdict::Wrong(_) = OctreeCells::verdict(&case, &x, &answer) {
                    let f = Failure::of(m, b, answer);
                    return Ok(Some(Found::of(case, f)));
                }
            }
            if matches!(w.end, End::Cycle { .. } | End::StepLimit { .. }) {
                return Err(FoundError::EndlessWalk(format!(
                    "{} on {:?}: {:?}",
                    m.name(),
                    b.ran().kind,
                    w.end
                )));
            }
        }
    }
    Ok(None)
}

/// Seed 001's octree cells traversed per pixel (row-major) of view `index` by octree method `method`
/// (each leaf's triangles tested with `hit`), the octree built as `settings` says over the scene's
/// constrained faces facing the camera: what `render octree-heat` draws.
pub fn cells_per_pixel(
    mesh: &Mesh,
    views: &Views,
    index: usize,
    method: &OctreeMethod,
    hit: HitFn,
    settings: crate::octree::Settings,
) -> Result<Vec<u32>, ViewError> {
    let (cam, start) = located_view(mesh, views, index)?;
    let region = crate::mesh::surface::region_of(mesh, start);
    let (tris, _) = crate::mesh::surface::scene_triangles(mesh, &region);
    let octree = crate::octree::Octree::build(&tris, settings)
        .map_err(|e| ViewError::Octree(e.to_string()))?;
    let cap = crate::walk::octree::default_max_steps(&octree);
    let walk = method.walk(Model::Plain);
    Ok(views
        .rays(&cam)
        .par_iter()
        .map(|r| walk(&octree, &tris, hit, r, cap).cells)
        .collect())
}
