//! `mt-precomputed`: Möller–Trumbore with the triangle's terms precomputed (seed 004 eq. 2, after
//! Barzel's jgt collection): `N = E1 × E2`, `E1`, `E2` once per triangle; per ray `S = O - P0`,
//! `(t, u, v) = -1/(N·D) · (N·S, -(D × S)·E2, (D × S)·E1)`, tested `0 ≤ u`, `0 ≤ v`, `u + v ≤ 1`.

use super::{HitMethod, Tri, Wide};
use crate::methods::lanes::{F4, V4, answers};
use crate::methods::{Arith, Plain};
use crate::tet::Ray;
use glam::Vec3;

/// Seed 004 eq. 2, the "improved Möller" test: `N`, `E1`, `E2` once per triangle.
pub struct MtPrecomputed;

/// Eq. 2's per-triangle terms.
#[derive(Clone, Copy, Debug)]
pub struct Precomputed {
    pub p0: Vec3,
    pub e1: Vec3,
    pub e2: Vec3,
    pub n: Vec3,
}

/// `P0`, `E1 = P1 - P0`, `E2 = P2 - P0` and `N = E1 × E2` (seed 004 §3.1).
#[inline(always)]
pub(super) fn precompute<A: Arith>(tri: &Tri) -> Precomputed {
    let e1 = tri[1] - tri[0];
    let e2 = tri[2] - tri[0];
    Precomputed {
        p0: tri[0],
        e1,
        e2,
        n: A::cross(e1, e2),
    }
}

/// The barycentric test of eqs. 2 and 3, `0 ≤ u`, `0 ≤ v`, `u + v ≤ 1`, in the paper's order.
#[inline(always)]
pub(super) fn inside(u: f32, v: f32) -> bool {
    u >= 0.0 && v >= 0.0 && u + v <= 1.0
}

impl HitMethod for MtPrecomputed {
    type TriData = Precomputed;
    type RayData = Ray;
    fn tri<A: Arith>(tri: &Tri) -> Precomputed {
        precompute::<A>(tri)
    }
    fn ray<A: Arith>(ray: &Ray) -> Ray {
        *ray
    }
    #[inline(always)]
    fn packet<A: Arith>(p: &Precomputed, _org: Vec3, rays: &[Ray], out: &mut [Option<f32>]) {
        for (ray, o) in rays.iter().zip(out) {
            let r = -1.0 / A::dot(p.n, ray.dir);
            let s = ray.org - p.p0;
            let ds = A::cross(ray.dir, s);
            let u = r * -A::dot(ds, p.e2);
            let v = r * A::dot(ds, p.e1);
            *o = inside(u, v).then(|| r * A::dot(p.n, s));
        }
    }
}

impl Wide for MtPrecomputed {
    /// Four rays' directions and origins.
    type Lanes = (V4, V4);
    type Shared = ();
    fn lanes(rays: [&Ray; 4]) -> (V4, V4) {
        (V4::new(rays.map(|r| r.dir)), V4::new(rays.map(|r| r.org)))
    }
    fn shared(_: &Precomputed, _: Vec3) {}
    /// The loop body above for four rays at once (SSE), op for op.
    fn packet4(p: &Precomputed, _: &(), &(d, org): &(V4, V4), out: &mut [Option<f32>]) {
        let (n, e1, e2) = (V4::splat(p.n), V4::splat(p.e1), V4::splat(p.e2));
        let r = F4::splat(-1.0) / n.dot::<Plain>(d);
        let s = org - V4::splat(p.p0);
        let ds = d.cross::<Plain>(s);
        let u = r * -ds.dot::<Plain>(e2);
        let v = r * ds.dot::<Plain>(e1);
        let (zero, one) = (F4::splat(0.0), F4::splat(1.0));
        let hit = u.ge(zero).and(v.ge(zero)).and((u + v).le(one));
        answers(hit, r * n.dot::<Plain>(s), out);
    }
}
