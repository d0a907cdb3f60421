//! `woop-watertight`: Woop, Benthin and Wald 2013, "Watertight Ray/Triangle Intersection" (JCGT 2(1),
//! Listing 1, backface culling off): the vertices translated to the ray origin and sheared so the ray
//! runs along +z, the 2-D edge functions `U, V, W` recomputed in f64 when one is exactly 0, a hit when
//! they have one sign and their sum is not 0. The listing's test against the current `hit.t` is the
//! nearest-hit loop's, done after the division like every method's.

use super::{HitMethod, Tri};
use crate::methods::Arith;
use crate::tet::Ray;
use glam::Vec3;

pub struct WoopWatertight;

/// Listing 1's per-ray precomputation: the axes `kx, ky, kz` and the shear `Sx, Sy, Sz`.
#[derive(Clone, Copy, Debug)]
pub struct Sheared {
    pub org: Vec3,
    pub k: [usize; 3],
    pub s: Vec3,
}

/// `a·b - c·d` in f64 from f32 factors (the products are exact in f64), rounded to f32.
#[inline(always)]
fn det2_f64(a: f32, b: f32, c: f32, d: f32) -> f32 {
    (a as f64 * b as f64 - c as f64 * d as f64) as f32
}

impl HitMethod for WoopWatertight {
    type TriData = Tri;
    type RayData = Sheared;
    fn tri<A: Arith>(tri: &Tri) -> Tri {
        *tri
    }
    fn ray<A: Arith>(ray: &Ray) -> Sheared {
        let d = ray.dir;
        let a = d.abs();
        // max_dim: the first of the largest components.
        let kz = if a.x >= a.y && a.x >= a.z {
            0
        } else if a.y >= a.z {
            1
        } else {
            2
        };
        let (mut kx, mut ky) = ((kz + 1) % 3, (kz + 2) % 3);
        if d[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        Sheared {
            org: ray.org,
            k: [kx, ky, kz],
            s: Vec3::new(d[kx] / d[kz], d[ky] / d[kz], 1.0 / d[kz]),
        }
    }
    #[inline(always)]
    fn packet<A: Arith>(tri: &Tri, _org: Vec3, rays: &[Sheared], out: &mut [Option<f32>]) {
        for (r, o) in rays.iter().zip(out) {
            *o = woop::<A>(tri, r);
        }
    }
}

#[inline(always)]
fn woop<A: Arith>(tri: &Tri, r: &Sheared) -> Option<f32> {
    let [kx, ky, kz] = r.k;
    let [a, b, c] = tri.map(|p| p - r.org);
    // Shear and scale: x' = x - Sx·z, y' = y - Sy·z.
    let shear = |p: Vec3| (A::mad(-r.s.x, p[kz], p[kx]), A::mad(-r.s.y, p[kz], p[ky]));
    let ((ax, ay), (bx, by), (cx, cy)) = (shear(a), shear(b), shear(c));
    let det2 = |p: f32, q: f32, s: f32, t: f32| A::mad(p, q, -(s * t));
    let mut u = det2(cx, by, cy, bx);
    let mut v = det2(ax, cy, ay, cx);
    let mut w = det2(bx, ay, by, ax);
    if u == 0.0 || v == 0.0 || w == 0.0 {
        u = det2_f64(cx, by, cy, bx);
        v = det2_f64(ax, cy, ay, cx);
        w = det2_f64(bx, ay, by, ax);
    }
    if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
        return None;
    }
    let det = u + v + w;
    if det == 0.0 {
        return None;
    }
    let (az, bz, cz) = (r.s.z * a[kz], r.s.z * b[kz], r.s.z * c[kz]);
    let t_scaled = A::dot(Vec3::new(u, v, w), Vec3::new(az, bz, cz));
    // xorf(T, sign(det)) < 0: T and det of opposite signs, the hit behind the origin.
    if (t_scaled < 0.0 && det > 0.0) || (t_scaled > 0.0 && det < 0.0) {
        return None;
    }
    Some(t_scaled * (1.0 / det))
}
