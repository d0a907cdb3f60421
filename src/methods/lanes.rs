//! Four f32 lanes: SSE (`std::arch`, part of every x86-64) where there is one, else four scalars; for
//! seed 004's SIMD packets (four rays) and the exit-face methods that compute the same step for every
//! face or vertex of a tetrahedron. Eight lanes ([`Eight`], for the six edges at once): two groups of
//! four, or one AVX register in the model compiled for AVX2 (`PlainAvx2`). Every operation is IEEE's,
//! lane by lane, as the scalar f32 one (no reciprocal estimates); multiply-adds go through
//! [`Arith::mad4`] and [`Arith::mad8`], each lane as [`Arith::mad`]. So code written in the scalar
//! one's order answers bit for bit as it does, in every model.

use crate::methods::Arith;
use glam::Vec3;
use std::ops::{Add, Div, Mul, Neg, Sub};

#[cfg(target_arch = "x86_64")]
mod imp {
    //! SAFETY, for every `unsafe` here but the store: the intrinsics need only SSE and SSE2, which
    //! every x86-64 target enables (they are the architecture's baseline).
    use std::arch::x86_64::*;

    /// Four f32 lanes.
    #[derive(Clone, Copy)]
    pub struct F4(pub(super) __m128);
    /// Four lanes' comparison results (all bits set where true).
    #[derive(Clone, Copy)]
    pub struct M4(__m128);

    impl F4 {
        /// Every lane `x`.
        #[inline(always)]
        pub fn splat(x: f32) -> F4 {
            F4(unsafe { _mm_set1_ps(x) })
        }
        /// Lane `i` holds `a[i]`.
        #[inline(always)]
        pub fn new(a: [f32; 4]) -> F4 {
            F4(unsafe { _mm_set_ps(a[3], a[2], a[1], a[0]) })
        }
        /// The lanes, lane 0 first.
        #[inline(always)]
        pub fn to_array(self) -> [f32; 4] {
            let mut out = [0.0f32; 4];
            // SAFETY: `out` holds four f32, the unaligned store writes exactly those 16 bytes.
            unsafe { _mm_storeu_ps(out.as_mut_ptr(), self.0) };
            out
        }
        #[inline(always)]
        pub(super) fn add(self, b: F4) -> F4 {
            F4(unsafe { _mm_add_ps(self.0, b.0) })
        }
        #[inline(always)]
        pub(super) fn sub(self, b: F4) -> F4 {
            F4(unsafe { _mm_sub_ps(self.0, b.0) })
        }
        #[inline(always)]
        pub(super) fn mul(self, b: F4) -> F4 {
            F4(unsafe { _mm_mul_ps(self.0, b.0) })
        }
        #[inline(always)]
        pub(super) fn div(self, b: F4) -> F4 {
            F4(unsafe { _mm_div_ps(self.0, b.0) })
        }
        /// The sign bit flipped, as scalar negation does (also of a zero and a NaN): lane by lane,
        /// so that the compiler sees a negation and folds `a + -b` into `a - b` (the same bits).
        #[inline(always)]
        pub(super) fn neg(self) -> F4 {
            F4::new(self.to_array().map(|x| -x))
        }
        /// Less, lane by lane, as scalar `<` (false where either is a NaN).
        #[inline(always)]
        pub fn lt(self, b: F4) -> M4 {
            M4(unsafe { _mm_cmplt_ps(self.0, b.0) })
        }
        /// Less or equal, as scalar `<=`.
        #[inline(always)]
        pub fn le(self, b: F4) -> M4 {
            M4(unsafe { _mm_cmple_ps(self.0, b.0) })
        }
        /// Greater, as scalar `>`.
        #[inline(always)]
        pub fn gt(self, b: F4) -> M4 {
            M4(unsafe { _mm_cmpgt_ps(self.0, b.0) })
        }
        /// Greater or equal, as scalar `>=`.
        #[inline(always)]
        pub fn ge(self, b: F4) -> M4 {
            M4(unsafe { _mm_cmpge_ps(self.0, b.0) })
        }
        /// Equal, as scalar `==` (false where either is a NaN).
        #[inline(always)]
        pub fn eq(self, b: F4) -> M4 {
            M4(unsafe { _mm_cmpeq_ps(self.0, b.0) })
        }
    }

