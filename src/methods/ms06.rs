//! `ms06`: Marmitt & Slusallek 2006 (as seed 000 §2.3.2 describes it): Plücker tests that use the
//! entry face, 2.67 side products on average.

use super::plucker::{PluckerRay, exit_by_sides_of, plucker_ray, side};
use super::{Arith, ExitMethod};
use crate::tet::{FACE_VERTICES, Ray, Tet};

/// Reconstructed: with entry face `F_e`, outward cycle `a0 a1 a2`, and apex `V = v_e`, the ray leaves
/// through the face holding `a_k a_(k+1) V` iff `σ_k ≥ 0` and `σ_(k+1) ≤ 0`, `σ_k` the side product with
/// the complement edge `a_k → V` (the edge on the entry face turns the right way already, since the ray
/// came in through it). `σ0, σ1` decide the first face (2 products, one case in three), `σ2` the other
/// two (3 products): 2.67 on average, 23 operations each (Platis & Theoharis' side product). Neither of
/// the last two passing gives `None`. In the starting tetrahedron (no entry face) all six side products
/// are taken, as Platis & Theoharis do.
pub struct Ms06;

impl ExitMethod for Ms06 {
    type RayData = PluckerRay;

    fn prepare<A: Arith>(ray: &Ray) -> PluckerRay {
        plucker_ray::<A>(ray)
    }

    #[inline(always)]
    fn exit_face<A: Arith>(tet: &Tet, ray: &PluckerRay, entry: Option<usize>) -> Option<usize> {
        let Some(e) = entry else {
            return exit_by_sides_of::<A>(ray, tet);
        };
        let a = FACE_VERTICES[e];
        // σ_k, the side product with the complement edge a_k → V (`side` is always inlined; a
        // closure around it was not, and the fused model's FMA instruction reaches only inlined code).
        let (s0, s1) = (
            side::<A>(ray, tet[a[0]], tet[e]),
            side::<A>(ray, tet[a[1]], tet[e]),
        );
        if s0 >= 0.0 && s1 <= 0.0 {
            return Some(a[2]);
        }
        let s2 = side::<A>(ray, tet[a[2]], tet[e]);
        if s1 >= 0.0 && s2 <= 0.0 {
            Some(a[0])
        } else if s2 >= 0.0 && s0 <= 0.0 {
            Some(a[1])
        } else {
            None
        }
    }
}
