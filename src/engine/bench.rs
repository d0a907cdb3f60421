//! Speed (`tetwalk bench`): walk speed per method and backend on a scene's primary rays — rays and
//! tetrahedra per second end to end (upload, kernel, readback, and the CPU's walks of rays the GPU
//! flagged), and the GPU's kernel time alone where the adapter has timestamp queries; rays are made
//! before the clock starts, in batches of whole views, every backend walking the same batches in one
//! run (seed 004 Figure 5's ray–triangle packet speed is the triangle family's,
//! `crate::family::triangle::engine`).

use crate::backend::{Backend, BackendError, BackendKind, Ran, Traffic};
use crate::choice::Choice;
use crate::mesh::layout::Layout;
use crate::methods::Model;
use crate::registry::Named;
use crate::registry::{GpuVersion, Method};
use crate::scenes::Loaded;
use crate::scenes::camera::Views;
use crate::tet::Ray;
use crate::walk::layouts::{LayoutKind, Source};
use crate::walk::{default_max_steps, locate};
use rayon::prelude::*;
use std::time::Instant;

#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    #[error(transparent)]
    Backend(#[from] BackendError),
    #[error(
        "nothing to time: none of the {0} camera positions lies inside the mesh (a scene needs the box around the model that `tetwalk scene build` adds)"
    )]
    NoView(usize),
    #[error("nothing to time: no method runs on {0}")]
    NoMethod(String),
}

/// Whether pass `pass` of `passes` is timed: the first batch's first pass (of `repeat + 1`) warms up.
fn warm_done(pass: usize, passes: usize, repeat: usize) -> bool {
    passes == repeat || pass > 0
}

/// One method on one backend.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct BenchRow {
    pub method: String,
    /// `cells` (the mesh's cells: 80 bytes on the CPU, 64 on the GPU) or one of seed 003's layouts.
    pub layout: String,
    pub backend: BackendKind,
    pub rays: u64,
    /// Tetrahedra traversed.
    pub tetrahedra: u64,
    /// Wall-clock seconds from handing the rays over to having every walk back.
    pub(crate) seconds: f64,
    /// GPU kernel seconds (timestamp queries), where measured.
    pub kernel_seconds: Option<f64>,
    /// Rays the GPU flagged and the CPU walked.
    pub(crate) flagged: u64,
    /// On a GPU, bytes written to it and read back per ray walked (the pipeline measured on any
    /// adapter).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) bytes_written_per_ray: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) bytes_read_per_ray: Option<f64>,
    /// What the timed passes moved, summed (the figures per ray are made from it).
    #[serde(skip)]
    traffic: Option<Traffic>,
    /// Each timed batch's end-to-end speed, Mrays/s (a batch timed `repeat` times gives as many).
    #[serde(default)]
    pub(crate) samples: Vec<f64>,
    /// The samples' median and range.
    #[serde(default)]
    pub(crate) spread: Option<Spread>,
    /// Against a baseline run's same row (`--baseline`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) change: Option<Change>,
}

/// Median and range of a row's samples, Mrays/s.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Spread {
    pub(crate) median: f64,
    pub(crate) low: f64,
    pub(crate) high: f64,
    pub(crate) samples: usize,
}

impl Spread {
    pub(crate) fn of(samples: &[f64]) -> Option<Spread> {
        let mut s: Vec<f64> = samples.iter().copied().filter(|x| x.is_finite()).collect();
        s.sort_by(f64::total_cmp);
        let n = s.len();
        (n > 0).then(|| Spread {
            median: if n % 2 == 1 {
                s[n / 2]
            } else {
                (s[n / 2 - 1] + s[n / 2]) / 2.0
            },
            low: s[0],
            high: s[n - 1],
            samples: n,
        })
    }
}

fn one() -> usize {
    1
}

/// Changes of medians smaller than this are noise whatever the ranges (criterion's default threshold).
const NOISE: f64 = 0.02;