    /// `(a, b, c, d)`: lanes `a, b` of a shuffle's first operand, `c, d` of its second.
    const fn order(a: i32, b: i32, c: i32, d: i32) -> i32 {
        a | b << 2 | c << 4 | d << 6
    }

    /// The x, y and z lanes of four points stored one after the other.
    #[inline(always)]
    pub(super) fn transpose(v: &[glam::Vec3; 4]) -> [F4; 3] {
        const _: () = assert!(std::mem::size_of::<[glam::Vec3; 4]>() == 48);
        let p = v.as_ptr() as *const f32;
        // SAFETY: glam's `Vec3` is three f32 (`repr(C)`, checked above: 48 bytes for four), so the
        // three unaligned 16-byte loads read exactly the twelve coordinates; then SSE shuffles.
        unsafe {
            // x0 y0 z0 x1 | y1 z1 x2 y2 | z2 x3 y3 z3
            let (r0, r1, r2) = (
                _mm_loadu_ps(p),
                _mm_loadu_ps(p.add(4)),
                _mm_loadu_ps(p.add(8)),
            );
            let x2x3 = _mm_shuffle_ps::<{ order(2, 2, 1, 1) }>(r1, r2);
            let x = _mm_shuffle_ps::<{ order(0, 3, 0, 2) }>(r0, x2x3);
            let y0y1 = _mm_shuffle_ps::<{ order(1, 1, 0, 0) }>(r0, r1);
            let y2y3 = _mm_shuffle_ps::<{ order(3, 3, 2, 2) }>(r1, r2);
            let y = _mm_shuffle_ps::<{ order(0, 2, 0, 2) }>(y0y1, y2y3);
            let z0z1 = _mm_shuffle_ps::<{ order(2, 2, 1, 1) }>(r0, r1);
            let z = _mm_shuffle_ps::<{ order(0, 2, 0, 3) }>(z0z1, r2);
            [F4(x), F4(y), F4(z)]
        }
    }

    /// `a·b + c` in every lane, rounded once by the FMA instruction, inline in code compiled for it
    /// (`crate::fpenv::with_fma`).
    ///
    /// # Safety
    /// The processor must have FMA (`crate::fpenv::has_fma`).
    #[target_feature(enable = "fma")]
    #[inline]
    pub(crate) unsafe fn fma_instruction(a: F4, b: F4, c: F4) -> F4 {
        F4(_mm_fmadd_ps(a.0, b.0, c.0))
    }

    /// Eight f32 lanes in one AVX register: the eight-lane type of the model compiled for AVX2 alone.
    ///
    /// SAFETY, for every `unsafe` of it: only `PlainAvx2` names it, whose work runs compiled for AVX2
    /// (`crate::fpenv::with_avx2`) and only where the processor has it; so each intrinsic is inlined
    /// into AVX2 code.
    #[derive(Clone, Copy)]
    pub struct F8(__m256);

