//! Exit-face methods: plain functions over plain data behind one small trait (registered once, in
//! the `registry` module), each beside its WGSL twin (`NAME.wgsl`).
//!
//! Every method is written once, generic over [`Arith`]: [`Plain`] rounds every product and sum as
//! written (what a CPU compiler emits), [`Fused`] contracts each `a·b + c` into one fused multiply-add
//! (what a GPU shader compiler may emit). Contractions applied by [`Fused`]: in [`Arith::dot`] the second
//! and third products are fused into the running sum; in [`Arith::cross`] the first product of each
//! component is fused with the negated second one; in [`Arith::axpy`] each product with its sum; and
//! wherever a method calls [`Arith::mad`]. Nothing else is contracted. [`Flushed`] rounds as
//! [`Plain`] does, with the processor set to read subnormal inputs as zero and flush subnormal results
//! to zero (the crate's `fpenv` module), as a GPU may compute; [`FusedFlushed`] does both at once, as
//! an NVIDIA GPU computes. The models are listed once (`crate::arithmetic_models!`). The plain and flushed models' work runs compiled
//! for AVX2 where the processor has it (`fpenv::wide`: the same IEEE operations, fewer
//! register copies; the registry runs the plain model's exit-face methods as `PlainAvx2`, whose
//! eight lanes are one AVX register).
#![warn(missing_docs)]

pub mod aman20;
pub mod certified;
mod exact;
mod halfspace;
pub mod lanes;
pub mod maria17;
mod ms06;
mod plucker;
pub mod portalez16;
mod ray_plane;
mod stp;
pub mod triangle;

pub use aman20::{Aman20, Aman20Scaled};
pub use certified::Certified;
pub use exact::Exact;
pub use halfspace::HalfSpace;
pub use maria17::{Maria17, MomentFirst, OriginFirst};
pub use ms06::Ms06;
pub use plucker::Plucker;
pub use ray_plane::RayPlane;
pub use stp::Stp;

use crate::tet::{Ray, Tet};
use glam::Vec3;
use lanes::{Eight, F4};

/// Rounding of a method's arithmetic: as written, contracted to fused multiply-add, flushed, or both.
pub trait Arith {
    /// Whether subnormal inputs and results are flushed to zero (what a method's fast path must allow for).
    const FLUSHES: bool = false;
    /// Eight f32 lanes as this model computes them ([`lanes::Eight`]).
    type Eight: lanes::Eight;
    /// Whether this instantiation can run on this processor: a twin compiled for an instruction
    /// the processor may lack checks it (`TETWALK_NO_FMA`, `TETWALK_NO_AVX2` turn them off).
    #[doc(hidden)]
    #[inline(always)]
    fn available() -> bool {
        true
    }
    /// Run a method's work in this model's floating-point environment (the registry's entry points do).
    #[inline(always)]
    fn run<T, R>(input: T, f: impl FnOnce(T) -> R) -> R {
        f(input)
    }
    /// `a·b + c`.
    fn mad(a: f32, b: f32, c: f32) -> f32;
    /// [`Arith::mad`] in four lanes ([`lanes`]).
    #[inline(always)]
    fn mad4(a: F4, b: F4, c: F4) -> F4 {
        F4::mad_by_lane::<Self>(a, b, c)
    }
    /// [`Arith::mad`] in eight lanes, four at a time.
    #[inline(always)]
    fn mad8(a: Self::Eight, b: Self::Eight, c: Self::Eight) -> Self::Eight {
        let (a, b, c) = (a.halves(), b.halves(), c.halves());
        Eight::of_halves([0, 1].map(|k| Self::mad4(a[k], b[k], c[k])))
    }
    /// `a.x·b.x + a.y·b.y + a.z·b.z`, summed left to right.
    #[inline(always)]
    fn dot(a: Vec3, b: Vec3) -> f32 {
        Self::mad(a.z, b.z, Self::mad(a.y, b.y, a.x * b.x))
    }
    /// `s·a + b`, per component.
    #[inline(always)]
    fn axpy(s: f32, a: Vec3, b: Vec3) -> Vec3 {
        Vec3::new(
            Self::mad(a.x, s, b.x),
            Self::mad(a.y, s, b.y),
            Self::mad(a.z, s, b.z),
        )
    }
    /// `a × b`, each component `a_j·b_k - a_k·b_j`.
    #[inline(always)]
    fn cross(a: Vec3, b: Vec3) -> Vec3 {
        Vec3::new(
            Self::mad(a.y, b.z, -(a.z * b.y)),
            Self::mad(a.z, b.x, -(a.x * b.z)),
            Self::mad(a.x, b.y, -(a.y * b.x)),
        )
    }
}