/// A row against the same row of a baseline run of the same settings, like with like: each batch's
/// speed (the median of its `repeat` timings) over the same batch's there — the same views, so the
/// spread between views does not hide a change. Faster or slower where every batch's ratio lies on
/// that side of 1 and their median more than `NOISE` from it, else within noise.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Change {
    pub(crate) baseline_median: f64,
    /// The median of the batches' ratios, now over the baseline.
    pub(crate) ratio: f64,
    /// The lowest and highest of the batches' ratios.
    #[serde(default)]
    pub(crate) ratio_range: (f64, f64),
    pub(crate) verdict: String,
}

/// Each batch's speed: the median of its `repeat` timings.
fn per_batch(samples: &[f64], repeat: usize) -> Vec<f64> {
    samples
        .chunks(repeat.max(1))
        .filter_map(|c| Spread::of(c).map(|s| s.median))
        .collect()
}

impl BenchReport {
    /// Why `baseline` cannot be compared with this run: the settings that make its batches other
    /// rays (scene, mesh, views, batch, order), each named with both values.
    pub(crate) fn differs_from(&self, baseline: &BenchReport) -> Option<String> {
        let mut d = Vec::new();
        let mut differ = |what: &str, now: String, then: String| {
            if now != then {
                d.push(format!("{what} {now} here, {then} there"));
            }
        };
        differ("scene", self.scene.clone(), baseline.scene.clone());
        differ(
            "tetrahedra",
            self.tetrahedra_in_mesh.to_string(),
            baseline.tetrahedra_in_mesh.to_string(),
        );
        differ(
            "views",
            format!("{:?}", self.views),
            format!("{:?}", baseline.views),
        );
        differ("batch", self.batch.to_string(), baseline.batch.to_string());
        differ(
            "hilbert",
            self.hilbert.to_string(),
            baseline.hilbert.to_string(),
        );
        (!d.is_empty()).then(|| d.join("; "))
    }

    /// Each row's change against the same method, layout and backend in `baseline` ([`Change`]);
    /// rows it lacks have none. How many rows were compared.
    pub(crate) fn compare(&mut self, baseline: &BenchReport) -> usize {
        let mut compared = 0;
        for r in &mut self.rows {
            let same = baseline
                .rows
                .iter()
                .find(|b| b.method == r.method && b.layout == r.layout && b.backend == r.backend);
            let (Some(b), Some(bs)) = (same, same.and_then(|b| b.spread)) else {
                r.change = None;
                continue;
            };
            let ratios: Vec<f64> = per_batch(&r.samples, self.repeat)
                .iter()
                .zip(per_batch(&b.samples, baseline.repeat))
                .map(|(now, then)| now / then)
                .collect();
            let Some(q) = Spread::of(&ratios) else {
                r.change = None;
                continue;
            };
            compared += 1;
            r.change = Some(Change {
                baseline_median: bs.median,
                ratio: q.median,
                ratio_range: (q.low, q.high),
                verdict: if q.low > 1.0 && q.median > 1.0 + NOISE {
                    "faster"
                } else if q.high < 1.0 && q.median < 1.0 - NOISE {
                    "slower"
                } else {
                    "within noise"
                }
                .to_string(),
            });
        }
        compared
    }
}

#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct BenchReport {
    pub(crate) scene: String,
    pub(crate) tetrahedra_in_mesh: usize,
    pub(crate) views: Views,
    /// Views whose camera lies inside the mesh (the others are skipped, as `count` skips them).
    pub views_timed: usize,
    /// Rays per batch handed to a backend at once.
    pub(crate) batch: usize,
    /// Each backend, with its adapter and driver for a GPU.
    pub(crate) backends: Vec<Ran>,
    /// Whether the mesh was put in Hilbert order first (seed 003 §3).
    pub(crate) hilbert: bool,
    /// Timings of each batch (`--repeat`): a row's samples are its batches' timings in turn.
    #[serde(default = "one")]
    pub(crate) repeat: usize,
    /// Whether `cpu-fma` ran on the processor's FMA instruction, or through `f32::mul_add` (no such
    /// instruction, or `TETWALK_NO_FMA=1`): the same answers, not the same speed.
    #[serde(default)]
    pub(crate) fma_instruction: bool,
    /// Whether `cpu` and `cpu-ftz` ran compiled for AVX2, or for SSE2 alone (no AVX2 here, or
    /// `TETWALK_NO_AVX2=1`): the same answers, not the same speed.
    #[serde(default)]
    pub(crate) avx2: bool,
    pub rows: Vec<BenchRow>,
}