    impl F8 {
        #[inline(always)]
        pub(super) fn splat(x: f32) -> F8 {
            F8(unsafe { _mm256_set1_ps(x) })
        }
        #[inline(always)]
        pub(super) fn pick(v: F4, from: [u32; 8]) -> F8 {
            let i = from.map(|i| i as i32);
            unsafe {
                let index = _mm256_setr_epi32(i[0], i[1], i[2], i[3], i[4], i[5], i[6], i[7]);
                F8(_mm256_permutevar8x32_ps(_mm256_castps128_ps256(v.0), index))
            }
        }
        #[inline(always)]
        pub(super) fn halves(self) -> [F4; 2] {
            unsafe {
                [
                    F4(_mm256_castps256_ps128(self.0)),
                    F4(_mm256_extractf128_ps::<1>(self.0)),
                ]
            }
        }
        #[inline(always)]
        pub(super) fn of_halves([lo, hi]: [F4; 2]) -> F8 {
            F8(unsafe { _mm256_set_m128(hi.0, lo.0) })
        }
        #[inline(always)]
        pub(super) fn add(self, b: F8) -> F8 {
            F8(unsafe { _mm256_add_ps(self.0, b.0) })
        }
        #[inline(always)]
        pub(super) fn sub(self, b: F8) -> F8 {
            F8(unsafe { _mm256_sub_ps(self.0, b.0) })
        }
        #[inline(always)]
        pub(super) fn mul(self, b: F8) -> F8 {
            F8(unsafe { _mm256_mul_ps(self.0, b.0) })
        }
        /// The sign bit flipped, as scalar negation does.
        #[inline(always)]
        pub(super) fn neg(self) -> F8 {
            F8(unsafe { _mm256_xor_ps(self.0, _mm256_set1_ps(-0.0)) })
        }
        /// Bit sets of the lanes `< 0`, `> 0` and NaN.
        #[inline(always)]
        pub(super) fn signs(self) -> [u32; 3] {
            unsafe {
                let zero = _mm256_setzero_ps();
                [
                    _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LT_OQ>(self.0, zero)) as u32,
                    _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_GT_OQ>(self.0, zero)) as u32,
                    _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_UNORD_Q>(self.0, self.0)) as u32,
                ]
            }
        }
    }

    impl M4 {
        /// True where both are.
        #[inline(always)]
        pub fn and(self, b: M4) -> M4 {
            M4(unsafe { _mm_and_ps(self.0, b.0) })
        }
        /// True where either is.
        #[inline(always)]
        pub fn or(self, b: M4) -> M4 {
            M4(unsafe { _mm_or_ps(self.0, b.0) })
        }
        /// True where this is false.
        #[inline(always)]
        pub fn flipped(self) -> M4 {
            M4(unsafe { _mm_xor_ps(self.0, _mm_castsi128_ps(_mm_set1_epi32(-1))) })
        }
        /// Bit `i` set where lane `i` is true.
        #[inline(always)]
        pub fn bits(self) -> u32 {
            unsafe { _mm_movemask_ps(self.0) as u32 }
        }
    }
}

#[cfg(not(target_arch = "x86_64"))]
mod imp {
    /// Four f32 lanes.
    #[derive(Clone, Copy)]
    pub struct F4(pub(super) [f32; 4]);
    /// Four lanes' comparison results.
    #[derive(Clone, Copy)]
    pub struct M4([bool; 4]);

    fn each(a: [f32; 4], b: [f32; 4], f: impl Fn(f32, f32) -> f32) -> F4 {
        F4(std::array::from_fn(|i| f(a[i], b[i])))
    }
    fn test(a: [f32; 4], b: [f32; 4], f: impl Fn(f32, f32) -> bool) -> M4 {
        M4(std::array::from_fn(|i| f(a[i], b[i])))
    }

    impl F4 {
        /// Every lane `x`.
        pub fn splat(x: f32) -> F4 {
            F4([x; 4])
        }
        /// Lane `i` holds `a[i]`.
        pub fn new(a: [f32; 4]) -> F4 {
            F4(a)
        }
        /// The lanes, lane 0 first.
        pub fn to_array(self) -> [f32; 4] {
            self.0
        }
        pub(super) fn add(self, b: F4) -> F4 {
            each(self.0, b.0, |x, y| x + y)
        }
        pub(super) fn sub(self, b: F4) -> F4 {
            each(self.0, b.0, |x, y| x - y)
        }
        pub(super) fn mul(self, b: F4) -> F4 {
            each(self.0, b.0, |x, y| x * y)
        }
        pub(super) fn div(self, b: F4) -> F4 {
            each(self.0, b.0, |x, y| x / y)
        }
        pub(super) fn neg(self) -> F4 {
            F4(self.0.map(|x| -x))
        }
        /// Equal, as scalar `==` (false where either is a NaN).
        pub fn eq(self, b: F4) -> M4 {
            test(self.0, b.0, |x, y| x == y)
        }
        /// Less, lane by lane, as scalar `<` (false where either is a NaN).
        pub fn lt(self, b: F4) -> M4 {
            test(self.0, b.0, |x, y| x < y)
        }
        /// Less or equal, as scalar `<=`.
        pub fn le(self, b: F4) -> M4 {
            test(self.0, b.0, |x, y| x <= y)
        }
        /// Greater, as scalar `>`.
        pub fn gt(self, b: F4) -> M4 {
            test(self.0, b.0, |x, y| x > y)
        }
        /// Greater or equal, as scalar `>=`.
        pub fn ge(self, b: F4) -> M4 {
            test(self.0, b.0, |x, y| x >= y)
        }
    }

