//! Pinhole cameras and the viewpoints of `tetwalk count` and `tetwalk render` (seed 000 §4: viewpoints
//! around the model, one primary ray per pixel).

use crate::tet::Ray;
use glam::{Mat3, Quat, Vec3};
use rand::RngExt;

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
        // Scaled by a power of two to about 1 first: exactly the same unit vector where the squares
        // neither underflow nor overflow, and a finite one for a model 1e-30 across.
        let d = target - eye;
        let e = d.abs().max_element().log2().floor().clamp(-127.0, 126.0) as i32;
        let scale = 2f32.powi(-e);
        let forward = (d * scale).normalize();
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

    /// Where the centre of pixel `(x, y)` lies on the screen, `(sx, sy)` in (-1, 1)², in f32: `sx`
    /// grows with `x` and `sy` falls with `y` (rounding is monotonic).
    pub(crate) fn screen(x: u32, y: u32, w: u32, h: u32) -> (f32, f32) {
        let sx = 2.0 * (x as f32 + 0.5) / w as f32 - 1.0;
        let sy = 1.0 - 2.0 * (y as f32 + 0.5) / h as f32;
        (sx, sy)
    }

    /// The axes a primary ray is made of: `forward`, `right` and `up`, as [`Camera::ray`] scales them.
    pub fn axes(&self) -> [Vec3; 3] {
        [self.forward, self.right, self.up]
    }

    /// The primary ray through the centre of pixel `(x, y)`, in f32: `forward + right·sx + up·sy`,
    /// summed in that order.
    pub fn ray(&self, x: u32, y: u32, w: u32, h: u32) -> Ray {
        let (sx, sy) = Camera::screen(x, y, w, h);
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

/// The viewpoints of a count or a render: `views` views of `width × height` pixels around a mesh,
/// placed by `seed` ([`view`]), with a vertical field of view of `fov_deg`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Views {
    pub(crate) views: usize,
    pub width: u32,
    pub height: u32,
    pub(crate) seed: u64,
    /// Vertical field of view, degrees.
    pub(crate) fov_deg: f32,
}

impl Views {
    /// The vertical field of view of every count and render.
    pub(crate) const FOV_DEG: f32 = 40.0;
    /// Most viewpoints a count, render or bench places (seed 000's runs have 1,282).
    pub(crate) const MOST: usize = 1 << 20;

    /// `views` viewpoints of `width × height` placed by `seed`, with [`Views::FOV_DEG`].
    pub fn new(views: usize, width: u32, height: u32, seed: u64) -> Views {
        Views {
            views,
            width,
            height,
            seed,
            fov_deg: Views::FOV_DEG,
        }
    }

    /// View `i`'s camera around the points bounded by `lo` and `hi`.
    pub fn camera(&self, lo: Vec3, hi: Vec3, i: usize) -> Camera {
        let aspect = self.width as f32 / self.height as f32;
        view(lo, hi, i, self.views, self.seed, self.fov_deg, aspect)
    }

    /// One primary ray per pixel, row by row (the rows made in parallel).
    pub fn rays(&self, cam: &Camera) -> Vec<Ray> {
        use rayon::prelude::*;
        let (w, h) = (self.width, self.height);
        let mut rays = vec![
            Ray {
                org: Vec3::ZERO,
                dir: Vec3::ZERO
            };
            w as usize * h as usize
        ];
        rays.par_chunks_mut(w.max(1) as usize)
            .zip(0..h)
            .for_each(|(row, y)| {
                for (x, r) in (0..w).zip(row) {
                    *r = cam.ray(x, y, w, h);
                }
            });
        rays
    }
}

/// Pixel indices (row-major) in packet order: `tile × tile` tiles row by row, in each tile its `p × p`
/// packets row by row, each packet row by row (`p` divides `tile`; a tile of `p` is packets alone).
pub fn packet_order(width: u32, height: u32, p: u32, tile: u32) -> Vec<usize> {
    debug_assert!(
        tile.is_multiple_of(p),
        "a packet side divides the tile side"
    );
    let mut out = Vec::with_capacity(width as usize * height as usize);
    for ty in (0..height).step_by(tile as usize) {
        for tx in (0..width).step_by(tile as usize) {
            for by in (ty..(ty + tile).min(height)).step_by(p as usize) {
                for bx in (tx..(tx + tile).min(width)).step_by(p as usize) {
                    for y in by..(by + p).min(height) {
                        for x in bx..(bx + p).min(width) {
                            out.push((y * width + x) as usize);
                        }
                    }
                }
            }
        }
    }
    out
}