pub use crate::choice::Model;

/// Every product and sum rounded separately.
pub struct Plain;
/// Products contracted into fused multiply-adds, as a GPU compiler may.
pub struct Fused;
/// Every product and sum rounded separately, subnormal inputs and results flushed to zero.
pub struct Flushed;
/// Products contracted into fused multiply-adds and subnormals flushed at once, as an NVIDIA GPU
/// computes (`cpu-gpu`): each operand of [`Arith::mad`] read as zero if subnormal, its result
/// flushed if below 2^-126 in magnitude; every other operation rounded as [`Flushed`] rounds it.
pub struct FusedFlushed;
/// [`FusedFlushed`] on the processor's FMA instruction, which flushes in the flushing environment;
/// the registry runs it only where the processor has FMA, as [`FusedFma`].
pub(crate) struct FusedFlushedFma;
/// [`Fused`] on the processor's FMA instruction: the same roundings, so the same bits, several times
/// faster than `f32::mul_add` without it (a library call). The registry runs the fused model in it
/// only where the processor has FMA ([`crate::fpenv::has_fma`]); nothing else may name it.
pub(crate) struct FusedFma;
/// [`Plain`] compiled for AVX2, its eight lanes one AVX register ([`lanes::F8`]): the same roundings,
/// so the same bits. The registry runs the plain model's exit-face methods in it only where the
/// processor has AVX2 ([`crate::fpenv::has_avx2`]); nothing else may name it.
pub(crate) struct PlainAvx2;

impl Arith for Plain {
    type Eight = lanes::F4x2;
    #[inline(always)]
    fn run<T, R>(input: T, f: impl FnOnce(T) -> R) -> R {
        crate::fpenv::wide(input, f)
    }
    #[inline(always)]
    fn mad(a: f32, b: f32, c: f32) -> f32 {
        a * b + c
    }
    #[inline(always)]
    fn mad4(a: F4, b: F4, c: F4) -> F4 {
        a * b + c
    }
}

impl Arith for Flushed {
    const FLUSHES: bool = true;
    type Eight = lanes::F4x2;
    #[inline(always)]
    fn run<T, R>(input: T, f: impl FnOnce(T) -> R) -> R {
        crate::fpenv::flushed(input, |input| crate::fpenv::wide(input, f))
    }
    #[inline(always)]
    fn mad(a: f32, b: f32, c: f32) -> f32 {
        a * b + c
    }
    #[inline(always)]
    fn mad4(a: F4, b: F4, c: F4) -> F4 {
        a * b + c
    }
}

#[cfg(target_arch = "x86_64")]
impl Arith for FusedFma {
    #[inline(always)]
    fn available() -> bool {
        crate::fpenv::has_fma()
    }
    type Eight = lanes::F4x2;
    #[inline(always)]
    fn run<T, R>(input: T, f: impl FnOnce(T) -> R) -> R {
        // SAFETY: the registry runs this model only where the processor has FMA.
        unsafe { crate::fpenv::with_fma(input, f) }
    }
    #[inline(always)]
    fn mad(a: f32, b: f32, c: f32) -> f32 {
        // SAFETY: as above.
        unsafe { crate::fpenv::fma_instruction(a, b, c) }
    }
    #[inline(always)]
    fn mad4(a: F4, b: F4, c: F4) -> F4 {
        // SAFETY: as above.
        unsafe { lanes::fma_instruction(a, b, c) }
    }
}

#[cfg(target_arch = "x86_64")]
impl Arith for PlainAvx2 {
    #[inline(always)]
    fn available() -> bool {
        crate::fpenv::has_avx2()
    }
    type Eight = lanes::F8;
    #[inline(always)]
    fn run<T, R>(input: T, f: impl FnOnce(T) -> R) -> R {
        // SAFETY: the registry runs this model only where the processor has AVX2.
        unsafe { crate::fpenv::with_avx2(input, f) }
    }
    #[inline(always)]
    fn mad(a: f32, b: f32, c: f32) -> f32 {
        Plain::mad(a, b, c)
    }
    #[inline(always)]
    fn mad4(a: F4, b: F4, c: F4) -> F4 {
        Plain::mad4(a, b, c)
    }
    #[inline(always)]
    fn mad8(a: lanes::F8, b: lanes::F8, c: lanes::F8) -> lanes::F8 {
        a * b + c
    }
}

