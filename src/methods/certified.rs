//! `certified`: tetwalk's own method — Maria et al.'s decision tree (Algorithm 1, Tables 1 and 2)
//! with every side product's sign certified: computed in f32 with a forward error bound, and decided
//! exactly (f64 filter, then exact arithmetic, ties broken by the same Simulation of Simplicity as
//! `exact`) only where the bound cannot settle it. Its walks therefore follow the perturbed line of the
//! `exact` walk, terminate, and end where it ends.

use super::maria17::{FACE_VERTICES, GET_FACE};
use super::plucker::exit_by_sides;
use super::{Arith, Exact, ExitMethod};
use crate::tet::{EDGES, Ray, Tet};
use glam::{Vec3, Vec3A, Vec3Swizzles};
use std::cell::Cell;

/// Half an ulp of 1 in f32 (Shewchuk's ε for single precision).
const EPS: f32 = f32::EPSILON / 2.0;

/// Shewchuk 1997 (orient3d): `|fl(det) - det| ≤ O3DERRBOUND_A · permanent` for a 3×3 determinant whose
/// rows are rounded differences of inputs (here two, the third the exact direction), evaluated as a
/// row against the 2×2 minors of the other two, `permanent` the same with absolute values, barring
/// underflow and overflow. Here with ε = 2^-24.
pub const O3DERRBOUND_A: f32 = (7.0 + 56.0 * EPS) * EPS;

/// The absolute error underflow can add, per unit of `1 + max |d|`: the six products of the minors and
/// the three by `d` may each lose up to 2^-149 where they fall below f32's normal range; 2^-120 covers
/// them with room and is itself a normal number (arithmetic on subnormal constants is slow on x86).
pub const UNDERFLOW: f32 = 1.0 / (1u128 << 120) as f32;

thread_local! {
    static EXACT_SIGNS: Cell<u64> = const { Cell::new(0) };
}

/// How many side-product signs the exact stage decided on this thread so far (every other sign was
/// settled by the f32 stage; counting only this rare path keeps the fast one free of bookkeeping).
pub fn exact_signs() -> u64 {
    EXACT_SIGNS.with(Cell::get)
}

/// The exact stage: the sign of `det[a - o, b - o, d]` (f64 filter, then exact arithmetic), counted.
#[cold]
#[inline(never)]
fn exact_side(a: Vec3, b: Vec3, ray: &Ray) -> i8 {
    EXACT_SIGNS.with(|c| c.set(c.get() + 1));
    crate::exact::side(a, b, ray)
}

/// The ray, prepared once: origin, direction, and the underflow term of the error bound.
#[derive(Clone, Copy, Debug)]
pub struct CertifiedRay {
    ray: Ray,
    org: Vec3A,
    dir: Vec3A,
    underflow: f32,
}

/// Side products with edges ending at `b`: `det[a - o, b - o, d] = (a - b) · ((b - o) × d)`, the cross
/// product `w` (and the absolute values its error bound needs, `m`) computed once for every `a` (as
/// Maria et al.'s translated moment is computed once per tetrahedron).
struct Apex {
    b: Vec3A,
    w: Vec3A,
    m: Vec3A,
}

impl Apex {
    #[inline(always)]
    fn new(b: Vec3, r: &CertifiedRay) -> Apex {
        let b = Vec3A::from(b);
        let (q, d) = (b - r.org, r.dir);
        // w = q × d, each component the difference of two products, m the sum of their magnitudes.
        let p1 = q.yzx() * d.zxy();
        let p2 = q.zxy() * d.yzx();
        Apex {
            b,
            w: p1 - p2,
            m: p1.abs() + p2.abs(),
        }
    }

