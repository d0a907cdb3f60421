//! `plucker`: Lagae & Dutré 2008's third method (seed 000 §2.3.2), the permuted inner products of
//! Platis & Theoharis 2003: six side products of the ray with the six edges.

use super::lanes::{Eight, V4, V8};
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

/// The two ends of the six edges ([`EDGES`]) of a tetrahedron whose vertices are in lanes, in the
/// first six of eight lanes (the last two repeat edge 5).
#[inline(always)]
pub(super) fn edge_ends<A: Arith>(v: V4) -> (V8<A>, V8<A>) {
    const fn ends(k: usize) -> [u32; 8] {
        let mut out = [0; 8];
        let mut i = 0;
        while i < 8 {
            out[i] = EDGES[if i < 5 { i } else { 5 }][k] as u32;
            i += 1;
        }
        out
    }
    (
        V8::pick(v, const { ends(0) }),
        V8::pick(v, const { ends(1) }),
    )
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
    pub(super) fn of_lanes<E: Eight>(x: E) -> EdgeSigns {
        let [lt, gt, nan] = x.signs().map(|bits| bits & 0b11_1111);
        EdgeSigns { lt, gt, nan }
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

/// The ray's [`side`] products with the six edges of `tet`, all in lanes ([`edge_ends`]), each as
/// [`side`] computes it.
#[inline(always)]
fn sides_of_tet<A: Arith>(ray: &PluckerRay, tet: &Tet) -> A::Eight {
    let (a, b) = edge_ends::<A>(V4::of(tet));
    let moment = a.cross(b);
    let dir = b - a;
    let v = V8::<A>::splat(ray.v);
    A::mad8(
        v.z,
        dir.z,
        A::mad8(
            v.y,
            dir.y,
            A::mad8(v.x, dir.x, V8::splat(ray.u).dot(moment)),
        ),
    )
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
/// the ray once; all six in lanes, lane by lane, `edge_ends`), then the face whose three edges
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
