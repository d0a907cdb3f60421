//! `plucker`: Lagae & Dutré 2008's third method (seed 000 §2.3.2), the permuted inner products of
//! Platis & Theoharis 2003: six side products of the ray with the six edges.

use super::{Arith, ExitMethod, each, leaves};
use crate::tet::{EDGES, FACE_VERTICES, Ray, Tet, edge_index};
use glam::Vec3;

/// The ray as a Plücker line `{u : v}` = `{d : o × d}`, computed once per ray.
#[derive(Clone, Copy, Debug)]
pub struct PluckerRay {
    pub u: Vec3,
    pub v: Vec3,
}

/// The ray's Plücker coordinates (6 mul, 3 sub).
#[inline(always)]
pub(super) fn plucker_ray<A: Arith>(ray: &Ray) -> PluckerRay {
    PluckerRay {
        u: ray.dir,
        v: A::cross(ray.org, ray.dir),
    }
}

/// Side product (Shoemake 1998) of the ray with the line `a → b`, whose Plücker coordinates are
/// `{b - a : a × b}`: `u_r · (a × b) + v_r · (b - a)`; 3 sub + 9 + 11 = 23 operations.
/// Positive when the ray turns counterclockwise around `a → b`; equals `det[a - o, b - o, d]`.
#[inline(always)]
pub(super) fn side<A: Arith>(ray: &PluckerRay, a: Vec3, b: Vec3) -> f32 {
    let moment = A::cross(a, b);
    let dir = b - a;
    A::mad(
        ray.v.z,
        dir.z,
        A::mad(
            ray.v.y,
            dir.y,
            A::mad(ray.v.x, dir.x, A::dot(ray.u, moment)),
        ),
    )
}

/// Platis & Theoharis 2003 exit test over all four faces: face `f` is left when the side products
/// along its outward cycle are all `≥ 0` and not all zero; the first such face in index order.
#[inline(always)]
pub(super) fn exit_by_sides(sides: &[f32; 6]) -> Option<usize> {
    (0..4).find(|&f| {
        let v = FACE_VERTICES[f];
        let s = each([0, 1, 2], |k| {
            let (e, rev) = edge_index(v[k], v[(k + 1) % 3]);
            if rev { -sides[e] } else { sides[e] }
        });
        leaves(&s)
    })
}

/// Reconstructed: the six side products of the ray with the edges (6 × 23 = 138 operations, plus 9 for
/// the ray once), then the face whose three edges all turn the right way. The entry face is not used.
/// `None` when no face passes.
pub struct Plucker;

impl ExitMethod for Plucker {
    type RayData = PluckerRay;

    fn prepare<A: Arith>(ray: &Ray) -> PluckerRay {
        plucker_ray::<A>(ray)
    }

    #[inline(always)]
    fn exit_face<A: Arith>(tet: &Tet, ray: &PluckerRay, _entry: Option<usize>) -> Option<usize> {
        let sides = each(EDGES, |[a, b]| side::<A>(ray, tet[a], tet[b]));
        exit_by_sides(&sides)
    }
}
