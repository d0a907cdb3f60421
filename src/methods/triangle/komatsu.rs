//! `komatsu-packet`: Komatsu et al.'s packet Möller–Trumbore (seed 004 eq. 3, Figure 3): for a packet
//! of rays sharing the origin `O`, `N·S`, `-S × E2` and `S × E1` are computed once per packet and
//! triangle; per ray `(t, u, v) = -1/(N·D) · (N·S, D·(-S × E2), D·(S × E1))`, with early termination
//! after `u` and after `v`.

use super::mt_precomputed::{Precomputed, precompute};
use super::{HitMethod, Tri, Wide};
use crate::methods::lanes::{F4, V4, answers};
use crate::methods::{Arith, Plain};
use crate::tet::Ray;
use glam::Vec3;

/// Seed 004 eq. 3 (Komatsu et al., Figure 3): `N·S`, `−S×E2` and `S×E1` once per packet of rays sharing
/// an origin, early termination after `u` and after `v`.
pub struct KomatsuPacket;

/// The dotted box of Figure 3, once per packet and triangle: `N·S`, `-S × E2`, `S × E1` (`S = O - P0`).
#[inline(always)]
fn per_packet<A: Arith>(p: &Precomputed, org: Vec3) -> (f32, Vec3, Vec3) {
    let s = org - p.p0;
    (A::dot(p.n, s), -A::cross(s, p.e2), A::cross(s, p.e1))
}

impl HitMethod for KomatsuPacket {
    type TriData = Precomputed;
    type RayData = Vec3;
    fn tri<A: Arith>(tri: &Tri) -> Precomputed {
        precompute::<A>(tri)
    }
    fn ray<A: Arith>(ray: &Ray) -> Vec3 {
        ray.dir
    }
    #[inline(always)]
    fn packet<A: Arith>(p: &Precomputed, org: Vec3, dirs: &[Vec3], out: &mut [Option<f32>]) {
        let (ns, a, b) = per_packet::<A>(p, org);
        for (d, o) in dirs.iter().zip(out) {
            *o = None;
            let r = -1.0 / A::dot(p.n, *d);
            let u = r * A::dot(*d, a);
            if u < 0.0 {
                continue;
            }
            let v = r * A::dot(*d, b);
            if v < 0.0 || u + v > 1.0 {
                continue;
            }
            *o = Some(r * ns);
        }
    }
}

impl Wide for KomatsuPacket {
    /// Four rays' directions.
    type Lanes = V4;
    /// `N·S`, `-S × E2`, `S × E1`: once per packet and triangle, as above.
    type Shared = (f32, Vec3, Vec3);
    fn lanes(dirs: [&Vec3; 4]) -> V4 {
        V4::new(dirs.map(|d| *d))
    }
    fn shared(p: &Precomputed, org: Vec3) -> (f32, Vec3, Vec3) {
        per_packet::<Plain>(p, org)
    }
    /// Four rays at once (SSE): the early exits become one miss mask of the same comparisons, and
    /// the four end after `u` where every lane missed (seed 004 §3.2's early termination).
    fn packet4(p: &Precomputed, &(ns, a, b): &(f32, Vec3, Vec3), d: &V4, out: &mut [Option<f32>]) {
        let r = F4::splat(-1.0) / V4::splat(p.n).dot::<Plain>(*d);
        let u = r * d.dot::<Plain>(V4::splat(a));
        let (zero, one) = (F4::splat(0.0), F4::splat(1.0));
        if u.lt(zero).bits() == 0b1111 {
            out.fill(None);
            return;
        }
        let v = r * d.dot::<Plain>(V4::splat(b));
        let miss = u.lt(zero).or(v.lt(zero)).or((u + v).gt(one));
        answers(miss.flipped(), r * F4::splat(ns), out);
    }
}
