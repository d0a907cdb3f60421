//! Four f32 lanes for seed 004's SIMD packets: SSE (`std::arch`, part of every x86-64) where there is
//! one, else four scalars. Every operation is IEEE's, lane by lane, as the scalar f32 one (no
//! reciprocal estimates, no fused multiply-add), so a 4-wide method written in the scalar one's order
//! answers bit for bit as it does in the plain model.

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
        /// The sign bit flipped, as scalar negation does (also of a zero and a NaN).
        #[inline(always)]
        pub(super) fn neg(self) -> F4 {
            F4(unsafe { _mm_xor_ps(self.0, _mm_set1_ps(-0.0)) })
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

pub use imp::{F4, M4};

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

    /// `a·b`, summed left to right as [`crate::methods::Arith::dot`] in the plain model.
    #[inline(always)]
    pub fn dot(self, b: V4) -> F4 {
        self.z * b.z + (self.y * b.y + self.x * b.x)
    }

    /// `a × b` as [`crate::methods::Arith::cross`] in the plain model: `a_j·b_k + -(a_k·b_j)`.
    #[inline(always)]
    pub fn cross(self, b: V4) -> V4 {
        V4 {
            x: self.y * b.z + -(self.z * b.y),
            y: self.z * b.x + -(self.x * b.z),
            z: self.x * b.y + -(self.y * b.x),
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
