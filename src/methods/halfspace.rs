//! `halfspace`: Lagae & Dutré 2008's second method (seed 000 §2.3.2): half-space classification.

use super::ray_plane::face_plane;
use super::{Arith, ExitMethod};
use crate::tet::{FACE_VERTICES, Ray, Tet};

/// Reconstructed: the faces with `n · d > 0` are the candidates (the half-spaces the ray is leaving);
/// a single candidate is the exit face at once. Otherwise, for each candidate in index order, the ray's
/// point on that face's plane, `p = o + t·d` with `t = n · (a - o) / (n · d)`, is classified against the
/// other candidates' half-spaces; the first candidate whose point lies in all of them
/// (`n_g · (p - a_g) ≤ 0`) is the exit face. Per tetrahedron: 80 operations for the four planes, then
/// per tested candidate 3 sub + 5 dot + 1 div + 6 for `p`, and 8 per half-space test.
/// The entry face is not used. `None` when no candidate passes.
pub struct HalfSpace;

impl ExitMethod for HalfSpace {
    type RayData = Ray;

    fn prepare<A: Arith>(ray: &Ray) -> Ray {
        *ray
    }

    #[inline(always)]
    fn exit_face<A: Arith>(tet: &Tet, ray: &Ray, _entry: Option<usize>) -> Option<usize> {
        let plane = |f| face_plane::<A>(tet, f, ray.dir);
        let planes = [plane(0), plane(1), plane(2), plane(3)];
        let leaving = |f: usize| planes[f].1 > 0.0;
        let candidates = (0..4).filter(|&f| leaving(f)).count();
        if candidates == 1 {
            return (0..4).find(|&f| leaving(f));
        }
        let anchor = |f: usize| tet[FACE_VERTICES[f][0]];
        (0..4).filter(|&f| leaving(f)).find(|&f| {
            let (n, nd) = planes[f];
            let t = A::dot(n, anchor(f) - ray.org) / nd;
            let p = A::axpy(t, ray.dir, ray.org);
            (0..4)
                .filter(|&g| g != f && leaving(g))
                .all(|g| A::dot(planes[g].0, p - anchor(g)) <= 0.0)
        })
    }
}
