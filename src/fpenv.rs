//! The floating-point environment of the calling thread: the flush-to-zero model (`cpu-ftz`, as a GPU
//! may compute) runs a method with subnormal inputs read as zero and subnormal results flushed to zero
//! by the processor itself, and the oracle always computes in the standard environment.
//!
//! x86-64: MXCSR's FTZ (bit 15, results) and DAZ (bit 6, inputs); AArch64: FPCR's FZ (bit 24, both).
//! The compiler assumes the standard environment, so each switch passes the work's input and result
//! through [`std::hint::black_box`]: nothing is computed across a switch.

use std::hint::black_box;

/// Whether this processor can run the flush-to-zero model.
pub(crate) const FLUSH_AVAILABLE: bool = cfg!(any(target_arch = "x86_64", target_arch = "aarch64"));

#[cfg(target_arch = "x86_64")]
mod reg {
    pub(crate) const FLUSH: u64 = (1 << 15) | (1 << 6);
    #[inline(always)]
    pub(crate) fn read() -> u64 {
        let mut csr: u32 = 0;
        // SAFETY: stores MXCSR into a local.
        unsafe { std::arch::asm!("stmxcsr [{}]", in(reg) &mut csr, options(nostack)) };
        csr as u64
    }
    #[inline(always)]
    pub(crate) fn write(v: u64) {
        let csr = v as u32;
        // SAFETY: loads MXCSR from a local holding a valid value (only the flush bits changed).
        unsafe { std::arch::asm!("ldmxcsr [{}]", in(reg) &csr, options(nostack)) };
    }
}

#[cfg(target_arch = "aarch64")]
mod reg {
    pub(crate) const FLUSH: u64 = 1 << 24;
    #[inline(always)]
    pub(crate) fn read() -> u64 {
        let v: u64;
        // SAFETY: reads FPCR.
        unsafe { std::arch::asm!("mrs {}, fpcr", out(reg) v, options(nostack)) };
        v
    }
    #[inline(always)]
    pub(crate) fn write(v: u64) {
        // SAFETY: writes FPCR with only the flush bit changed.
        unsafe { std::arch::asm!("msr fpcr, {}", in(reg) v, options(nostack)) };
    }
}

#[cfg(not(any(target_arch = "x86_64", target_arch = "aarch64")))]
mod reg {
    pub(crate) const FLUSH: u64 = 0;
    pub(crate) fn read() -> u64 {
        0
    }
    pub(crate) fn write(_: u64) {}
}

/// Restores the caller's environment when dropped, also when the work panics.
struct Restore(u64);

impl Drop for Restore {
    #[inline(always)]
    fn drop(&mut self) {
        reg::write(self.0);
    }
}

/// Run `f(input)` with the flush bits set to `flush`, restoring the caller's environment after.
#[inline(always)]
fn with<T, R>(flush: bool, input: T, f: impl FnOnce(T) -> R) -> R {
    let saved = reg::read();
    let want = if flush {
        saved | reg::FLUSH
    } else {
        saved & !reg::FLUSH
    };
    if want == saved {
        return f(input);
    }
    reg::write(want);
    let restore = Restore(saved);
    let out = black_box(f(black_box(input)));
    drop(restore);
    out
}

/// `f(input)` with subnormal inputs and results flushed to zero (the `cpu-ftz` model).
#[inline(always)]
pub fn flushed<T, R>(input: T, f: impl FnOnce(T) -> R) -> R {
    with(true, input, f)
}

/// `f(input)` in the standard environment (gradual underflow), whatever the caller's: the oracle's
/// filters widen f32 inputs and must read a subnormal as itself.
#[inline(always)]
pub(crate) fn standard<T, R>(input: T, f: impl FnOnce(T) -> R) -> R {
    with(false, input, f)
}

/// A processor feature the models' code may be compiled for.
#[derive(Clone, Copy)]
enum Feature {
    Fma,
    Avx2,
}

/// Whether `feature` is used: x86-64 with it (checked at run time), unless the environment turns it
/// off (`TETWALK_NO_FMA=1`, `TETWALK_NO_AVX2=1`: for comparing the code with and without it, which
/// answer alike). Decided once per process.
fn used(feature: Feature) -> bool {
    static USED: [std::sync::OnceLock<bool>; 2] = [const { std::sync::OnceLock::new() }; 2];
    *USED[feature as usize].get_or_init(|| {
        let off = match feature {
            Feature::Fma => "TETWALK_NO_FMA",
            Feature::Avx2 => "TETWALK_NO_AVX2",
        };
        #[cfg(target_arch = "x86_64")]
        let detected = match feature {
            Feature::Fma => std::arch::is_x86_feature_detected!("fma"),
            Feature::Avx2 => std::arch::is_x86_feature_detected!("avx2"),
        };
        #[cfg(not(target_arch = "x86_64"))]
        let detected = false;
        std::env::var_os(off).is_none_or(|v| v != "1") && detected
    })
}

/// Whether the fused model runs on the processor's fused multiply-add instruction (FMA3; without it
/// `f32::mul_add`, a library call: the same answers, slower).
pub(crate) fn has_fma() -> bool {
    used(Feature::Fma)
}

/// Whether the plain and flushed models run in code compiled for AVX2 ([`wide`]; the plain model's
/// exit-face methods as `crate::methods::PlainAvx2`, eight lanes in one register; without it SSE2's
/// encoding: the same answers).
pub fn has_avx2() -> bool {
    used(Feature::Avx2)
}

