//! `plucker-packet`: the Plücker packet test seed 004 compares against (Benthin 2006 §4): the packet's
//! origin translated to the coordinate origin, so that a ray's side product with an edge `a → b` is
//! `D · (a' × b')` (`a' = a - O`): the three edge moments and `N · a'` once per packet and triangle,
//! three dot products per ray, a hit when all three have one sign, then `t = N·a' / N·D`.

use super::{HitMethod, Tri, Wide};
use crate::methods::lanes::{F4, V4, answers};
use crate::methods::{Arith, Plain};
use crate::tet::Ray;
use glam::Vec3;

/// Benthin 2006 as seed 004 §2 describes it: the packet's origin moved to the coordinate origin, three
/// edge moments once per packet, three dot products per ray.
pub struct PluckerPacket;

/// Once per packet and triangle: the vertices translated by the packet's origin (`a' = a - O`), the
/// three edge moments `a'×b'`, `b'×c'`, `c'×a'`, and `N · a'`.
#[inline(always)]
fn per_packet<A: Arith>(tri: &WithNormal, org: Vec3) -> ([Vec3; 3], f32) {
    let [a, b, c] = tri.v.map(|p| p - org);
    (
        [A::cross(a, b), A::cross(b, c), A::cross(c, a)],
        A::dot(tri.n, a),
    )
}

/// The vertices and the normal `N = (P1 - P0) × (P2 - P0)`, once per triangle.
#[derive(Clone, Copy, Debug)]
pub struct WithNormal {
    pub v: Tri,
    pub n: Vec3,
}

impl HitMethod for PluckerPacket {
    type TriData = WithNormal;
    type RayData = Vec3;
    fn tri<A: Arith>(tri: &Tri) -> WithNormal {
        WithNormal {
            v: *tri,
            n: A::cross(tri[1] - tri[0], tri[2] - tri[0]),
        }
    }
    fn ray<A: Arith>(ray: &Ray) -> Vec3 {
        ray.dir
    }
    #[inline(always)]
    fn packet<A: Arith>(tri: &WithNormal, org: Vec3, dirs: &[Vec3], out: &mut [Option<f32>]) {
        let ([mab, mbc, mca], na) = per_packet::<A>(tri, org);
        for (d, o) in dirs.iter().zip(out) {
            let s = [A::dot(*d, mab), A::dot(*d, mbc), A::dot(*d, mca)];
            let one_sign = s.iter().all(|&x| x >= 0.0) || s.iter().all(|&x| x <= 0.0);
            *o = one_sign.then(|| na / A::dot(tri.n, *d));
        }
    }
}

impl Wide for PluckerPacket {
    /// Four rays' directions.
    type Lanes = V4;
    /// The three edge moments and `N · a'`: once per packet and triangle, as above.
    type Shared = ([Vec3; 3], f32);
    fn lanes(dirs: [&Vec3; 4]) -> V4 {
        V4::new(dirs.map(|d| *d))
    }
    fn shared(tri: &WithNormal, org: Vec3) -> ([Vec3; 3], f32) {
        per_packet::<Plain>(tri, org)
    }
    /// Four rays' three side products at once (SSE).
    fn packet4(tri: &WithNormal, &(m, na): &([Vec3; 3], f32), d: &V4, out: &mut [Option<f32>]) {
        let s = m.map(|m| d.dot::<Plain>(V4::splat(m)));
        let zero = F4::splat(0.0);
        let all_ge = s[0].ge(zero).and(s[1].ge(zero)).and(s[2].ge(zero));
        let all_le = s[0].le(zero).and(s[1].le(zero)).and(s[2].le(zero));
        answers(
            all_ge.or(all_le),
            F4::splat(na) / V4::splat(tri.n).dot::<Plain>(*d),
            out,
        );
    }
}
