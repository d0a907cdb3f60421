//! `certified`: tetwalk's own method — Maria et al.'s decision tree (Algorithm 1, Tables 1 and 2)
//! with every side product's sign certified: computed in f32 with a forward error bound, and decided
//! exactly (f64 filter, then exact arithmetic, ties broken by the same Simulation of Simplicity as
//! `exact`) only where the bound cannot settle it. Its walks therefore follow the perturbed line of the
//! `exact` walk, terminate, and end where it ends. The f32 stage's bound holds for every finite f32
//! input in each arithmetic model (gradual underflow, flushed to zero, a GPU's): its derivation, term
//! by term as the code computes it, is `certified.md` beside this file, checked in part by z3
//! (`proofs/certified/`).

use super::maria17::{FACE_VERTICES, GET_FACE};
use super::plucker::{EdgeSigns, exit_by_sides};
use super::{Arith, Exact, ExitMethod};
use crate::tet::{EDGE_OF, Ray, Tet};
use glam::{Vec3, Vec3A, Vec3Swizzles};

/// The f32 stage's error bound for one arithmetic model: a side product `det` computed as
/// [`f32_stage`] computes it has the sign of the exact one whenever
/// `|det| > a · permanent + c`, the permanent computed with every `|p1| + |p2|` raised by `mu`
/// (derivation in the module's text, `certified.md` beside this file).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bound {
    /// The relative part, `8u` (u the model's unit roundoff): covers `G = γ7/((1-u)^5 (1-γ3))`.
    pub a: f32,
    /// Added to each `|p1| + |p2|`: carries the absolute error of underflowed products (and of flushed
    /// sums) in `w`, which the side product multiplies by `|e|`, into the permanent.
    pub mu: f32,
    /// The absolute part: the underflow of the side product's own products and sums.
    pub c: f32,
}

/// 2^k as an f32 (k within the normal range).
const fn two_to(k: i32) -> f32 {
    f32::from_bits(((127 + k) as u32) << 23)
}

/// Gradual underflow, round to nearest (`cpu`, `cpu-fma`): u = 2^-24, a product's absolute error
/// η× ≤ 2^-150, a sum's η± = 0 (a difference that underflows is exact).
pub const GRADUAL: Bound = Bound {
    a: two_to(-21),
    mu: two_to(-126),
    c: two_to(-126),
};

/// Subnormals flushed to zero, round to nearest (`cpu-ftz`): u = 2^-24, η× = η± = 2^-126, inputs gated
/// (`tiny`).
pub const FLUSHING: Bound = Bound {
    a: two_to(-21),
    mu: two_to(-102),
    c: two_to(-122),
};

/// A GPU (WGSL, `certified.wgsl`): any rounding within one ulp (u = 2^-23), flushed or not,
/// contracted to fused multiply-adds or not, η× = η± = 2^-126, inputs gated.
pub const GPU: Bound = Bound {
    a: two_to(-20),
    mu: two_to(-102),
    c: two_to(-122),
};

/// Where subnormals may be flushed, a nonzero input coordinate below this magnitude (or a subnormal
/// direction component) sends the case to the exact stage: above it, the difference of two inputs is
/// zero or normal, so it is never flushed.
pub const TINY: f32 = two_to(-102);

/// Whether a nonzero coordinate of `v` lies below `limit` in magnitude (on the bits: a flushing
/// processor compares a subnormal as zero).
#[inline(always)]
fn below(v: Vec3, limit: f32) -> bool {
    v.to_array().iter().any(|x| {
        let b = x.to_bits() & 0x7fff_ffff;
        b != 0 && b < limit.to_bits()
    })
}

/// Whether a point is too near zero for the flushing model's bound (see [`TINY`]).
#[inline(always)]
fn tiny(v: Vec3) -> bool {
    below(v, TINY)
}

/// The exact stage: the sign of `det[a - o, b - o, d]` (f64 filter, then exact arithmetic),
/// computed in the standard floating-point environment whatever the model.
#[cold]
#[inline(never)]
fn exact_side(a: Vec3, b: Vec3, ray: &Ray) -> i8 {
    crate::fpenv::standard((a, b, ray), |(a, b, ray)| crate::exact::side(a, b, ray))
}

