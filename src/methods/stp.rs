//! `stp`: Lagae & Dutré 2008's fourth and fastest method (seed 000 §2.3.2, seed 003 §2.2): three to six
//! scalar triple products with early outs.

use super::{Arith, ExitMethod, each};
use crate::tet::{FACE_VERTICES, Ray, Tet, edge_index};

/// Reconstructed: with the vertices relative to the origin, `a' = a - o`, the scalar triple product
/// `[d, a', b'] = d · (a' × b')` is the ray's side of edge `a → b` (14 operations each, shared between
/// the two faces of an edge). Faces are tried in the order 3, 2, 1, 0; a face's edges are evaluated
/// along its outward cycle until one is negative (early out), and the first face whose three products
/// are all `≥ 0` (not all zero) is the exit face: 3 products at best, 6 at most. The entry face is not
/// used. `None` when no face passes.
pub struct Stp;

impl ExitMethod for Stp {
    type RayData = Ray;

    fn prepare<A: Arith>(ray: &Ray) -> Ray {
        *ray
    }

    #[inline(always)]
    fn exit_face<A: Arith>(tet: &Tet, ray: &Ray, _entry: Option<usize>) -> Option<usize> {
        let rel = each(*tet, |v| v - ray.org);
        let mut known: [Option<f32>; 6] = [None; 6];
        let mut stp = |i: usize, j: usize| {
            let (e, rev) = edge_index(i, j);
            let s = *known[e].get_or_insert_with(|| {
                let [a, b] = if rev {
                    [rel[j], rel[i]]
                } else {
                    [rel[i], rel[j]]
                };
                A::dot(ray.dir, A::cross(a, b))
            });
            if rev { -s } else { s }
        };
        (0..4).rev().find(|&f| {
            let v = FACE_VERTICES[f];
            let mut nonzero = false;
            for k in 0..3 {
                let s = stp(v[k], v[(k + 1) % 3]);
                if s < 0.0 {
                    return false;
                }
                nonzero |= s != 0.0;
            }
            nonzero
        })
    }
}
