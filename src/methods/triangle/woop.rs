//! `woop-watertight`: Woop, Benthin and Wald 2013, "Watertight Ray/Triangle Intersection" (JCGT 2(1),
//! Listing 1, backface culling off): the vertices translated to the ray origin and sheared so the ray
//! runs along +z, the 2-D edge functions `U, V, W` recomputed in f64 when one is exactly 0, a hit when
//! they have one sign and their sum is not 0. The listing's test against the current `hit.t` is the
//! nearest-hit loop's, done after the division like every method's.

use super::{HitMethod, Tri, Wide};
use crate::methods::lanes::{F4, V4, answers};
use crate::methods::{Arith, Plain};
use crate::tet::Ray;
use glam::Vec3;

/// Woop, Benthin, Wald 2013, Listing 1 (culling off): sheared ray space, `U, V, W` recomputed in f64
/// when one is exactly 0.
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

/// Four rays as [`WoopWatertight`]'s 4-wide test reads them: each ray's own data (for a lane the f32
/// test cannot decide alone), and, where the four share their axes `kx, ky, kz` (nearly always: the
/// rays of a packet point nearly one way), the origins and shears in lanes.
#[derive(Clone, Copy)]
pub struct WoopLanes {
    rays: [Sheared; 4],
    shared: Option<([usize; 3], V4, V4)>,
}

/// Component `k` of four vectors.
#[inline(always)]
fn component(v: V4, k: usize) -> F4 {
    match k {
        0 => v.x,
        1 => v.y,
        _ => v.z,
    }
}

impl Wide for WoopWatertight {
    type Lanes = WoopLanes;
    type Shared = ();
    fn lanes(rays: [&Sheared; 4]) -> WoopLanes {
        let k = rays[0].k;
        WoopLanes {
            rays: rays.map(|r| *r),
            shared: rays
                .iter()
                .all(|r| r.k == k)
                .then(|| (k, V4::new(rays.map(|r| r.org)), V4::new(rays.map(|r| r.s)))),
        }
    }
    fn shared(_: &Tri, _: Vec3) {}
    /// `woop` for four rays at once (SSE), op for op; a lane whose edge functions include an exact 0
    /// (the f64 recomputation), and every lane where the rays' axes differ, answered by `woop`.
    fn packet4(tri: &Tri, _: &(), l: &WoopLanes, out: &mut [Option<f32>]) {
        let scalar = |i: usize| woop::<Plain>(tri, &l.rays[i]);
        let Some(([kx, ky, kz], org, s)) = l.shared else {
            for (i, o) in out.iter_mut().enumerate() {
                *o = scalar(i);
            }
            return;
        };
        let [a, b, c] = tri.map(|p| V4::splat(p) - org);
        let shear = |p: V4| {
            let pz = component(p, kz);
            (-s.x * pz + component(p, kx), -s.y * pz + component(p, ky))
        };
        let ((ax, ay), (bx, by), (cx, cy)) = (shear(a), shear(b), shear(c));
        let det2 = |p: F4, q: F4, s: F4, t: F4| p * q + -(s * t);
        let u = det2(cx, by, cy, bx);
        let v = det2(ax, cy, ay, cx);
        let w = det2(bx, ay, by, ax);
        let zero = F4::splat(0.0);
        let flat = u.eq(zero).or(v.eq(zero)).or(w.eq(zero)).bits();
        let negative = u.lt(zero).or(v.lt(zero)).or(w.lt(zero));
        let positive = u.gt(zero).or(v.gt(zero)).or(w.gt(zero));
        let det = u + v + w;
        let (az, bz, cz) = (
            s.z * component(a, kz),
            s.z * component(b, kz),
            s.z * component(c, kz),
        );
        let t_scaled = w * cz + (v * bz + u * az);
        let behind = t_scaled
            .lt(zero)
            .and(det.gt(zero))
            .or(t_scaled.gt(zero).and(det.lt(zero)));
        let miss = negative.and(positive).or(det.eq(zero)).or(behind);
        answers(miss.flipped(), t_scaled * (F4::splat(1.0) / det), out);
        for (i, o) in out.iter_mut().enumerate() {
            if flat >> i & 1 == 1 {
                *o = scalar(i);
            }
        }
    }
}
