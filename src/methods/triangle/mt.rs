//! Möller & Trumbore 1997 as seed 004 §3.1 describes it (eq. 1): `(D × E2) · E1` computed first and
//! tested for the front side, then `u` and `v` tested, then `t`. Seed 004 prints eq. 1 with a minus
//! sign that Möller & Trumbore's own eq. (and eq. 2 of the same paper) do not have; with it, `t`, `u`
//! and `v` come out negated and no ray in front would ever hit, so it is read as a misprint.
//!
//! "Tested whether the triangle is front side or not" reads two ways, both implemented: [`Mt`] rejects
//! back faces (Möller & Trumbore's `TEST_CULL` branch), [`MtTwoSided`] tests both sides (their other
//! branch, dividing first). Their `EPSILON` is 0: no epsilon is added.

use super::{SingleRay, Tri};
use crate::methods::Arith;
use crate::tet::Ray;
use glam::Vec3;

/// `mt`: front faces only (`det > 0`, counter-clockwise as the ray sees them); division deferred.
pub struct Mt;

/// `mt-two-sided`: both faces; `1 / det` first, then `u`, `v` and `t` scaled by it.
pub struct MtTwoSided;

/// Edges `E1 = P1 - P0`, `E2 = P2 - P0`, `P_vec = D × E2` and `det = E1 · P_vec` (MT97 Fig. 1).
#[inline(always)]
fn setup<A: Arith>(tri: &Tri, ray: &Ray) -> (Vec3, Vec3, Vec3, f32) {
    let e1 = tri[1] - tri[0];
    let e2 = tri[2] - tri[0];
    let pvec = A::cross(ray.dir, e2);
    (e1, e2, pvec, A::dot(e1, pvec))
}

impl SingleRay for Mt {
    fn test<A: Arith>(tri: &Tri, ray: &Ray) -> Option<f32> {
        mt_cull::<A>(tri, ray)
    }
}

#[inline(always)]
fn mt_cull<A: Arith>(tri: &Tri, ray: &Ray) -> Option<f32> {
    let (e1, e2, pvec, det) = setup::<A>(tri, ray);
    if det < 0.0 {
        return None;
    }
    let tvec = ray.org - tri[0];
    let u = A::dot(tvec, pvec);
    if u < 0.0 || u > det {
        return None;
    }
    let qvec = A::cross(tvec, e1);
    let v = A::dot(ray.dir, qvec);
    if v < 0.0 || u + v > det {
        return None;
    }
    let t = A::dot(e2, qvec);
    Some(t * (1.0 / det))
}

impl SingleRay for MtTwoSided {
    fn test<A: Arith>(tri: &Tri, ray: &Ray) -> Option<f32> {
        mt_both::<A>(tri, ray)
    }
}

#[inline(always)]
fn mt_both<A: Arith>(tri: &Tri, ray: &Ray) -> Option<f32> {
    let (e1, e2, pvec, det) = setup::<A>(tri, ray);
    // MT97's `det > -EPSILON && det < EPSILON` with EPSILON = 0 rejects nothing; a zero det gives
    // infinite or NaN `u`, `v`, `t`, which the comparisons below and `t > 0` then decide.
    let inv_det = 1.0 / det;
    let tvec = ray.org - tri[0];
    let u = A::dot(tvec, pvec) * inv_det;
    #[allow(
        clippy::manual_range_contains,
        reason = "MT97's comparisons, which a NaN u passes, not a range test, which it fails"
    )]
    if u < 0.0 || u > 1.0 {
        return None;
    }
    let qvec = A::cross(tvec, e1);
    let v = A::dot(ray.dir, qvec) * inv_det;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    Some(A::dot(e2, qvec) * inv_det)
}
