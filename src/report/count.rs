//! `tetwalk count`: for a scene, how many rays of an image each method gets wrong in f32 (seed 000
//! Table 4), judged exactly against the `exact` walk, with traversed tetrahedra per image (Φ) and speed.

use crate::backend::{Backend, BackendError};
use crate::mesh::Mesh;
use crate::registry::{Method, reference};
use crate::report::wrong::{Class, Seen, WrongRay};
use crate::scenes::camera::Views;
use crate::tet::Ray;
use crate::walk::{OutcomeKind, Walk, default_max_steps, judge, locate};
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
    #[error("writing the dump: {0}")]
    Dump(std::io::Error),
    #[error(
        "no view could be counted: none of the {0} camera positions lies inside the mesh (a scene needs the box around the model that `tetwalk scene build` adds)"
    )]
    NoView(usize),
}

/// Numbers per kind of wrong ending, in [`OutcomeKind::ALL`] order; written as a map labelled by
/// [`OutcomeKind::wrong_key`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PerKind<T>(pub [T; 5]);

impl<T: serde::Serialize> serde::Serialize for PerKind<T> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut m = s.serialize_map(Some(5))?;
        for (k, v) in OutcomeKind::ALL.iter().zip(&self.0) {
            m.serialize_entry(k.wrong_key(), v)?;
        }
        m.end()
    }
}

/// One method's numbers per image: the totals over the views counted.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct PerImage {
    pub wrong: f64,
    pub by_kind: PerKind<f64>,
    pub wrong_face_adjacent: f64,
    pub wrong_face_elsewhere: f64,
    /// Tetrahedra traversed per image (Φ).
    pub tetrahedra: f64,
}

/// One method's totals over all views.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct MethodCount {
    pub method: String,
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
    /// Wall-clock seconds spent walking.
    pub seconds: f64,
    /// Rays walked per second, in millions.
    pub mrays_per_second: f64,
}

/// One view's wrong rays for one method (`walks` beside the `exact` walks `reference`, pixel `i` at
/// column `i % width`), each described; wrong rays are few, so each is described where it is found.
#[allow(clippy::too_many_arguments)]
pub fn wrong_rays(
    mesh: &Mesh,
    seen: &Seen,
    width: u32,
    rays: &[Ray],
    walks: &[Walk],
    reference: &[Walk],
    start: u32,
    max_steps: u32,
) -> Vec<WrongRay> {
    let wrong: Vec<usize> = (0..rays.len())
        .into_par_iter()
        .filter(|&i| judge(mesh, &rays[i], &walks[i], &reference[i]).is_some())
        .collect();
    wrong
        .par_iter()
        .map(|&i| {
            let seen = Seen {
                pixel: [i as u32 % width, i as u32 / width],
                ..*seen
            };
            WrongRay::of(
                mesh,
                &seen,
                &rays[i],
                &walks[i],
                &reference[i],
                start,
                max_steps,
            )
        })
        .collect()
}

impl MethodCount {
    /// Count one wrong ray.
    pub fn add(&mut self, kind: OutcomeKind, class: Option<Class>) {
        self.wrong.0[kind.code() as usize] += 1;
        self.wrong_total += 1;
        match class {
            Some(Class::Adjacent) => self.wrong_face_adjacent += 1,
            Some(Class::Elsewhere) => self.wrong_face_elsewhere += 1,
            None => {}
        }
    }

    /// Fill in the per-image numbers and the speed, once every view is counted.
    pub fn finish(&mut self, views: usize, rays: u64) {
        let v = views.max(1) as f64;
        self.per_image = PerImage {
            wrong: self.wrong_total as f64 / v,
            by_kind: PerKind(self.wrong.0.map(|n| n as f64 / v)),
            wrong_face_adjacent: self.wrong_face_adjacent as f64 / v,
            wrong_face_elsewhere: self.wrong_face_elsewhere as f64 / v,
            tetrahedra: self.steps as f64 / v,
        };
        self.mrays_per_second = rays as f64 / self.seconds.max(1e-9) / 1e6;
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

/// Where each wrong ray goes besides the tallies (`count --dump`).
pub type Sink<'a> = dyn FnMut(&WrongRay) -> std::io::Result<()> + 'a;

/// Count wrong rays per method over the views; `tick` is called once per view, and `sink` sees every
/// wrong ray written out ([`WrongRay`]). Memory holds one view's rays and walks at a time.
pub fn run(
    mesh: &Mesh,
    s: &Settings,
    methods: &[&Method],
    backend: &Backend,
    tick: &(dyn Fn() + Sync),
    mut sink: Option<&mut Sink>,
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
            total.steps += walks.iter().map(|w| w.steps as u64).sum::<u64>();
            let seen = Seen {
                scene: &s.scene,
                view: v,
                pixel: [0, 0],
                method: m,
                backend: backend.for_method(m).kind(),
            };
            let described = wrong_rays(
                mesh,
                &seen,
                s.views.width,
                &rays,
                &walks,
                &reference,
                located,
                max,
            );
            for d in &described {
                let kind = d.kind().expect("a wrong ray has a kind");
                total.add(kind, d.class);
                if let Some(sink) = sink.as_mut() {
                    sink(d).map_err(CountError::Dump)?;
                }
            }
        }
    }
    if views_counted == 0 {
        return Err(CountError::NoView(s.views.views));
    }
    for t in &mut totals {
        t.finish(views_counted, rays_counted);
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
    /// The table: per method, wrong rays per image by kind (wrong faces also split into adjacent and
    /// elsewhere), Φ per image, and speed; then the totals.
    pub fn markdown(&self) -> String {
        let s = &self.settings.views;
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
            "| method | wrong rays | {} | wrong face adjacent | wrong face elsewhere | Φ (tetrahedra) | Mrays/s |\n",
            OutcomeKind::ALL.map(|k| k.wrong()).join(" | ")
        );
        out += &format!(
            "|---|---|{}---|---|---|---|\n",
            "---|".repeat(OutcomeKind::ALL.len())
        );
        for m in &self.methods {
            let p = &m.per_image;
            let kinds: Vec<String> = p.by_kind.0.iter().map(|w| format!("{w:.3}")).collect();
            out += &format!(
                "| {} | {:.3} | {} | {:.3} | {:.3} | {:.0} | {:.2} |\n",
                m.method,
                p.wrong,
                kinds.join(" | "),
                p.wrong_face_adjacent,
                p.wrong_face_elsewhere,
                p.tetrahedra,
                m.mrays_per_second
            );
        }
        out += &format!(
            "\ntotals over {} rays: {}\n",
            self.rays,
            self.methods
                .iter()
                .map(|m| format!("{} {}", m.method, m.wrong_total))
                .collect::<Vec<_>>()
                .join(", ")
        );
        out
    }
}