/// Methods a backend can time: on a GPU, those with a GPU version (the others would time the CPU).
pub(crate) fn runs_on<'a>(methods: &[&'a Method], backend: &Backend) -> Vec<&'a Method> {
    methods
        .iter()
        .copied()
        .filter(|m| backend.kind() != BackendKind::Gpu || matches!(m.info.gpu, GpuVersion::Wgsl(_)))
        .collect()
}

/// What one row times: a method's walk over the mesh's cells, or over one of seed 003's layouts.
#[derive(Clone, Copy)]
enum Walker<'a> {
    Cells(&'a Method),
    Layout(&'a Method, LayoutKind),
}

/// Time every method on every backend over the views' primary rays, `batch` rays at most at once
/// (whole views; one view when a view is larger), each batch `repeat` times (every timing a sample);
/// with `layouts`, also the methods that walk seed 003's layouts over Tet32, Tet20 and Tet16.
/// With `hilbert`, the mesh is put in Hilbert order first (seed 003 §3).
#[allow(clippy::too_many_arguments)]
pub fn run(
    scene: &Loaded,
    hilbert: bool,
    views: &Views,
    methods: &[&Method],
    backends: &[&Backend],
    (batch, layouts, repeat): (usize, bool, usize),
    tick: &dyn Fn(),
) -> Result<BenchReport, BenchError> {
    let sorted = hilbert.then(|| crate::mesh::reorder::hilbert_sorted(&scene.mesh));
    let mesh = sorted.as_ref().unwrap_or(&scene.mesh);
    let (lo, hi) = crate::mesh::bounds(&mesh.points);
    let max = default_max_steps(mesh);
    let layout = layouts.then(|| Layout::build(mesh));
    let mut rows: Vec<BenchRow> = Vec::new();
    // (row, backend, what) in the order they are timed.
    let mut plan: Vec<(usize, usize, Walker)> = Vec::new();
    for (bi, b) in backends.iter().enumerate() {
        let on = runs_on(methods, b);
        if on.is_empty() {
            return Err(BenchError::NoMethod(b.describe()));
        }
        let mut walkers: Vec<Walker> = on.iter().map(|m| Walker::Cells(m)).collect();
        if layout.is_some() {
            for m in on.iter().filter(|m| m.layout_walk(Model::Plain).is_some()) {
                walkers.extend(LayoutKind::ALL.iter().map(|k| Walker::Layout(m, *k)));
            }
        }
        for w in walkers {
            let (m, layout) = match w {
                Walker::Cells(m) => (m, "cells"),
                Walker::Layout(m, k) => (m, k.name()),
            };
            plan.push((rows.len(), bi, w));
            rows.push(BenchRow {
                method: m.name().to_string(),
                layout: layout.to_string(),
                backend: b.kind(),
                rays: 0,
                tetrahedra: 0,
                seconds: 0.0,
                kernel_seconds: b.for_method(m).measures_kernels().then_some(0.0),
                flagged: 0,
                bytes_written_per_ray: None,
                bytes_read_per_ray: None,
                traffic: None,
                samples: Vec::new(),
                spread: None,
                change: None,
            });
        }
    }
    let meshes: Vec<_> = backends.iter().map(|b| b.mesh(mesh)).collect();
    let layouts_on: Vec<_> = backends
        .iter()
        .map(|b| layout.as_ref().map(|l| b.layout(l, &mesh.points)))
        .collect();
    let per_view = views.width as usize * views.height as usize;
    let views_per_batch = (batch / per_view.max(1)).max(1);
    let (mut start, mut timed, mut warm) = (0, 0, false);
    let mut v = 0;
    while v < views.views {
        // The next batch of whole views, rays made before the clock starts.
        let mut rays: Vec<(Ray, u32)> = Vec::with_capacity(views_per_batch * per_view);
        while v < views.views && rays.len() + per_view <= (views_per_batch * per_view) {
            let cam = views.camera(lo, hi, v);
            v += 1;
            tick();
            let Ok(located) = locate(mesh, cam.eye, start) else {
                continue;
            };
            start = located;
            timed += 1;
            rays.extend(views.rays(&cam).into_iter().map(|r| (r, located)));
        }
        if rays.is_empty() {
            continue;
        }
        let sourced: Vec<(Ray, Source)> = layout.as_ref().map_or(Vec::new(), |l| {
            rays.iter().map(|(r, s)| (*r, Source::new(l, *s))).collect()
        });
        // One pass per walker; the first batch once more before, untimed, to compile every pipeline
        // and size every buffer.
        let passes = if warm { repeat } else { repeat + 1 };
        warm = true;
        for pass in 0..passes {
            for &(row, b, w) in &plan {
                let before = backends[b].traffic();
                let t0 = Instant::now();
                // The clock stops when the walks are back; counting their steps is not timed.
                let (seconds, steps, kernel, flagged) = match w {
                    Walker::Cells(m) => {
                        let done = backends[b].walks_from(m, &meshes[b], &rays, max)?;
                        let seconds = t0.elapsed().as_secs_f64();
                        let steps = done.walks.par_iter().map(|w| w.steps as u64).sum::<u64>();
                        (seconds, steps, done.kernel_seconds, done.flagged as u64)
                    }
                    Walker::Layout(m, kind) => {
                        let Some(on) = &layouts_on[b] else { continue };
                        let done = backends[b].layout_walks(m, kind, on, &sourced, max)?;
                        let seconds = t0.elapsed().as_secs_f64();
                        let steps = done.walks.par_iter().map(|w| w.1 as u64).sum::<u64>();
                        (seconds, steps, done.kernel_seconds, 0)
                    }
                };
                if !warm_done(pass, passes, repeat) {
                    continue;
                }
                let r = &mut rows[row];
                r.samples.push(rays.len() as f64 / seconds.max(1e-12) / 1e6);
                r.seconds += seconds;
                r.kernel_seconds = r.kernel_seconds.zip(kernel).map(|(a, k)| a + k);
                r.rays += rays.len() as u64;
                r.tetrahedra += steps;
                r.flagged += flagged;
                if let Some(t) = backends[b].traffic().zip(before).map(|(a, b)| a.since(b)) {
                    r.traffic = Some(r.traffic.map_or(t, |s| s.plus(&t)));
                }
            }
        }
    }
    if timed == 0 {
        return Err(BenchError::NoView(views.views));
    }
    for r in &mut rows {
        r.spread = Spread::of(&r.samples);
        let per_ray = |bytes: u64| bytes as f64 / r.rays.max(1) as f64;
        r.bytes_written_per_ray = r.traffic.map(|t| per_ray(t.written));
        r.bytes_read_per_ray = r.traffic.map(|t| per_ray(t.read));
    }
    Ok(BenchReport {
        scene: scene.name.clone(),
        tetrahedra_in_mesh: mesh.tets.len(),
        views: *views,
        views_timed: timed,
        batch: views_per_batch * per_view,
        backends: backends.iter().map(|b| b.ran()).collect(),
        hilbert,
        repeat,
        fma_instruction: crate::fpenv::has_fma(),
        avx2: crate::fpenv::has_avx2(),
        rows,
    })
}

/// Seed 000 Table 5's queries: `n_rays` random rays stabbing each of `n_tets` random well-shaped
/// tetrahedra, each with its exact entry face (as a walk has it).
pub fn table5_queries(
    n_tets: usize,
    n_rays: usize,
    seed: u64,
) -> (Vec<crate::tet::Tet>, Vec<crate::methods::Query>) {
    use crate::scenes::tets::{TetShape, stabbing_ray, tet};
    let mut r = crate::scenes::rng(seed);
    let tets: Vec<crate::tet::Tet> = (0..n_tets)
        .map(|_| tet(TetShape::Well, 1.0, &mut r))
        .collect();
    let mut queries: Vec<crate::methods::Query> = Vec::with_capacity(n_tets * n_rays);
    for (i, t) in tets.iter().enumerate() {
        for _ in 0..n_rays {
            let ray = stabbing_ray(t, &mut r);
            let entry = crate::exact::classify(t, &ray)
                .ok()
                .and_then(|c| c.entry.first());
            queries.push((i as u32, ray, entry));
        }
    }
    (tets, queries)
}