    impl M4 {
        /// True where both are.
        pub fn and(self, b: M4) -> M4 {
            M4(std::array::from_fn(|i| self.0[i] && b.0[i]))
        }
        /// True where either is.
        pub fn or(self, b: M4) -> M4 {
            M4(std::array::from_fn(|i| self.0[i] || b.0[i]))
        }
        /// True where this is false.
        pub fn flipped(self) -> M4 {
            M4(self.0.map(|x| !x))
        }
        /// Bit `i` set where lane `i` is true.
        pub fn bits(self) -> u32 {
            (0..4).map(|i| (self.0[i] as u32) << i).sum()
        }
    }
}

pub use imp::{F4, M4};
#[cfg(target_arch = "x86_64")]
pub(crate) use imp::{F8, fma_instruction};

/// One f32 or four lanes of them: what code written once for both ([`crate::methods::aman20`]'s
/// projections) computes with.
pub trait Lane: Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> {
    /// Every lane `x`.
    fn splat(x: f32) -> Self;
    /// `a·b + c` as [`Arith::mad`] rounds it, lane by lane.
    fn mad<A: Arith>(a: Self, b: Self, c: Self) -> Self;
}

/// `a·b` as [`Arith::dot`] computes it, over one f32 or four lanes.
#[inline(always)]
pub fn dot<A: Arith, L: Lane>(a: [L; 3], b: [L; 3]) -> L {
    L::mad::<A>(a[2], b[2], L::mad::<A>(a[1], b[1], a[0] * b[0]))
}

impl Lane for f32 {
    #[inline(always)]
    fn splat(x: f32) -> f32 {
        x
    }
    #[inline(always)]
    fn mad<A: Arith>(a: f32, b: f32, c: f32) -> f32 {
        A::mad(a, b, c)
    }
}

impl Lane for F4 {
    #[inline(always)]
    fn splat(x: f32) -> F4 {
        F4::splat(x)
    }
    #[inline(always)]
    fn mad<A: Arith>(a: F4, b: F4, c: F4) -> F4 {
        A::mad4(a, b, c)
    }
}

impl F4 {
    /// Lane `i` holds this one's lane `from[i]`.
    #[inline(always)]
    pub fn pick(self, from: [usize; 4]) -> F4 {
        let a = self.to_array();
        F4::new([a[from[0]], a[from[1]], a[from[2]], a[from[3]]])
    }

    /// `a·b + c` in every lane, each rounded as [`Arith::mad`] rounds it (the models' default).
    #[inline(always)]
    pub fn mad_by_lane<A: Arith + ?Sized>(a: F4, b: F4, c: F4) -> F4 {
        let (a, b, c) = (a.to_array(), b.to_array(), c.to_array());
        F4::new([
            A::mad(a[0], b[0], c[0]),
            A::mad(a[1], b[1], c[1]),
            A::mad(a[2], b[2], c[2]),
            A::mad(a[3], b[3], c[3]),
        ])
    }
}

/// The operators of a lane type, each its inherent operation of the same name.
macro_rules! lane_ops {
    ($t:ty: $($tr:ident $f:ident),*) => {
        $(impl $tr for $t {
            type Output = $t;
            #[inline(always)]
            fn $f(self, b: $t) -> $t {
                <$t>::$f(self, b)
            }
        })*
        impl Neg for $t {
            type Output = $t;
            #[inline(always)]
            fn neg(self) -> $t {
                <$t>::neg(self)
            }
        }
    };
}

lane_ops!(F4: Add add, Sub sub, Mul mul, Div div);
#[cfg(target_arch = "x86_64")]
lane_ops!(F8: Add add, Sub sub, Mul mul);
lane_ops!(F4x2: Add add, Sub sub, Mul mul);