/// The ray, prepared once: origin and direction as SIMD vectors.
#[derive(Clone, Copy, Debug)]
pub struct CertifiedRay {
    org: Vec3A,
    dir: Vec3A,
}

impl CertifiedRay {
    fn ray(&self) -> Ray {
        Ray {
            org: self.org.into(),
            dir: self.dir.into(),
        }
    }
}

/// The bound of arithmetic model `A` (a constant).
#[inline(always)]
fn bound<A: Arith>() -> Bound {
    if A::FLUSHES { FLUSHING } else { GRADUAL }
}

/// Side products with edges ending at `b`: `det[a - o, b - o, d] = (a - b) · ((b - o) × d)`, the cross
/// product `w` (and `m`, the magnitudes of its products raised by `mu`, for the permanent) computed
/// once for every `a` (as Maria et al.'s translated moment is computed once per tetrahedron).
struct Apex {
    b: Vec3A,
    w: Vec3A,
    m: Vec3A,
}

impl Apex {
    #[inline(always)]
    fn new(b: Vec3, r: &CertifiedRay, bound: Bound) -> Apex {
        let b = Vec3A::from(b);
        let (q, d) = (b - r.org, r.dir);
        // w = q × d, each component the difference of two products; m = |p1| + |p2| + mu.
        let p1 = q.yzx() * d.zxy();
        let p2 = q.zxy() * d.yzx();
        Apex {
            b,
            w: p1 - p2,
            m: (p1.abs() + p2.abs()) + Vec3A::splat(bound.mu),
        }
    }

    /// The f32 stage: the sign of the side product of the ray with the edge `a → b` when it clears
    /// its error bound; `None` when it does not, or is not finite (NaN fails the comparison, and so
    /// does an infinite bound).
    #[inline(always)]
    fn settled(&self, a: Vec3, bound: Bound) -> Option<i8> {
        let e = Vec3A::from(a) - self.b;
        let det = e.dot(self.w);
        let permanent = e.abs().dot(self.m);
        let bound = bound.a * permanent + bound.c;
        // Branch on whether the sign is settled (nearly always), never on the sign itself, which is as
        // likely one way as the other (Maria et al.'s tree is branch-free for the same reason).
        (det.abs() > bound).then(|| (det > 0.0) as i8 * 2 - 1)
    }

    /// The f32 stage for the three vertices `tet[lambda[k]]` of the entry face at once, one lane each
    /// (the same operations as [`Apex::settled`], lane by lane): bit `k` of the first mask set where
    /// vertex `k`'s sign is settled, of the second where it is positive. (Each lane is read from the
    /// tetrahedron itself: gathering the vertices into an array first made a store-forwarding stall.)
    #[inline(always)]
    fn entry_face(&self, tet: &Tet, lambda: [usize; 3], bound: Bound) -> (u32, u32) {
        let lanes = |f: fn(&Vec3) -> f32| {
            Vec3A::new(f(&tet[lambda[0]]), f(&tet[lambda[1]]), f(&tet[lambda[2]]))
        };
        let ex = lanes(|p| p.x) - Vec3A::splat(self.b.x);
        let ey = lanes(|p| p.y) - Vec3A::splat(self.b.y);
        let ez = lanes(|p| p.z) - Vec3A::splat(self.b.z);
        let det = ex * self.w.x + ey * self.w.y + ez * self.w.z;
        let permanent = ex.abs() * self.m.x + ey.abs() * self.m.y + ez.abs() * self.m.z;
        let bound = permanent * bound.a + Vec3A::splat(bound.c);
        // A settled det is nonzero, so its sign bit is its sign.
        (det.abs().cmpgt(bound).bitmask(), !det.is_negative_bitmask())
    }
}

/// Lane `k`'s sign of `det[a - o, b - o, d]`, certified, from [`Apex::entry_face`]'s masks: the f32
/// stage's where it settled, else the exact sign — 0, a tie, when it is exactly zero (the line meets
/// the edge, or is parallel to it).
#[inline(always)]
fn lane_sign((settled, above): (u32, u32), k: usize, a: Vec3, b: Vec3, r: &CertifiedRay) -> i8 {
    if settled >> k & 1 == 1 {
        (above >> k & 1) as i8 * 2 - 1
    } else {
        exact_side(a, b, &r.ray())
    }
}

