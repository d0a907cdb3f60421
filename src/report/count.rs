//! `tetwalk count`: for a scene, how many rays of an image each method gets wrong in f32 (seed 000
//! Table 4), judged exactly against the `exact` walk, with traversed tetrahedra per image (Φ) and speed.

use crate::mesh::Mesh;
use crate::methods::{Method, by_name};
use crate::tet::Ray;
use crate::walk::{Walk, default_max_steps, locate, same_result};
use glam::{Mat3, Quat, Vec3};
use rand::RngExt;
use rayon::prelude::*;
use std::time::Instant;

/// What is counted, and how the rays are made.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Settings {
    pub scene: String,
    pub views: usize,
    pub width: u32,
    pub height: u32,
    pub seed: u64,
    /// Vertical field of view, degrees.
    pub fov_deg: f32,
}

/// The kinds of wrong ray, in table order.
pub const KINDS: [&str; 5] = [
    "wrong face",
    "false miss",
    "no exit face",
    "cycle",
    "step limit",
];

/// One method's totals over all views.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct MethodCount {
    pub method: String,
    /// Wrong rays by kind ([`KINDS`]), summed over views.
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

/// Which kind of wrong `w` is, or `None` when it is right.
pub fn judge(mesh: &Mesh, ray: &Ray, w: &Walk, reference: &Walk) -> Option<usize> {
    if same_result(mesh, ray, w, reference) {
        return None;
    }
    // A wrong hit is a wrong face, a wrong miss a false miss: KINDS follows Outcome's order.
    Some(w.outcome.index())
}

/// A pinhole camera at `eye` looking at `target`.
#[derive(Clone, Copy, Debug)]
pub struct Camera {
    pub eye: Vec3,
    forward: Vec3,
    right: Vec3,
    up: Vec3,
}

impl Camera {
    pub fn look_at(eye: Vec3, target: Vec3, fov_deg: f32, aspect: f32) -> Camera {
        let forward = (target - eye).normalize();
        let up0 = if forward.y.abs() > 0.99 {
            Vec3::Z
        } else {
            Vec3::Y
        };
        let right = forward.cross(up0).normalize();
        let up = right.cross(forward);
        let h = (fov_deg.to_radians() * 0.5).tan();
        Camera {
            eye,
            forward,
            right: right * h * aspect,
            up: up * h,
        }
    }

    /// The primary ray through the centre of pixel `(x, y)`, in f32.
    pub fn ray(&self, x: u32, y: u32, w: u32, h: u32) -> Ray {
        let sx = 2.0 * (x as f32 + 0.5) / w as f32 - 1.0;
        let sy = 1.0 - 2.0 * (y as f32 + 0.5) / h as f32;
        Ray {
            org: self.eye,
            dir: self.forward + self.right * sx + self.up * sy,
        }
    }
}

/// View `i` of `n`: Fibonacci points on a sphere (rotated by the seed) at twice the model's radius from
/// its centre, looking at it. The model is taken to fill the middle third of the mesh's bounding box, as
/// [`crate::scenes::build::boxed`] makes it.
pub fn view(
    mesh_lo: Vec3,
    mesh_hi: Vec3,
    i: usize,
    n: usize,
    seed: u64,
    fov: f32,
    aspect: f32,
) -> Camera {
    let mut r = crate::scenes::rng(seed);
    let q = Quat::from_xyzw(
        r.random_range(-1.0..1.0),
        r.random_range(-1.0..1.0),
        r.random_range(-1.0..1.0),
        1.0,
    );
    let rot = Mat3::from_quat(q.normalize());
    let c = (mesh_lo + mesh_hi) * 0.5;
    let radius = (mesh_hi - mesh_lo).min_element() / 6.0;
    let y = 1.0 - 2.0 * (i as f32 + 0.5) / n as f32;
    let rho = (1.0 - y * y).max(0.0).sqrt();
    let phi = i as f32 * std::f32::consts::PI * (3.0 - 5f32.sqrt());
    let dir = rot * Vec3::new(rho * phi.cos(), y, rho * phi.sin());
    Camera::look_at(c + dir * (2.0 * radius), c, fov, aspect)
}

/// Where the methods' walks run: given a method and one view's rays (all from the tetrahedron
/// `start`), a backend returns each ray's walk. Judging is shared and stays on the CPU.
pub trait Backend: Sync {
    /// Name, adapter and driver, for the report.
    fn describe(&self) -> String;
    fn walks(
        &self,
        mesh: &Mesh,
        method: &Method,
        rays: &[Ray],
        start: u32,
        max_steps: u32,
    ) -> Result<Vec<Walk>, String>;
}

