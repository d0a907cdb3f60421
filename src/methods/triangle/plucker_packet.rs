//! `plucker-packet`: the Plücker packet test seed 004 compares against (Benthin 2006 §4): the packet's
//! origin translated to the coordinate origin, so that a ray's side product with an edge `a → b` is
//! `D · (a' × b')` (`a' = a - O`): the three edge moments and `N · a'` once per packet and triangle,
//! three dot products per ray, a hit when all three have one sign, then `t = N·a' / N·D`.

use super::{HitMethod, Tri};
use crate::methods::Arith;
use crate::tet::Ray;
use glam::Vec3;

pub struct PluckerPacket;

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
    fn packet<A: Arith>(tri: &WithNormal, org: Vec3, dirs: &[Vec3], out: &mut [Option<f32>]) {
        let [a, b, c] = tri.v.map(|p| p - org);
        let (mab, mbc, mca) = (A::cross(a, b), A::cross(b, c), A::cross(c, a));
        let na = A::dot(tri.n, a);
        for (d, o) in dirs.iter().zip(out) {
            let s = [A::dot(*d, mab), A::dot(*d, mbc), A::dot(*d, mca)];
            let one_sign = s.iter().all(|&x| x >= 0.0) || s.iter().all(|&x| x <= 0.0);
            *o = one_sign.then(|| na / A::dot(tri.n, *d));
        }
    }
}