/// Four vectors, one per lane (structure of arrays).
#[derive(Clone, Copy)]
pub struct V4 {
    /// The lanes' x coordinates.
    pub x: F4,
    /// The lanes' y coordinates.
    pub y: F4,
    /// The lanes' z coordinates.
    pub z: F4,
}

impl V4 {
    /// One vector in every lane.
    #[inline(always)]
    pub fn splat(v: Vec3) -> V4 {
        V4 {
            x: F4::splat(v.x),
            y: F4::splat(v.y),
            z: F4::splat(v.z),
        }
    }

    /// Lane `i` holds `v[i]`.
    #[inline(always)]
    pub fn new(v: [Vec3; 4]) -> V4 {
        V4 {
            x: F4::new(v.map(|p| p.x)),
            y: F4::new(v.map(|p| p.y)),
            z: F4::new(v.map(|p| p.z)),
        }
    }

    /// [`V4::new`] of four points in memory (a tetrahedron's vertices): on x86-64 three 16-byte loads
    /// and seven shuffles instead of twelve loads and their inserts.
    #[inline(always)]
    pub fn of(v: &[Vec3; 4]) -> V4 {
        #[cfg(target_arch = "x86_64")]
        {
            let [x, y, z] = imp::transpose(v);
            V4 { x, y, z }
        }
        #[cfg(not(target_arch = "x86_64"))]
        V4::new(*v)
    }

    /// Lane `i` holds this one's lane `from[i]`.
    #[inline(always)]
    pub fn pick(self, from: [usize; 4]) -> V4 {
        V4 {
            x: self.x.pick(from),
            y: self.y.pick(from),
            z: self.z.pick(from),
        }
    }

    /// `a·b` as [`Arith::dot`] computes it, in every lane.
    #[inline(always)]
    pub fn dot<A: Arith>(self, b: V4) -> F4 {
        dot::<A, F4>([self.x, self.y, self.z], [b.x, b.y, b.z])
    }

    /// `a × b` as [`Arith::cross`] computes it, in every lane.
    #[inline(always)]
    pub fn cross<A: Arith>(self, b: V4) -> V4 {
        V4 {
            x: A::mad4(self.y, b.z, -(self.z * b.y)),
            y: A::mad4(self.z, b.x, -(self.x * b.z)),
            z: A::mad4(self.x, b.y, -(self.y * b.x)),
        }
    }

    /// `s·a + b` as [`Arith::axpy`] computes it, in every lane.
    #[inline(always)]
    pub fn axpy<A: Arith>(s: F4, a: V4, b: V4) -> V4 {
        V4 {
            x: A::mad4(a.x, s, b.x),
            y: A::mad4(a.y, s, b.y),
            z: A::mad4(a.z, s, b.z),
        }
    }
}

impl Sub for V4 {
    type Output = V4;
    #[inline(always)]
    fn sub(self, b: V4) -> V4 {
        V4 {
            x: self.x - b.x,
            y: self.y - b.y,
            z: self.z - b.z,
        }
    }
}

/// Eight f32 lanes, as a model computes them ([`Arith::Eight`]).
pub trait Eight:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Neg<Output = Self>
{
    /// Every lane `x`.
    fn splat(x: f32) -> Self;
    /// Lane `i` holds lane `from[i]` of `v`.
    fn pick(v: F4, from: [u32; 8]) -> Self;
    /// Lanes 0 to 3, and 4 to 7.
    fn halves(self) -> [F4; 2];
    /// Lanes 0 to 3 from `h[0]`, 4 to 7 from `h[1]`.
    fn of_halves(h: [F4; 2]) -> Self;
    /// Bit sets of the lanes `< 0`, `> 0` and NaN.
    fn signs(self) -> [u32; 3];
}

/// Eight lanes as two groups of four.
#[derive(Clone, Copy)]
pub struct F4x2([F4; 2]);

