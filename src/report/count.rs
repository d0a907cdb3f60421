//! `tetwalk count`: for a scene, how many rays of an image each method gets wrong in f32 (seed 000
//! Table 4), judged exactly against the `exact` walk, with traversed tetrahedra per image (Φ) and speed.

use crate::backend::{Backend, BackendError};
use crate::mesh::Mesh;
use crate::registry::{Method, reference};
use crate::scenes::camera::Views;
use crate::walk::{OutcomeKind, default_max_steps, judge, locate};
use rayon::prelude::*;
use std::time::Instant;

/// What is counted, and how the rays are made.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Settings {
    pub scene: String,
    #[serde(flatten)]
    pub views: Views,
}

/// Why a count could not be made.
#[derive(Debug, thiserror::Error)]
pub enum CountError {
    #[error(transparent)]
    Backend(#[from] BackendError),
    #[error(
        "no view could be counted: none of the {0} camera positions lies inside the mesh (a scene needs the box around the model that `tetwalk scene build` adds)"
    )]
    NoView(usize),
}

/// One method's totals over all views.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct MethodCount {
    pub method: String,
    /// Wrong rays by the kind of their ending ([`OutcomeKind::ALL`] order), summed over views.
    pub wrong: [u64; 5],
    /// Tetrahedra traversed, summed over views (Φ per image is this over the views).
    pub steps: u64,
    /// Wall-clock seconds spent walking.
    pub seconds: f64,
}

impl MethodCount {
    pub fn wrong_total(&self) -> u64 {
        self.wrong.iter().sum()
    }
}

#[derive(Clone, Debug, serde::Serialize)]
pub struct CountReport {
    pub settings: Settings,
    /// The backend the methods ran on (the `exact` reference always runs on the CPU).
    pub backend: String,
    pub tetrahedra: usize,
    /// Rays judged (all pixels of all views whose camera is inside the mesh).
    pub rays: u64,
    pub views_counted: usize,
    /// The `exact` walk, first, then every method.
    pub methods: Vec<MethodCount>,
}

/// Count wrong rays per method over the views; `tick` is called once per view. Memory holds one view's
/// rays and walks at a time.
pub fn run(
    mesh: &Mesh,
    s: &Settings,
    methods: &[&Method],
    backend: &Backend,
    tick: &(dyn Fn() + Sync),
) -> Result<CountReport, CountError> {
    let exact = reference();
    let max = default_max_steps(mesh);
    let (lo, hi) = crate::mesh::bounds(&mesh.points);
    let on = backend.mesh(mesh);
    let mut totals: Vec<MethodCount> = std::iter::once(exact)
        .chain(methods.iter().copied())
        .map(|m| MethodCount {
            method: m.name.to_string(),
            ..Default::default()
        })
        .collect();
    let (mut rays_counted, mut views_counted) = (0u64, 0usize);
    let mut start = 0;
    for v in 0..s.views.views {
        let cam = s.views.camera(lo, hi, v);
        tick();
        let Ok(located) = locate(mesh, cam.eye, start) else {
            continue;
        };
        start = located;
        views_counted += 1;
        let rays = s.views.rays(&cam);
        rays_counted += rays.len() as u64;
        let t0 = Instant::now();
        let reference = backend.walks(exact, &on, &rays, located, max)?;
        totals[0].seconds += t0.elapsed().as_secs_f64();
        totals[0].steps += reference.iter().map(|w| w.steps as u64).sum::<u64>();
        for (m, total) in methods.iter().zip(&mut totals[1..]) {
            let t0 = Instant::now();
            let walks = backend.walks(m, &on, &rays, located, max)?;
            total.seconds += t0.elapsed().as_secs_f64();
            let (wrong, steps) = rays
                .par_iter()
                .zip(&walks)
                .zip(&reference)
                .map(|((r, w), re)| {
                    let mut k = [0u64; 5];
                    if let Some(kind) = judge(mesh, r, w, re) {
                        k[kind.code() as usize] = 1;
                    }
                    (k, w.steps as u64)
                })
                .reduce(
                    || ([0; 5], 0),
                    |(a, sa), (b, sb)| (std::array::from_fn(|i| a[i] + b[i]), sa + sb),
                );
            (0..5).for_each(|i| total.wrong[i] += wrong[i]);
            total.steps += steps;
        }
    }
    if views_counted == 0 {
        return Err(CountError::NoView(s.views.views));
    }
    Ok(CountReport {
        settings: s.clone(),
        backend: backend.describe(),
        tetrahedra: mesh.tets.len(),
        rays: rays_counted,
        views_counted,
        methods: totals,
    })
}

impl CountReport {
    /// The table: per method, wrong rays per image by kind, Φ per image, and speed.
    pub fn markdown(&self) -> String {
        let s = &self.settings.views;
        let views = self.views_counted.max(1) as f64;
        let mut out = format!(
            "scene {} ({} tetrahedra), {} views of {}x{}, backend {}, seed {}; per image, averaged over views\n\n",
            self.settings.scene,
            self.tetrahedra,
            self.views_counted,
            s.width,
            s.height,
            self.backend,
            s.seed
        );
        out += &format!(
            "| method | wrong rays | {} | Φ (tetrahedra) | Mrays/s |\n",
            OutcomeKind::ALL.map(|k| k.wrong()).join(" | ")
        );
        out += &format!(
            "|---|---|{}---|---|\n",
            "---|".repeat(OutcomeKind::ALL.len())
        );
        for m in &self.methods {
            let kinds: Vec<String> = m
                .wrong
                .iter()
                .map(|&w| format!("{:.3}", w as f64 / views))
                .collect();
            out += &format!(
                "| {} | {:.3} | {} | {:.0} | {:.2} |\n",
                m.method,
                m.wrong_total() as f64 / views,
                kinds.join(" | "),
                m.steps as f64 / views,
                self.rays as f64 / m.seconds.max(1e-9) / 1e6
            );
        }
        out
    }
}