/// The CPU, both cores (rayon), plain f32 or as a GPU compiles it (`fma`).
pub struct Cpu {
    pub fma: bool,
}

impl Backend for Cpu {
    fn describe(&self) -> String {
        if self.fma {
            "cpu-fma".into()
        } else {
            "cpu".into()
        }
    }

    fn walks(
        &self,
        mesh: &Mesh,
        method: &Method,
        rays: &[Ray],
        start: u32,
        max_steps: u32,
    ) -> Result<Vec<Walk>, String> {
        let walk = method.walk(self.fma);
        Ok(rays
            .par_iter()
            .map(|r| walk(mesh, r, start, max_steps))
            .collect())
    }
}

/// A GPU through wgpu, with the mesh uploaded once.
pub struct Gpu {
    pub gpu: crate::gpu::Gpu,
    mesh: crate::gpu::GpuMesh,
}

impl Gpu {
    pub fn new(gpu: crate::gpu::Gpu, mesh: &Mesh) -> Gpu {
        let uploaded = gpu.upload(mesh);
        Gpu {
            gpu,
            mesh: uploaded,
        }
    }
}

impl Backend for Gpu {
    fn describe(&self) -> String {
        format!("gpu: {}", self.gpu.describe())
    }

    fn walks(
        &self,
        mesh: &Mesh,
        method: &Method,
        rays: &[Ray],
        start: u32,
        max_steps: u32,
    ) -> Result<Vec<Walk>, String> {
        if mesh.tets.len() != self.mesh.tetrahedra {
            return Err("the GPU holds another mesh".into());
        }
        self.gpu
            .walks(method.name, &self.mesh, rays, start, max_steps)
            .map_err(|e| e.to_string())
    }
}

/// Count wrong rays per method over `views` views; `tick` is called once per view. Memory holds one
/// view's rays and walks at a time.
pub fn run(
    mesh: &Mesh,
    s: &Settings,
    methods: &[&Method],
    backend: &dyn Backend,
    tick: &(dyn Fn() + Sync),
) -> Result<CountReport, String> {
    let exact = by_name("exact").expect("registered");
    let max = default_max_steps(mesh);
    let (lo, hi) = crate::mesh::bounds(&mesh.points);
    let aspect = s.width as f32 / s.height as f32;
    let mut totals: Vec<MethodCount> = std::iter::once(exact)
        .chain(methods.iter().copied())
        .map(|m| MethodCount {
            method: m.name.to_string(),
            ..Default::default()
        })
        .collect();
    let (mut rays_counted, mut views_counted) = (0u64, 0usize);
    let mut start = 0;
    for v in 0..s.views {
        let cam = view(lo, hi, v, s.views, s.seed, s.fov_deg, aspect);
        tick();
        let Ok(located) = locate(mesh, cam.eye, start) else {
            continue;
        };
        start = located;
        views_counted += 1;
        let rays: Vec<Ray> = (0..s.height)
            .flat_map(|y| (0..s.width).map(move |x| cam.ray(x, y, s.width, s.height)))
            .collect();
        rays_counted += rays.len() as u64;
        let t0 = Instant::now();
        let reference = Cpu { fma: false }.walks(mesh, exact, &rays, located, max)?;
        totals[0].seconds += t0.elapsed().as_secs_f64();
        totals[0].steps += reference.iter().map(|w| w.steps as u64).sum::<u64>();
        for (m, total) in methods.iter().zip(&mut totals[1..]) {
            let t0 = Instant::now();
            let walks = backend.walks(mesh, m, &rays, located, max)?;
            total.seconds += t0.elapsed().as_secs_f64();
            let (wrong, steps) = rays
                .par_iter()
                .zip(&walks)
                .zip(&reference)
                .map(|((r, w), re)| {
                    let mut k = [0u64; 5];
                    if let Some(i) = judge(mesh, r, w, re) {
                        k[i] = 1;
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
        let s = &self.settings;
        let views = self.views_counted.max(1) as f64;
        let mut out = format!(
            "scene {} ({} tetrahedra), {} views of {}x{}, backend {}, seed {}; per image, averaged over views\n\n",
            s.scene, self.tetrahedra, self.views_counted, s.width, s.height, self.backend, s.seed
        );
        out += &format!(
            "| method | wrong rays | {} | Φ (tetrahedra) | Mrays/s |\n",
            KINDS.join(" | ")
        );
        out += &format!("|---|---|{}---|---|\n", "---|".repeat(KINDS.len()));
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