/// The f32 stage alone, for checking it against the exact sign: `det[a - o, b - o, d]`'s sign when
/// `bound` settles it, computed in the caller's floating-point environment; where `gated`, `None` for
/// inputs the flushing models send to the exact stage ([`TINY`]).
pub fn f32_stage(a: Vec3, b: Vec3, ray: &Ray, bound: Bound, gated: bool) -> Option<i8> {
    let r = CertifiedRay {
        org: ray.org.into(),
        dir: ray.dir.into(),
    };
    let gate = gated && gated_inputs(ray, &[a, b]);
    (!gate)
        .then(|| Apex::new(b, &r, bound).settled(a, bound))
        .flatten()
}

/// Whether the flushing models send this ray's signs with these points to the exact stage: the
/// origin or a point has a nonzero coordinate below [`TINY`], or the direction a subnormal one.
#[inline(always)]
fn gated_inputs(ray: &Ray, points: &[Vec3]) -> bool {
    tiny(ray.org) || below(ray.dir, f32::MIN_POSITIVE) || points.iter().any(|&v| tiny(v))
}

/// Whether the f32 stage may settle this tetrahedron's signs for this ray: always with gradual
/// underflow; where subnormals may be flushed, unless the ray or a vertex is gated ([`TINY`]).
#[inline(always)]
fn settles<A: Arith>(tet: &Tet, r: &CertifiedRay) -> bool {
    !A::FLUSHES || !gated_inputs(&r.ray(), tet)
}

/// Algorithm 1 from entry face `e` with certified signs: the side products with `Λ = V_k V_f`
/// (`V_f` the complement vertex), `det[V_k - o, V_f - o, d]`; `None` at a tie (the line meets an edge
/// through `V_f`, so it may pass through a vertex of the entry face, where the given entry face and the
/// one the tie-breaking enters through can differ).
#[inline(always)]
fn algorithm_1<A: Arith>(tet: &Tet, r: &CertifiedRay, e: usize) -> Option<usize> {
    if !settles::<A>(tet, r) {
        return None;
    }
    let apex = Apex::new(tet[e], r, bound::<A>());
    let lambda = FACE_VERTICES[e];
    let masks @ (settled, positive) = apex.entry_face(tet, lambda, bound::<A>());
    if settled == 0b111 {
        // Every sign settled (nearly always): the tree without a branch.
        let id = (positive >> 2 & 1) as usize;
        return Some(GET_FACE[e][id + (positive >> id & 1 == 0) as usize]);
    }
    decision_tree(e, |k| lane_sign(masks, k, tet[lambda[k]], tet[e], r))
}

/// Maria et al.'s Algorithm 1 (Tables 1 and 2) from entry face `e`, given the sign of
/// `det[V_k - o, V_f - o, d]` for the vertex `V_k = λ_k` (`k` in 0..3, `λ` the entry face's
/// [`FACE_VERTICES`]); `None` at a zero sign (a tie).
#[inline(always)]
pub(super) fn decision_tree(e: usize, mut sign: impl FnMut(usize) -> i8) -> Option<usize> {
    let s = sign(2);
    if s == 0 {
        return None;
    }
    let id = (s > 0) as usize;
    let s = sign(id);
    if s == 0 {
        return None;
    }
    Some(GET_FACE[e][id + (s < 0) as usize])
}

/// The edges `[a, b]` of [`crate::tet::EDGES`] by their end `b` = 1, 2, 3: the ends `a` in lanes
/// (the last repeated), so that [`Apex::entry_face`] takes each apex's side products at once.
const BY_END: [[usize; 3]; 3] = [[0, 0, 0], [0, 1, 1], [0, 1, 2]];

/// The starting tetrahedron: all six certified signs, the face the perturbed line leaves through
/// (`None` at a tie, or when the perturbed line passes beside the tetrahedron).
#[inline(never)]
fn start<A: Arith>(tet: &Tet, r: &CertifiedRay) -> Option<usize> {
    if !settles::<A>(tet, r) {
        return None;
    }
    let (mut negative, mut positive) = (0, 0);
    for (b, ends) in (1..4).zip(BY_END) {
        let apex = Apex::new(tet[b], r, bound::<A>());
        let masks = apex.entry_face(tet, ends, bound::<A>());
        for (k, a) in ends.into_iter().enumerate().take(b) {
            let sign = lane_sign(masks, k, tet[a], tet[b], r);
            if sign == 0 {
                return None;
            }
            let edge = EDGE_OF[a][b].0;
            negative |= ((sign < 0) as u32) << edge;
            positive |= ((sign > 0) as u32) << edge;
        }
    }
    exit_by_sides(EdgeSigns::of_signs(negative, positive))
}

