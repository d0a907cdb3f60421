//! `ray-plane`: Lagae & Dutré 2008's first method (seed 000 §2.3.2, seed 003 §2.3), after Garrity 1990:
//! intersect the ray with the face planes it is leaving through and exit where `t` is smallest.

use super::lanes::{F4, V4};
use super::{Arith, ExitMethod};
use crate::tet::{FACE_VERTICES, Ray, Tet};
use glam::Vec3;

/// The four faces' planes as this family of methods computes them, face `f` in lane `f`: the outward
/// normal `n = (b - a) × (c - a)`, the first vertex `a`, and `n · d`; each lane op for op as one face
/// alone (2 vector subtractions, a cross product, a dot product), so bit for bit the same.
#[inline(always)]
pub(super) fn face_planes<A: Arith>(tet: &Tet, dir: Vec3) -> (V4, V4, F4) {
    let v = V4::of(tet);
    let corner = |k: usize| v.pick(FACE_VERTICES.map(|f| f[k]));
    let (a, b, c) = (corner(0), corner(1), corner(2));
    let n = (b - a).cross::<A>(c - a);
    (n, a, n.dot::<A>(V4::splat(dir)))
}

/// Reconstructed: for each of the four faces, `n` (2 vector subtractions, a cross product) and
/// `n · d`; where `n · d > 0` the ray leaves through the plane at `t = n · (a - o) / (n · d)`; the exit
/// face is the one with the smallest `t` (strictly smaller wins, so the lowest index on a tie). Per
/// tetrahedron: 4 × (6 sub + 9 cross + 5 dot) + up to 4 × (3 sub + 5 dot + 1 div) = 80 to 116 operations,
/// the four faces' in four lanes (`face_planes`; `t` in every lane, kept where `n · d > 0`).
/// The entry face is not used. `None` when no face has `n · d > 0` (or every `t` is NaN).
pub struct RayPlane;

impl ExitMethod for RayPlane {
    type RayData = Ray;

    fn prepare<A: Arith>(ray: &Ray) -> Ray {
        *ray
    }

    #[inline(always)]
    fn exit_face<A: Arith>(tet: &Tet, ray: &Ray, _entry: Option<usize>) -> Option<usize> {
        let (n, a, nd) = face_planes::<A>(tet, ray.dir);
        let leaving = nd.gt(F4::splat(0.0)).bits();
        let t = (n.dot::<A>(a - V4::splat(ray.org)) / nd).to_array();
        let mut best: Option<(usize, f32)> = None;
        // Indexed, not iterated: so compiled with branches the processor predicts along a walk (the
        // iterator form compiled to selects, whose chain from face to next tetrahedron ran 1.8x slower).
        #[allow(clippy::needless_range_loop)]
        for f in 0..4 {
            if leaving >> f & 1 == 1 && best.is_none_or(|(_, bt)| t[f] < bt) {
                best = Some((f, t[f]));
            }
        }
        best.map(|(f, _)| f)
    }
}
