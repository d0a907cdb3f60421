//! `stp`: Lagae & Dutré 2008's fourth and fastest method (seed 000 §2.3.2, seed 003 §2.2): three to six
//! scalar triple products with early outs.

use super::lanes::{V4, V8};
use super::plucker::{EdgeSigns, edge_ends};
use super::{Arith, ExitMethod};
use crate::tet::{Ray, Tet};

/// Reconstructed: with the vertices relative to the origin, `a' = a - o`, the scalar triple product
/// `[d, a', b'] = d · (a' × b')` is the ray's side of edge `a → b` (14 operations each, shared between
/// the two faces of an edge). Faces are tried in the order 3, 2, 1, 0; the first face whose three
/// products along its outward cycle are none `< 0` (not all zero) is the exit face. The published
/// method evaluates a face's products until one is negative (early outs: 3 products at best, 6 at
/// most); here all six are computed at once in lanes, lane by lane (faster than the early outs'
/// branches), which decides the same face: a product's value does not depend on when it is taken.
/// The entry face is not used. `None` when no face passes.
pub struct Stp;

impl ExitMethod for Stp {
    type RayData = Ray;

    fn prepare<A: Arith>(ray: &Ray) -> Ray {
        *ray
    }

    #[inline(always)]
    fn exit_face<A: Arith>(tet: &Tet, ray: &Ray, _entry: Option<usize>) -> Option<usize> {
        let (a, b) = edge_ends::<A>(V4::of(tet) - V4::splat(ray.org));
        EdgeSigns::of_lanes(V8::<A>::splat(ray.dir).dot(a.cross(b))).stp_exit()
    }
}