/// `f(input)` compiled, as far as it inlines, for AVX2 where the processor has it ([`has_avx2`]),
/// else as it is: the same IEEE operations lane by lane (nothing is contracted into a fused
/// multiply-add: that takes the FMA feature, which this does not enable), encoded with three
/// operands, so with fewer register copies.
#[inline(always)]
pub(crate) fn wide<T, R>(input: T, f: impl FnOnce(T) -> R) -> R {
    #[cfg(target_arch = "x86_64")]
    if has_avx2() {
        // SAFETY: the processor has AVX2, checked just above.
        return unsafe { with_avx2(input, f) };
    }
    f(input)
}

/// `f(input)` compiled, as far as it inlines, for AVX2.
///
/// # Safety
/// The processor must have AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
pub(crate) unsafe fn with_avx2<T, R>(input: T, f: impl FnOnce(T) -> R) -> R {
    f(input)
}

/// `a·b + c` rounded once by the FMA instruction: inline in code compiled for it ([`with_fma`]),
/// a call to one instruction elsewhere.
///
/// # Safety
/// The processor must have FMA ([`has_fma`]).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "fma")]
#[inline]
pub(crate) unsafe fn fma_instruction(a: f32, b: f32, c: f32) -> f32 {
    a.mul_add(b, c)
}

/// `f(input)` compiled, as far as it inlines, for the FMA instruction.
///
/// # Safety
/// The processor must have FMA ([`has_fma`]).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "fma")]
#[inline]
pub(crate) unsafe fn with_fma<T, R>(input: T, f: impl FnOnce(T) -> R) -> R {
    f(input)
}

/// 200,000 operand triples `(a, b, c)` for `a·b + c` from `seed`: every exponent regime (subnormal to
/// near overflow, mixed in one operation), signed zeros, infinities and NaN, addends that cancel the
/// product's leading bits, and sums near 2^-126, where flushing decides.
#[cfg(test)]
pub(crate) fn mad_operands(seed: u64) -> Vec<(f32, f32, f32)> {
    let mut state = seed;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    let special = [
        0.0,
        -0.0,
        f32::MIN_POSITIVE,
        1e-45,
        f32::MAX,
        f32::INFINITY,
        f32::NAN,
    ];
    // Sign and mantissa from `r`, any finite exponent (0: subnormal or zero); or a special.
    let x = |r: u64| {
        if r.is_multiple_of(16) {
            special[(r >> 8) as usize % special.len()]
        } else {
            f32::from_bits((r as u32 & 0x807f_ffff) | (((r >> 40) as u32 % 255) << 23))
        }
    };
    (0..200_000)
        .map(|_| {
            let (a, b) = (x(next()), x(next()));
            let c = match next() % 4 {
                0 => x(next()),
                1 => -(a * b) * f32::from_bits(0x3f80_0000 + (next() % 64) as u32),
                2 => f32::from_bits(0x0080_0000 + (next() % 2048) as u32 - 1024) - a * b,
                _ => -(a * b),
            };
            (a, b, c)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The fused model's two instantiations round alike (`methods::Fused`, `methods::FusedFma`):
    /// the FMA instruction, inline and called, against `f32::mul_add` without it, on operands from
    /// every exponent regime ([`mad_operands`]).
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn hardware_fma_rounds_as_the_library_fma() {
        let ops = mad_operands(0x9e37_79b9_7f4a_7c15);
        let library: Vec<u32> = ops
            .iter()
            .map(|&(a, b, c)| std::hint::black_box(a).mul_add(b, c).to_bits())
            .collect();
        if !std::arch::is_x86_feature_detected!("fma") {
            eprintln!(
                "SKIPPED: this processor has no FMA instruction; the fused model uses mul_add"
            );
            return;
        }
        // SAFETY: the processor has FMA (checked above).
        let inside: Vec<u32> = unsafe {
            with_fma(&ops, |ops| {
                ops.iter()
                    .map(|&(a, b, c)| a.mul_add(b, c).to_bits())
                    .collect()
            })
        };
        // SAFETY: likewise.
        let called: Vec<u32> = ops
            .iter()
            .map(|&(a, b, c)| unsafe { fma_instruction(a, b, c) }.to_bits())
            .collect();
        for (((op, l), f), c) in ops.iter().zip(&library).zip(&inside).zip(&called) {
            let nan = |x: u32| f32::from_bits(x).is_nan();
            assert!(
                (l == f && l == c) || (nan(*l) && nan(*f) && nan(*c)),
                "{op:?}: mul_add {l:#x}, inline FMA {f:#x}, called FMA {c:#x}"
            );
        }
    }

    /// Whether the calling thread flushes subnormals now.
    fn flushing() -> bool {
        reg::FLUSH != 0 && reg::read() & reg::FLUSH == reg::FLUSH
    }

    #[test]
    fn flushed_reads_and_writes_subnormals_as_zero_and_standard_undoes_it() {
        if !FLUSH_AVAILABLE {
            return;
        }
        let tiny = f32::MIN_POSITIVE / 4.0;
        let (x, y) = (f32::MIN_POSITIVE, 0.25f32);
        assert_eq!(x * y, tiny);
        assert_eq!(
            flushed((x, y), |(x, y)| x * y),
            0.0,
            "a subnormal result is flushed"
        );
        assert_eq!(
            flushed(tiny, |t| t * 4.0),
            0.0,
            "a subnormal input is read as zero"
        );
        assert_eq!(
            flushed(tiny, |t| standard(t, |t| t * 4.0)),
            f32::MIN_POSITIVE,
            "standard() restores gradual underflow inside"
        );
        assert!(flushed((), |_| flushing()));
        assert!(!flushing(), "the caller's environment is restored");
        let panicked = std::panic::catch_unwind(|| flushed((), |_| panic!("inside")));
        assert!(panicked.is_err());
        assert!(!flushing(), "restored after a panic too");
    }
}
