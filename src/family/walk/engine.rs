//! The walk family's runs beyond its `Family` (the engine layer in its folder): `tetwalk walk`'s
//! rays through a generated mesh, each method's walk judged step by step against the `exact` walk
//! (also under the 12 orientation-preserving relabellings), and a scene's view walked pixel by pixel
//! for `render`.

use crate::backend::{Backend, BackendError};
use crate::engine::view::{Frame, ViewError, located_view};
use crate::family::Summed;
use crate::mesh::layout::Layout;
use crate::mesh::{HULL, Mesh, MeshError};
use crate::methods::Model;
use crate::registry::{Method, Named, reference};
use crate::scenes::camera::Views;
use crate::tet::{EVEN_PERMUTATIONS, Ray};
use crate::walk::layouts::{LayoutKind, Source};
use crate::walk::{Outcome, OutcomeKind, Walk, default_max_steps, judge, locate, same_result};
use rayon::prelude::*;

/// Why a walk run stopped.
#[derive(Debug, thiserror::Error)]
pub enum WalkRunError {
    #[error(transparent)]
    Backend(#[from] BackendError),
    #[error(transparent)]
    Mesh(#[from] MeshError),
}

/// How the walks are judged: every step on the CPU under an arithmetic model, or (a `--wgsl`
/// function's walks) by their endings, walked on the GPU.
#[derive(Clone, Copy)]
pub enum Walker<'a> {
    /// Every step judged by the oracle, so that "diverged" is measured.
    Checked(Model),
    /// Walked on this GPU backend, judged by their endings ("diverged" unmeasured).
    Gpu(&'a Backend),
}

/// One method's walks: how they ended ([`OutcomeKind::ALL`] order), how many ended elsewhere than the
/// `exact` walk, how many took a step outside the exact exit set, and the steps.
#[derive(Default, Clone, Copy, Debug, serde::Serialize)]
pub struct MethodWalks {
    pub rays: u64,
    pub kinds: [u64; 5],
    pub wrong: u64,
    pub diverged: u64,
    pub steps: u64,
}

impl Summed for MethodWalks {
    fn add(&mut self, t: &MethodWalks) {
        self.rays += t.rays;
        self.wrong += t.wrong;
        self.diverged += t.diverged;
        self.steps += t.steps;
        (0..5).for_each(|k| self.kinds[k] += t.kinds[k]);
    }
}

/// One method's row: its walks, and the compact layout it walked over (if it did).
#[derive(serde::Serialize)]
pub struct MethodRow {
    pub method: String,
    pub layout: Option<LayoutKind>,
    #[serde(flatten)]
    pub tally: MethodWalks,
}

/// One method under the 12 relabellings: wrong results and cycles for each, the identity first.
#[derive(serde::Serialize)]
pub struct Relabelled {
    pub method: String,
    pub wrong: Vec<u64>,
    pub cycles: Vec<u64>,
}

/// Every method's walks over one mesh's rays: the rays starting outside it (skipped), and one row per
/// method, in the order asked.
pub struct MethodWalksTable {
    pub outside: usize,
    pub rows: Vec<MethodRow>,
}

/// `tetwalk walk`'s report (its JSON): the mesh, the rays, and each method's row.
#[derive(serde::Serialize)]
pub struct WalkReport {
    pub mesh: crate::scenes::Generated,
    pub size: u32,
    pub offset: f32,
    pub tetrahedra: usize,
    pub rays: usize,
    pub outside: usize,
    pub seed: u64,
    pub backend: crate::backend::BackendKind,
    pub methods: Vec<MethodRow>,
    /// With `--relabel all`.
    pub relabellings: Option<Vec<Relabelled>>,
}

/// Walk `rays` through `mesh` with each method (over `layout` where the method can), each walk
/// judged against the `exact` one.
pub fn walk_table(
    mesh: &Mesh,
    rays: &[Ray],
    methods: &[&'static Method],
    walker: Walker,
    layout: Option<(LayoutKind, &Layout)>,
) -> Result<MethodWalksTable, WalkRunError> {
    let (per_ray, model) = match walker {
        Walker::Checked(model) => (per_ray(mesh, rays, methods, model, layout, true), model),
        Walker::Gpu(backend) => (gpu_per_ray(backend, mesh, rays, methods)?, Model::Plain),
    };
    let rows = methods
        .iter()
        .enumerate()
        .map(|(i, m)| {
            let mut tally = MethodWalks::default();
            per_ray.iter().flatten().for_each(|t| tally.add(&t[i]));
            MethodRow {
                method: m.name().into(),
                layout: layout
                    .map(|(kind, _)| kind)
                    .filter(|_| m.layout_walk(model).is_some()),
                tally,
            }
        })
        .collect();
    Ok(MethodWalksTable {
        outside: per_ray.iter().filter(|r| r.is_none()).count(),
        rows,
    })
}

/// Per ray (none when its origin is outside the mesh), each method's tally: checked walks (every step
/// judged, so that "diverged" is measured) or plain ones.
fn per_ray(
    mesh: &Mesh,
    rays: &[Ray],
    methods: &[&'static Method],
    model: Model,
    layout: Option<(LayoutKind, &Layout)>,
    checked: bool,
) -> Vec<Option<Vec<MethodWalks>>> {
    let max = default_max_steps(mesh);
    let exact = reference();
    rays.par_iter()
        .map(|ray| {
            let start = locate(mesh, ray.org, 0).ok()?;
            let reference = exact.walk(Model::Plain)(mesh, ray, start, max);
            let tallies = methods
                .iter()
                .map(|m| {
                    let (w, div) = match layout.zip(m.layout_walk(model)) {
                        Some(((kind, layout), walk)) => {
                            let (end, steps) = walk(
                                kind,
                                layout,
                                &mesh.points,
                                ray,
                                &Source::new(layout, start),
                                max,
                            );
                            (
                                Walk {
                                    outcome: end.to_outcome(mesh),
                                    steps,
                                },
                                None,
                            )
                        }
                        None if checked => m.walk_checked(model)(mesh, ray, start, max),
                        None => (m.walk(model)(mesh, ray, start, max), None),
                    };
                    tally(mesh, ray, &w, &reference, div.is_some())
                })
                .collect();
            Some(tallies)
        })
        .collect()
}

/// One ray's tally: how walk `w` ended, whether wrongly (against the `exact` walk), whether it
/// diverged.
fn tally(mesh: &Mesh, ray: &Ray, w: &Walk, exact: &Walk, diverged: bool) -> MethodWalks {
    let mut t = MethodWalks {
        rays: 1,
        steps: w.steps as u64,
        wrong: !same_result(mesh, ray, w, exact) as u64,
        diverged: diverged as u64,
        ..MethodWalks::default()
    };
    t.kinds[w.outcome.kind().code() as usize] = 1;
    t
}

/// Per ray (none when its origin is outside the mesh), each method's tally from walks on the GPU
/// (`--wgsl`), judged by their endings against the `exact` walk on the CPU ("diverged" unmeasured).
fn gpu_per_ray(
    backend: &Backend,
    mesh: &Mesh,
    rays: &[Ray],
    methods: &[&'static Method],
) -> Result<Vec<Option<Vec<MethodWalks>>>, BackendError> {
    let max = default_max_steps(mesh);
    let starts: Vec<Option<u32>> = rays
        .par_iter()
        .map(|r| locate(mesh, r.org, 0).ok())
        .collect();
    let asked: Vec<(Ray, u32)> = rays
        .iter()
        .zip(&starts)
        .filter_map(|(r, s)| Some((*r, (*s)?)))
        .collect();
    let on = backend.mesh(mesh);
    let mut walks = Vec::new();
    for m in std::iter::once(&reference()).chain(methods) {
        walks.push(backend.walks_from(m, &on, &asked, max)?.walks);
    }
    let mut k = 0;
    Ok(starts
        .iter()
        .map(|s| {
            s.map(|_| {
                let (ray, _) = asked[k];
                let exact = &walks[0][k];
                let t = walks[1..]
                    .iter()
                    .map(|w| tally(mesh, &ray, &w[k], exact, false))
                    .collect();
                k += 1;
                t
            })
        })
        .collect())
}

/// Every method's wrong results and cycles under each of the 12 orientation-preserving relabellings
/// ([`EVEN_PERMUTATIONS`], the identity first).
pub fn relabellings(
    mesh: &Mesh,
    rays: &[Ray],
    methods: &[&'static Method],
    model: Model,
) -> Result<Vec<Relabelled>, MeshError> {
    // Per method its wrong results, then its cycles.
    let measure = |k: usize| -> Result<Vec<u64>, MeshError> {
        let relabelled = mesh.relabelled(EVEN_PERMUTATIONS[k])?;
        let mut n = vec![0; 2 * methods.len()];
        for t in per_ray(&relabelled, rays, methods, model, None, false)
            .iter()
            .flatten()
        {
            for (i, t) in t.iter().enumerate() {
                n[2 * i] += t.wrong;
                n[2 * i + 1] += t.kinds[OutcomeKind::Cycle.code() as usize];
            }
        }
        Ok(n)
    };
    let all = crate::engine::under_labellings(measure(0)?, EVEN_PERMUTATIONS.len(), measure)?;
    Ok(methods
        .iter()
        .zip(all.chunks(2))
        .map(|(m, n)| Relabelled {
            method: m.name().into(),
            wrong: n[0].clone(),
            cycles: n[1].clone(),
        })
        .collect())
}

/// View `index` of `views` (placed as `tetwalk count` places them) walked by the exact walk and by
/// `methods` on `backend`, each method's walks judged against the exact ones, and the exact hits
/// shaded: what `render shaded`, `failures` and `heat` draw.
pub fn frame(
    mesh: &Mesh,
    views: &Views,
    index: usize,
    methods: &[&Method],
    backend: &Backend,
) -> Result<Frame, ViewError> {
    let (cam, start) = located_view(mesh, views, index)?;
    let max = default_max_steps(mesh);
    let rays = views.rays(&cam);
    let on = backend.mesh(mesh);
    let exact = backend.walks(reference(), &on, &rays, start, max)?;
    let mut wrong = Vec::new();
    for m in methods {
        let walks = backend.walks(m, &on, &rays, start, max)?;
        let w: Vec<Option<OutcomeKind>> = rays
            .par_iter()
            .zip(&walks)
            .zip(&exact)
            .map(|((r, w), re)| judge(mesh, r, w, re))
            .collect();
        wrong.push((m.name().to_string(), w));
    }
    let shade = rays
        .iter()
        .zip(&exact)
        .map(|(r, w)| match w.outcome {
            Outcome::Hit { tet, face } => {
                let [a, b, c] = mesh
                    .face(tet, face as usize)
                    .map(|i| mesh.points[i as usize]);
                let n = (b - a).cross(c - a).normalize_or_zero();
                let s = (n.dot(r.dir.normalize()).abs() * 205.0 + 50.0) as u8;
                (s, mesh.neighbors[tet as usize][face as usize] == HULL)
            }
            _ => (0, false),
        })
        .collect();
    Ok(Frame {
        width: views.width,
        height: views.height,
        exact,
        wrong,
        shade,
    })
}