/// Off x86-64 the plain model has no second instantiation: [`Plain`]'s.
#[cfg(not(target_arch = "x86_64"))]
impl Arith for PlainAvx2 {
    #[inline(always)]
    fn available() -> bool {
        crate::fpenv::has_avx2()
    }
    type Eight = lanes::F4x2;
    #[inline(always)]
    fn mad(a: f32, b: f32, c: f32) -> f32 {
        Plain::mad(a, b, c)
    }
}

/// Off x86-64 the fused model has no second instantiation: [`Fused`]'s.
#[cfg(not(target_arch = "x86_64"))]
impl Arith for FusedFma {
    #[inline(always)]
    fn available() -> bool {
        crate::fpenv::has_fma()
    }
    type Eight = lanes::F4x2;
    #[inline(always)]
    fn mad(a: f32, b: f32, c: f32) -> f32 {
        Fused::mad(a, b, c)
    }
}

impl Arith for Fused {
    type Eight = lanes::F4x2;
    #[inline(always)]
    fn mad(a: f32, b: f32, c: f32) -> f32 {
        a.mul_add(b, c)
    }
}

/// `x`, or a zero of its sign where it is subnormal (as a flushing GPU reads and writes it).
#[inline(always)]
fn flush(x: f32) -> f32 {
    if x.abs() < f32::MIN_POSITIVE {
        0f32.copysign(x)
    } else {
        x
    }
}

impl Arith for FusedFlushed {
    const FLUSHES: bool = true;
    type Eight = lanes::F4x2;
    #[inline(always)]
    fn run<T, R>(input: T, f: impl FnOnce(T) -> R) -> R {
        crate::fpenv::flushed(input, f)
    }
    #[inline(always)]
    fn mad(a: f32, b: f32, c: f32) -> f32 {
        flush(flush(a).mul_add(flush(b), flush(c)))
    }
}

#[cfg(target_arch = "x86_64")]
impl Arith for FusedFlushedFma {
    #[inline(always)]
    fn available() -> bool {
        FusedFma::available()
    }
    const FLUSHES: bool = true;
    type Eight = lanes::F4x2;
    #[inline(always)]
    fn run<T, R>(input: T, f: impl FnOnce(T) -> R) -> R {
        crate::fpenv::flushed(input, |input| FusedFma::run(input, f))
    }
    #[inline(always)]
    fn mad(a: f32, b: f32, c: f32) -> f32 {
        FusedFma::mad(a, b, c)
    }
    #[inline(always)]
    fn mad4(a: F4, b: F4, c: F4) -> F4 {
        FusedFma::mad4(a, b, c)
    }
}

/// Off x86-64 the fused, flushed model has no second instantiation (never available).
#[cfg(not(target_arch = "x86_64"))]
impl Arith for FusedFlushedFma {
    #[inline(always)]
    fn available() -> bool {
        false
    }
    const FLUSHES: bool = true;
    type Eight = lanes::F4x2;
    #[inline(always)]
    fn mad(a: f32, b: f32, c: f32) -> f32 {
        FusedFlushed::mad(a, b, c)
    }
}

/// An exit-face method: per-ray data computed once, then one call per tetrahedron.
pub trait ExitMethod {
    /// What the method precomputes once per ray (e.g. the Plücker moment).
    type RayData: Copy + Send + Sync;
    /// Walks one thread advances in turn (in the walk module's `walks`, which caps it): several where the decision has no sign-dependent branch, so the
    /// walks' latencies overlap; one where it branches on signs, which one coherent walk predicts well
    /// and interleaved walks do not.
    const LANES: usize = 1;
    /// The per-ray data, computed once in arithmetic model `A`.
    fn prepare<A: Arith>(ray: &Ray) -> Self::RayData;
    /// The face (0..4, opposite that vertex) through which the ray leaves the positively oriented
    /// tetrahedron, knowing the face it entered through (`None` in the starting tetrahedron); `None`
    /// when the method finds no exit face.
    fn exit_face<A: Arith>(tet: &Tet, ray: &Self::RayData, entry: Option<usize>) -> Option<usize>;
}

