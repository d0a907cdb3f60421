//! `halfspace`: Lagae & Dutré 2008's second method (seed 000 §2.3.2): half-space classification.

use super::lanes::{F4, V4};
use super::ray_plane::face_planes;
use super::{Arith, ExitMethod};
use crate::tet::{Ray, Tet};

/// Reconstructed: the faces with `n · d > 0` are the candidates (the half-spaces the ray is leaving);
/// a single candidate is the exit face at once. Otherwise, for each candidate in index order, the ray's
/// point on that face's plane, `p = o + t·d` with `t = n · (a - o) / (n · d)`, is classified against the
/// other candidates' half-spaces; the first candidate whose point lies in all of them
/// (`n_g · (p - a_g) ≤ 0`) is the exit face. Per tetrahedron: 80 operations for the four planes, then
/// per tested candidate 3 sub + 5 dot + 1 div + 6 for `p`, and 8 per half-space test. Computed in four
/// lanes, op for op (`face_planes`): the planes and the points `p` face by face, and one candidate's
/// point against the four half-spaces at once (those of faces that are not candidates ignored).
/// The entry face is not used. `None` when no candidate passes.
pub struct HalfSpace;

impl ExitMethod for HalfSpace {
    type RayData = Ray;

    fn prepare<A: Arith>(ray: &Ray) -> Ray {
        *ray
    }

    #[inline(always)]
    fn exit_face<A: Arith>(tet: &Tet, ray: &Ray, _entry: Option<usize>) -> Option<usize> {
        let (n, a, nd) = face_planes::<A>(tet, ray.dir);
        let leaving = nd.gt(F4::splat(0.0)).bits();
        if leaving.count_ones() == 1 {
            return Some(leaving.trailing_zeros() as usize);
        }
        let org = V4::splat(ray.org);
        let t = n.dot::<A>(a - org) / nd;
        let p = V4::axpy::<A>(t, V4::splat(ray.dir), org);
        (0..4).filter(|&f| leaving >> f & 1 == 1).find(|&f| {
            let inside = n.dot::<A>(p.pick([f; 4]) - a).le(F4::splat(0.0)).bits();
            let others = leaving & !(1 << f);
            inside & others == others
        })
    }
}
