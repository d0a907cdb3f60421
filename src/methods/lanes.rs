//! Four f32 lanes: SSE (`std::arch`, part of every x86-64) where there is one, else four scalars; for
//! seed 004's SIMD packets (four rays) and the exit-face methods that compute the same step for every
//! face or edge of a tetrahedron (four faces, six edges in two groups). Every operation is IEEE's, lane
//! by lane, as the scalar f32 one (no reciprocal estimates); multiply-adds go through
//! [`Arith::mad4`], each lane as [`Arith::mad`]. So code written in the scalar one's order answers bit
//! for bit as it does, in every model.

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
        #[inline(always)]
        pub fn splat(x: f32) -> F4 {
            F4(unsafe { _mm_set1_ps(x) })
        }
        #[inline(always)]
        pub fn new(a: [f32; 4]) -> F4 {
            F4(unsafe { _mm_set_ps(a[3], a[2], a[1], a[0]) })
        }
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
        #[inline(always)]
        pub fn lt(self, b: F4) -> M4 {
            M4(unsafe { _mm_cmplt_ps(self.0, b.0) })
        }
        #[inline(always)]
        pub fn le(self, b: F4) -> M4 {
            M4(unsafe { _mm_cmple_ps(self.0, b.0) })
        }
        #[inline(always)]
        pub fn gt(self, b: F4) -> M4 {
            M4(unsafe { _mm_cmpgt_ps(self.0, b.0) })
        }
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

    impl M4 {
        #[inline(always)]
        pub fn and(self, b: M4) -> M4 {
            M4(unsafe { _mm_and_ps(self.0, b.0) })
        }
        #[inline(always)]
        pub fn or(self, b: M4) -> M4 {
            M4(unsafe { _mm_or_ps(self.0, b.0) })
        }
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
        pub fn splat(x: f32) -> F4 {
            F4([x; 4])
        }
        pub fn new(a: [f32; 4]) -> F4 {
            F4(a)
        }
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
        pub fn eq(self, b: F4) -> M4 {
            test(self.0, b.0, |x, y| x == y)
        }
        pub fn lt(self, b: F4) -> M4 {
            test(self.0, b.0, |x, y| x < y)
        }
        pub fn le(self, b: F4) -> M4 {
            test(self.0, b.0, |x, y| x <= y)
        }
        pub fn gt(self, b: F4) -> M4 {
            test(self.0, b.0, |x, y| x > y)
        }
        pub fn ge(self, b: F4) -> M4 {
            test(self.0, b.0, |x, y| x >= y)
        }
    }

    impl M4 {
        pub fn and(self, b: M4) -> M4 {
            M4(std::array::from_fn(|i| self.0[i] && b.0[i]))
        }
        pub fn or(self, b: M4) -> M4 {
            M4(std::array::from_fn(|i| self.0[i] || b.0[i]))
        }
        pub fn flipped(self) -> M4 {
            M4(self.0.map(|x| !x))
        }
        pub fn bits(self) -> u32 {
            (0..4).map(|i| (self.0[i] as u32) << i).sum()
        }
    }
}

#[cfg(target_arch = "x86_64")]
pub(crate) use imp::fma_instruction;
pub use imp::{F4, M4};

/// One f32 or four lanes of them: what code written once for both ([`crate::methods::aman20`]'s
/// projections) computes with.
pub trait Lane: Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> {
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

impl Add for F4 {
    type Output = F4;
    #[inline(always)]
    fn add(self, b: F4) -> F4 {
        F4::add(self, b)
    }
}
impl Sub for F4 {
    type Output = F4;
    #[inline(always)]
    fn sub(self, b: F4) -> F4 {
        F4::sub(self, b)
    }
}
impl Mul for F4 {
    type Output = F4;
    #[inline(always)]
    fn mul(self, b: F4) -> F4 {
        F4::mul(self, b)
    }
}
impl Div for F4 {
    type Output = F4;
    #[inline(always)]
    fn div(self, b: F4) -> F4 {
        F4::div(self, b)
    }
}
impl Neg for F4 {
    type Output = F4;
    #[inline(always)]
    fn neg(self) -> F4 {
        F4::neg(self)
    }
}

/// Four vectors, one per lane (structure of arrays).
#[derive(Clone, Copy)]
pub struct V4 {
    pub x: F4,
    pub y: F4,
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
}