/// At a tie (or where the f32 stage may not settle): the exact answer, ties broken as `exact` breaks
/// them.
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
            org: ray.org.into(),
            dir: ray.dir.into(),
        }
    }

    /// Algorithm 1 with a known entry face (the face the perturbed line enters through, as in a walk).
    /// In the starting tetrahedron, where the origin may lie on the boundary and the perturbed line
    /// may pass beside it, all six signs instead (Platis & Theoharis' test) — once per walk. At a tie
    /// (a sign exactly zero), `exact`'s answer.
    #[inline(always)]
    fn exit_face<A: Arith>(tet: &Tet, r: &CertifiedRay, entry: Option<usize>) -> Option<usize> {
        match entry {
            Some(e) => algorithm_1::<A>(tet, r, e),
            None => start::<A>(tet, r),
        }
        .or_else(|| at_tie(tet, &r.ray()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::methods::{Flushed, Plain};

    /// Why the flushing model's gate exists, and that it holds: two points whose x coordinates are
    /// normal but differ by a subnormal (their difference flushed to zero), seen along a direction of
    /// 2^100, make the f32 stage settle a side product with the wrong sign when nothing gates them
    /// (`f32_stage` with the gate off); with the gate, and through `settles` (what the method
    /// checks before its f32 stage), that case goes to the exact stage. Points and rays above the
    /// gate settle; the model that does not flush settles everything.
    #[test]
    fn the_flushing_gate_sends_what_the_bound_cannot_cover_to_the_exact_stage() {
        let x = two_to(-125);
        let b = Vec3::new(x, 1.0, 0.0);
        // The ulp of 2^-125 is 2^-148 (a subnormal, made from its bits).
        let ulp = f32::from_bits(1 << 1);
        assert_eq!(ulp as f64, 2f64.powi(-148));
        let a = Vec3::new(x + 3.0 * ulp, 1.0 + f32::EPSILON, 0.0);
        let ray = Ray {
            org: Vec3::ZERO,
            dir: Vec3::new(0.0, 0.0, two_to(100)),
        };
        let exact = crate::exact::side(a, b, &ray);
        assert_eq!(exact, 1, "det = 3·2^-48 - 2^-48 > 0");
        let ungated = crate::fpenv::flushed((a, b, ray), |(a, b, ray)| {
            f32_stage(a, b, &ray, FLUSHING, false)
        });
        assert_eq!(
            ungated,
            Some(-1),
            "flushed and ungated, the f32 stage settles it wrongly"
        );
        let gated = crate::fpenv::flushed((a, b, ray), |(a, b, ray)| {
            f32_stage(a, b, &ray, FLUSHING, true)
        });
        assert_eq!(gated, None, "the gate leaves it to the exact stage");
        let tet = [a, b, Vec3::new(0.0, 2.0, 1.0), Vec3::new(1.0, 2.0, 0.0)];
        let r = Certified::prepare::<Flushed>(&ray);
        assert!(
            !settles::<Flushed>(&tet, &r),
            "a vertex below TINY is gated"
        );
        assert!(
            settles::<Plain>(&tet, &r),
            "gradual underflow needs no gate"
        );
        let normal = tet.map(|v| v + Vec3::ONE);
        assert!(
            settles::<Flushed>(&normal, &r),
            "above the gate the f32 stage settles"
        );
        let subnormal_dir = Certified::prepare::<Flushed>(&Ray {
            org: Vec3::ONE,
            dir: Vec3::new(1.0, f32::from_bits(1 << 9), 0.0),
        });
        assert!(
            !settles::<Flushed>(&normal, &subnormal_dir),
            "a subnormal direction is gated"
        );
        let tiny_org = Certified::prepare::<Flushed>(&Ray {
            org: Vec3::new(TINY / 2.0, 1.0, 1.0),
            dir: Vec3::X,
        });
        assert!(
            !settles::<Flushed>(&normal, &tiny_org),
            "a tiny origin is gated"
        );
    }
}