    /// Sign of the side product of the ray with the edge `a → b`, certified: the f32 value when it
    /// clears its error bound, else the exact sign — 0, a tie, when it is exactly zero (the line meets
    /// the edge, or is parallel to it).
    #[inline(always)]
    fn side(&self, a: Vec3, r: &CertifiedRay) -> i8 {
        let e = Vec3A::from(a) - self.b;
        let det = e.dot(self.w);
        let permanent = e.abs().dot(self.m);
        let bound = O3DERRBOUND_A * permanent + r.underflow;
        // Branch on whether the sign is settled (nearly always), never on the sign itself, which is as
        // likely one way as the other (Maria et al.'s tree is branch-free for the same reason).
        if det.abs() > bound {
            (det > 0.0) as i8 * 2 - 1
        } else {
            // Not settled, or not finite: decide exactly; 0 is a tie.
            exact_side(a, self.b.into(), &r.ray)
        }
    }
}

/// Algorithm 1 from entry face `e` with certified signs: the side products with `Λ = V_k V_f`
/// (`V_f` the complement vertex), `det[V_k - o, V_f - o, d]`; `None` at a tie (the line meets an edge
/// through `V_f`, so it may pass through a vertex of the entry face, where the given entry face and the
/// one the tie-breaking enters through can differ).
#[inline(always)]
fn algorithm_1(tet: &Tet, r: &CertifiedRay, e: usize) -> Option<usize> {
    let apex = Apex::new(tet[e], r);
    decision_tree(tet, e, |a| apex.side(a, r))
}

/// Maria et al.'s Algorithm 1 (Tables 1 and 2) from entry face `e`, given the sign of
/// `det[V_k - o, V_f - o, d]` for a vertex `V_k` of the entry face; `None` at a zero sign (a tie).
#[inline(always)]
pub(super) fn decision_tree(
    tet: &Tet,
    e: usize,
    mut sign: impl FnMut(Vec3) -> i8,
) -> Option<usize> {
    let lambda = FACE_VERTICES[e];
    let s = sign(tet[lambda[2]]);
    if s == 0 {
        return None;
    }
    let id = (s > 0) as usize;
    let s = sign(tet[lambda[id]]);
    if s == 0 {
        return None;
    }
    Some(GET_FACE[e][id + (s < 0) as usize])
}

/// The starting tetrahedron: all six certified signs, the face the perturbed line leaves through
/// (`None` at a tie, or when the perturbed line passes beside the tetrahedron).
#[inline(never)]
fn start(tet: &Tet, r: &CertifiedRay) -> Option<usize> {
    let apex: [Apex; 4] = std::array::from_fn(|b| Apex::new(tet[b], r));
    let sides = EDGES.map(|[a, b]| apex[b].side(tet[a], r) as f32);
    if sides.contains(&0.0) {
        None
    } else {
        exit_by_sides(&sides)
    }
}

/// At a tie: the exact answer, ties broken as `exact` breaks them.
#[cold]
#[inline(never)]
fn at_tie(tet: &Tet, ray: &Ray) -> Option<usize> {
    Exact::exit_face::<super::Plain>(tet, ray, None)
}

/// Maria et al.'s method with certified signs. Where an edge is parallel to the ray (a sign that no
/// perturbation of the origin moves off zero), the answer is `exact`'s.
pub struct Certified;

impl ExitMethod for Certified {
    type RayData = CertifiedRay;
    const LANES: usize = 4;

    fn prepare<A: Arith>(ray: &Ray) -> CertifiedRay {
        CertifiedRay {
            ray: *ray,
            org: ray.org.into(),
            dir: ray.dir.into(),
            underflow: UNDERFLOW * (1.0 + ray.dir.abs().max_element()),
        }
    }

    /// Algorithm 1 with a known entry face (the face the perturbed line enters through, as in a walk).
    /// In the starting tetrahedron, where the origin may lie on the boundary and the perturbed line
    /// may pass beside it, all six signs instead (Platis & Theoharis' test) — once per walk. At a tie
    /// (a sign exactly zero), `exact`'s answer.
    fn exit_face<A: Arith>(tet: &Tet, r: &CertifiedRay, entry: Option<usize>) -> Option<usize> {
        match entry {
            Some(e) => algorithm_1(tet, r, e),
            None => start(tet, r),
        }
        .or_else(|| at_tie(tet, &r.ray))
    }
}