impl F4x2 {
    #[inline(always)]
    fn each(self, b: F4x2, f: impl Fn(F4, F4) -> F4) -> F4x2 {
        F4x2([f(self.0[0], b.0[0]), f(self.0[1], b.0[1])])
    }
    #[inline(always)]
    fn add(self, b: F4x2) -> F4x2 {
        self.each(b, |x, y| x + y)
    }
    #[inline(always)]
    fn sub(self, b: F4x2) -> F4x2 {
        self.each(b, |x, y| x - y)
    }
    #[inline(always)]
    fn mul(self, b: F4x2) -> F4x2 {
        self.each(b, |x, y| x * y)
    }
    #[inline(always)]
    fn neg(self) -> F4x2 {
        F4x2(self.0.map(|x| -x))
    }
}

impl Eight for F4x2 {
    #[inline(always)]
    fn splat(x: f32) -> F4x2 {
        F4x2([F4::splat(x); 2])
    }
    #[inline(always)]
    fn pick(v: F4, from: [u32; 8]) -> F4x2 {
        let half = |k: usize| v.pick(std::array::from_fn(|i| from[4 * k + i] as usize));
        F4x2([half(0), half(1)])
    }
    #[inline(always)]
    fn halves(self) -> [F4; 2] {
        self.0
    }
    #[inline(always)]
    fn of_halves(h: [F4; 2]) -> F4x2 {
        F4x2(h)
    }
    #[inline(always)]
    fn signs(self) -> [u32; 3] {
        let zero = F4::splat(0.0);
        let bits = |test: fn(F4, F4) -> M4| {
            test(self.0[0], zero).bits() | test(self.0[1], zero).bits() << 4
        };
        [bits(F4::lt), bits(F4::gt), bits(|x, _| x.eq(x).flipped())]
    }
}

#[cfg(target_arch = "x86_64")]
impl Eight for F8 {
    #[inline(always)]
    fn splat(x: f32) -> F8 {
        F8::splat(x)
    }
    #[inline(always)]
    fn pick(v: F4, from: [u32; 8]) -> F8 {
        F8::pick(v, from)
    }
    #[inline(always)]
    fn halves(self) -> [F4; 2] {
        F8::halves(self)
    }
    #[inline(always)]
    fn of_halves(h: [F4; 2]) -> F8 {
        F8::of_halves(h)
    }
    #[inline(always)]
    fn signs(self) -> [u32; 3] {
        F8::signs(self)
    }
}

/// Eight vectors, one per lane, in model `A`'s eight lanes.
pub struct V8<A: Arith> {
    /// The lanes' x coordinates.
    pub x: A::Eight,
    /// The lanes' y coordinates.
    pub y: A::Eight,
    /// The lanes' z coordinates.
    pub z: A::Eight,
}

impl<A: Arith> Clone for V8<A> {
    #[inline(always)]
    fn clone(&self) -> Self {
        *self
    }
}
impl<A: Arith> Copy for V8<A> {}

impl<A: Arith> V8<A> {
    /// One vector in every lane.
    #[inline(always)]
    pub fn splat(v: Vec3) -> Self {
        V8 {
            x: A::Eight::splat(v.x),
            y: A::Eight::splat(v.y),
            z: A::Eight::splat(v.z),
        }
    }

    /// Lane `i` holds lane `from[i]` of `v`.
    #[inline(always)]
    pub fn pick(v: V4, from: [u32; 8]) -> Self {
        V8 {
            x: A::Eight::pick(v.x, from),
            y: A::Eight::pick(v.y, from),
            z: A::Eight::pick(v.z, from),
        }
    }

    /// `a·b` as [`Arith::dot`] computes it, in every lane.
    #[inline(always)]
    pub fn dot(self, b: Self) -> A::Eight {
        A::mad8(self.z, b.z, A::mad8(self.y, b.y, self.x * b.x))
    }

    /// `a × b` as [`Arith::cross`] computes it, in every lane.
    #[inline(always)]
    pub fn cross(self, b: Self) -> Self {
        V8 {
            x: A::mad8(self.y, b.z, -(self.z * b.y)),
            y: A::mad8(self.z, b.x, -(self.x * b.z)),
            z: A::mad8(self.x, b.y, -(self.y * b.x)),
        }
    }
}

impl<A: Arith> Sub for V8<A> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, b: Self) -> Self {
        V8 {
            x: self.x - b.x,
            y: self.y - b.y,
            z: self.z - b.z,
        }
    }
}