/// An octree cell method (seed 001's family): per-ray data computed once, then one call per cell.
pub trait CellMethod {
    /// What the method precomputes once per ray.
    type RayData: Copy + Send + Sync;
    /// The per-ray data, computed once in arithmetic model `A`.
    fn prepare<A: Arith>(ray: &Ray) -> Self::RayData;
    /// The face (0..6, numbered as [`crate::octree::cell`] states) through which the ray leaves the
    /// box `[lo, hi]` and the quarter of it (the neighbour index among four); `None` when the method
    /// finds no exit face.
    fn exit<A: Arith>(lo: Vec3, hi: Vec3, ray: &Self::RayData) -> Option<(usize, usize)>;
}

/// `a.map(f)` for the methods' small arrays, always inlined: `std`'s `map` and `from_fn` may be
/// compiled apart, and the fused model's FMA instruction reaches only what its walk inlines
/// (`crate::fpenv::with_fma`).
#[inline(always)]
pub(crate) fn each<T: Copy, U: Copy + Default, const N: usize>(
    a: [T; N],
    mut f: impl FnMut(T) -> U,
) -> [U; N] {
    let mut out = [U::default(); N];
    for k in 0..N {
        out[k] = f(a[k]);
    }
    out
}

/// Whether a face is left, from the signs along its outward cycle (side products or projected
/// determinants): all `≥ 0` and not all zero (Platis & Theoharis' test).
#[inline(always)]
pub(crate) fn leaves(s: &[f32; 3]) -> bool {
    s.iter().all(|&x| x >= 0.0) && s.iter().any(|&x| x != 0.0)
}

/// One exit-face query of a batch: a tetrahedron (by index), a ray, and its entry face.
pub type Query = (u32, Ray, Option<usize>);

/// Time `M`'s exit-face search over `queries` (seed 000 Table 5's measure): the per-ray data prepared
/// first, once per ray and untimed, then every query answered in one loop, statically dispatched; the
/// best of `repeats` runs in seconds, and a checksum of the answers.
pub fn time_queries<M: ExitMethod, A: Arith>(
    tets: &[Tet],
    queries: &[Query],
    repeats: usize,
) -> (f64, usize) {
    let prepared: Vec<(u32, M::RayData, Option<usize>)> = queries
        .iter()
        .map(|(t, r, e)| (*t, M::prepare::<A>(r), *e))
        .collect();
    let mut best = f64::INFINITY;
    let mut sum = 0;
    for _ in 0..repeats.max(1) {
        let t0 = std::time::Instant::now();
        sum = 0;
        for (t, data, e) in &prepared {
            let tet = &tets[*t as usize];
            sum += M::exit_face::<A>(std::hint::black_box(tet), data, *e).map_or(4, |f| f);
        }
        best = best.min(t0.elapsed().as_secs_f64());
    }
    (best, std::hint::black_box(sum))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The fused, flushed model's two instantiations round alike ([`FusedFlushed`] portable,
    /// [`FusedFlushedFma`] on the FMA instruction in the flushing environment), and flush, on operands
    /// from every exponent regime (`fpenv::mad_operands`).
    #[test]
    fn fused_flushed_twins_round_alike_and_flush() {
        if !crate::fpenv::FLUSH_AVAILABLE || !FusedFlushedFma::available() {
            eprintln!(
                "SKIPPED: no FMA instruction or flushing mode here; the model has one instantiation"
            );
            return;
        }
        let ops = crate::fpenv::mad_operands(0x2545_f491_4f6c_dd1d);
        let portable: Vec<f32> = FusedFlushed::run(&ops, |ops| {
            ops.iter()
                .map(|&(a, b, c)| FusedFlushed::mad(a, b, c))
                .collect()
        });
        let twin: Vec<f32> = FusedFlushedFma::run(&ops, |ops| {
            ops.iter()
                .map(|&(a, b, c)| FusedFlushedFma::mad(a, b, c))
                .collect()
        });
        for ((op, p), t) in ops.iter().zip(&portable).zip(&twin) {
            assert!(
                p.to_bits() == t.to_bits() || (p.is_nan() && t.is_nan()),
                "{op:?}: portable {p:e} ({:#x}), FMA instruction {t:e} ({:#x})",
                p.to_bits(),
                t.to_bits()
            );
            assert!(!p.is_subnormal(), "{op:?}: {p:e} is not flushed");
        }
    }
}
