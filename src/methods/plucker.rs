//! `plucker`: Lagae & Dutré 2008's third method (seed 000 §2.3.2), the permuted inner products of
//! Platis & Theoharis 2003: six side products of the ray with the six edges.

use super::lanes::{F4, M4, V4};
use super::{Arith, ExitMethod};
use crate::tet::{EDGE_OF, EDGES, FACE_VERTICES, Ray, Tet};
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

/// [`side`] of four lines `a → b` at once, lane by lane op for op.
#[inline(always)]
fn sides4<A: Arith>(ray: &PluckerRay, a: V4, b: V4) -> F4 {
    let moment = a.cross::<A>(b);
    let dir = b - a;
    let v = V4::splat(ray.v);
    A::mad4(
        v.z,
        dir.z,
        A::mad4(
            v.y,
            dir.y,
            A::mad4(v.x, dir.x, V4::splat(ray.u).dot::<A>(moment)),
        ),
    )
}

/// The two ends of the six edges ([`EDGES`]) of a tetrahedron whose vertices are in lanes: edges 0 to
/// 3 in the first four lanes, 4 and 5 in the second four's first two (the last two repeat edge 5).
#[inline(always)]
pub(super) fn edge_ends(v: V4) -> [(V4, V4); 2] {
    let end = |k: usize, first: usize| v.pick([0, 1, 2, 3].map(|i| EDGES[(first + i).min(5)][k]));
    [(end(0, 0), end(1, 0)), (end(0, 4), end(1, 4))]
}

/// Six products' signs, one per edge, as bit sets over [`EDGES`]: `< 0`, `> 0`, NaN.
#[derive(Clone, Copy)]
pub(super) struct EdgeSigns {
    lt: u32,
    gt: u32,
    nan: u32,
}

impl EdgeSigns {
    /// The signs of six products known to be nonzero and finite: bit `e` of `negative` or
    /// `positive` set for edge `e`.
    #[inline(always)]
    pub(super) fn of_signs(negative: u32, positive: u32) -> EdgeSigns {
        EdgeSigns {
            lt: negative,
            gt: positive,
            nan: 0,
        }
    }

    /// The signs of six products in lanes ([`edge_ends`]' order).
    #[inline(always)]
    pub(super) fn of_lanes([lo, hi]: [F4; 2]) -> EdgeSigns {
        let zero = F4::splat(0.0);
        let bits =
            |test: fn(F4, F4) -> M4| test(lo, zero).bits() | (test(hi, zero).bits() & 0b11) << 4;
        EdgeSigns {
            lt: bits(F4::lt),
            gt: bits(F4::gt),
            nan: bits(|x, _| x.eq(x).flipped()),
        }
    }

    /// The first face in `order` whose products along its outward cycle are none `< 0` (an edge run
    /// backwards flips the sign) and not all zero; where `nan_fails`, none NaN either.
    #[inline(always)]
    fn first_face(self, mut order: impl Iterator<Item = usize>, nan_fails: bool) -> Option<usize> {
        let nan = if nan_fails { self.nan } else { 0 };
        let (forward_fails, backward_fails) = (self.lt | nan, self.gt | nan);
        let nonzero = self.lt | self.gt | self.nan;
        order.find(|&f| {
            let (forward, backward, all) = FACE_SIGNS[f];
            forward_fails & forward == 0 && backward_fails & backward == 0 && nonzero & all != 0
        })
    }

    /// Scalar triple products' test, faces 3 to 0: the first whose products are none `< 0` and
    /// not all zero (a NaN passes).
    #[inline(always)]
    pub(super) fn stp_exit(self) -> Option<usize> {
        self.first_face((0..4).rev(), false)
    }
}

/// The ray's [`side`] products with the six edges of `tet`, four at a time ([`edge_ends`]).
#[inline(always)]
fn sides_of_tet<A: Arith>(ray: &PluckerRay, tet: &Tet) -> [F4; 2] {
    let [(a, b), (c, d)] = edge_ends(V4::of(tet));
    [sides4::<A>(ray, a, b), sides4::<A>(ray, c, d)]
}

/// Per face, the edges its outward cycle runs forward and those it runs backward, and all three.
const FACE_SIGNS: [(u32, u32, u32); 4] = {
    let mut t = [(0, 0, 0); 4];
    let mut f = 0;
    while f < 4 {
        let v = FACE_VERTICES[f];
        let mut k = 0;
        while k < 3 {
            let (e, rev) = EDGE_OF[v[k]][v[(k + 1) % 3]];
            if rev {
                t[f].1 |= 1 << e;
            } else {
                t[f].0 |= 1 << e;
            }
            t[f].2 |= 1 << e;
            k += 1;
        }
        f += 1;
    }
    t
};

/// Platis & Theoharis 2003 exit test over all four faces: face `f` is left when the side products
/// along its outward cycle are all `≥ 0` and not all zero (a NaN fails); the first such face in index
/// order.
#[inline(always)]
pub(super) fn exit_by_sides(s: EdgeSigns) -> Option<usize> {
    s.first_face(0..4, true)
}

/// The ray's side products with the six edges of `tet`, and the face [`exit_by_sides`] finds.
#[inline(always)]
pub(super) fn exit_by_sides_of<A: Arith>(ray: &PluckerRay, tet: &Tet) -> Option<usize> {
    exit_by_sides(EdgeSigns::of_lanes(sides_of_tet::<A>(ray, tet)))
}

/// Reconstructed: the six side products of the ray with the edges (6 × 23 = 138 operations, plus 9 for
/// the ray once; four at a time, lane by lane, [`edge_ends`]), then the face whose three edges
/// all turn the right way. The entry face is not used. `None` when no face passes.
pub struct Plucker;

impl ExitMethod for Plucker {
    type RayData = PluckerRay;

    fn prepare<A: Arith>(ray: &Ray) -> PluckerRay {
        plucker_ray::<A>(ray)
    }

    #[inline(always)]
    fn exit_face<A: Arith>(tet: &Tet, ray: &PluckerRay, _entry: Option<usize>) -> Option<usize> {
        exit_by_sides_of::<A>(ray, tet)
    }
}