/// Lane by lane: `Some(t)` where `hit` holds.
#[inline(always)]
pub fn answers(hit: M4, t: F4, out: &mut [Option<f32>]) {
    let (bits, t) = (hit.bits(), t.to_array());
    for (i, o) in out.iter_mut().enumerate() {
        *o = (bits >> i & 1 == 1).then_some(t[i]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Four points read from memory in three loads land in the lanes [`V4::new`] puts them in, bit
    /// for bit (NaN payloads and signed zeros included).
    #[test]
    fn of_transposes_as_new() {
        let bits = |v: V4| [v.x, v.y, v.z].map(|l| l.to_array().map(f32::to_bits));
        let p: [Vec3; 4] = std::array::from_fn(|i| {
            let i = i as u32;
            Vec3::new(
                i as f32 + 0.25,
                f32::from_bits(0x8000_0000 | i),
                f32::from_bits(0x7fc0_0001 + i),
            )
        });
        assert_eq!(bits(V4::of(&p)), bits(V4::new(p)));
    }

    /// Every operation of `E` on lanes picked from `v` (as bits, every NaN as one: IEEE 754 leaves to
    /// the implementation which operand's payload a two-NaN operation keeps, and the compiler may order
    /// a commutative operation's operands either way, as an opt-level 1 build does), and the sign sets
    /// of `v[0]` and `v[3]` put in eight lanes.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn computed<E: Eight>(
        v: &[[f32; 4]; 4],
        from: [u32; 8],
        mad: impl Fn(E, E, E) -> E,
    ) -> ([[u32; 8]; 6], [u32; 3]) {
        let [a, b, c, d] = v.map(|x| E::pick(F4::new(x), from));
        let e = E::of_halves([F4::new(v[0]), F4::new(v[3])]);
        let bits = |x: E| {
            let [lo, hi] = x.halves().map(F4::to_array);
            std::array::from_fn(|i| {
                let x = if i < 4 { lo[i] } else { hi[i - 4] };
                if x.is_nan() { f32::NAN } else { x }.to_bits()
            })
        };
        (
            [a + b, a - c, b * d, -d, mad(a, b, c), e].map(bits),
            e.signs(),
        )
    }

    /// One AVX register's eight lanes ([`F8`], the plain model's compiled for AVX2) compute as two
    /// groups of four ([`F4x2`], every other model's), bit for bit: each operation, the picks the
    /// six edges use, the multiply-add and the sign sets, on values from every exponent regime (signed
    /// zeros, subnormals, overflow, infinities, NaN).
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn one_avx_register_computes_as_two_groups_of_four() {
        use crate::methods::{Arith, Plain, PlainAvx2};
        if !PlainAvx2::available() {
            eprintln!(
                "SKIPPED: no AVX2 here (or TETWALK_NO_AVX2=1): the plain model has no eight-lane register"
            );
            return;
        }
        let specials = [
            0.0,
            -0.0,
            1e-45,
            -3e-39,
            1.5,
            -2.5e-20,
            3e38,
            -f32::INFINITY,
            f32::NAN,
        ];
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            if state.is_multiple_of(4) {
                specials[(state >> 8) as usize % specials.len()]
            } else {
                f32::from_bits((state >> 16) as u32)
            }
        };
        for _ in 0..20_000 {
            let v: [[f32; 4]; 4] = std::array::from_fn(|_| std::array::from_fn(|_| next()));
            let from: [u32; 8] = std::array::from_fn(|_| next().to_bits() % 4);
            let wide = PlainAvx2::run(&v, |v| computed::<F8>(v, from, PlainAvx2::mad8));
            let pair = computed::<F4x2>(&v, from, Plain::mad8);
            assert_eq!(wide, pair, "{v:?} {from:?}");
            let lanes = [v[0], v[3]].concat();
            let set =
                |test: fn(f32) -> bool| (0..8).map(|i| (test(lanes[i]) as u32) << i).sum::<u32>();
            let signs = [set(|x| x < 0.0), set(|x| x > 0.0), set(f32::is_nan)];
            assert_eq!(pair.1, signs, "{lanes:?}");
        }
    }
}
