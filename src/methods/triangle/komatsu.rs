//! `komatsu-packet`: Komatsu et al.'s packet Möller–Trumbore (seed 004 eq. 3, Figure 3): for a packet
//! of rays sharing the origin `O`, `N·S`, `-S × E2` and `S × E1` are computed once per packet and
//! triangle; per ray `(t, u, v) = -1/(N·D) · (N·S, D·(-S × E2), D·(S × E1))`, with early termination
//! after `u` and after `v`.

use super::mt_precomputed::{Precomputed, precompute};
use super::{HitMethod, Tri};
use crate::methods::Arith;
use crate::tet::Ray;
use glam::Vec3;

pub struct KomatsuPacket;

impl HitMethod for KomatsuPacket {
    type TriData = Precomputed;
    type RayData = Vec3;
    fn tri<A: Arith>(tri: &Tri) -> Precomputed {
        precompute::<A>(tri)
    }
    fn ray<A: Arith>(ray: &Ray) -> Vec3 {
        ray.dir
    }
    fn packet<A: Arith>(p: &Precomputed, org: Vec3, dirs: &[Vec3], out: &mut [Option<f32>]) {
        // The dotted box of Figure 3: once per packet.
        let s = org - p.p0;
        let ns = A::dot(p.n, s);
        let a = -A::cross(s, p.e2);
        let b = A::cross(s, p.e1);
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
