//! The floating-point environment of the calling thread: the flush-to-zero model (`cpu-ftz`, as a GPU
//! may compute) runs a method with subnormal inputs read as zero and subnormal results flushed to zero
//! by the processor itself, and the oracle always computes in the standard environment.
//!
//! x86-64: MXCSR's FTZ (bit 15, results) and DAZ (bit 6, inputs); AArch64: FPCR's FZ (bit 24, both).
//! The compiler assumes the standard environment, so each switch passes the work's input and result
//! through [`std::hint::black_box`]: nothing is computed across a switch.

use std::hint::black_box;

/// Whether this processor can run the flush-to-zero model.
pub const FLUSH_AVAILABLE: bool = cfg!(any(target_arch = "x86_64", target_arch = "aarch64"));

#[cfg(target_arch = "x86_64")]
mod reg {
    pub const FLUSH: u64 = (1 << 15) | (1 << 6);
    #[inline(always)]
    pub fn read() -> u64 {
        let mut csr: u32 = 0;
        // SAFETY: stores MXCSR into a local.
        unsafe { std::arch::asm!("stmxcsr [{}]", in(reg) &mut csr, options(nostack)) };
        csr as u64
    }
    #[inline(always)]
    pub fn write(v: u64) {
        let csr = v as u32;
        // SAFETY: loads MXCSR from a local holding a valid value (only the flush bits changed).
        unsafe { std::arch::asm!("ldmxcsr [{}]", in(reg) &csr, options(nostack)) };
    }
}

#[cfg(target_arch = "aarch64")]
mod reg {
    pub const FLUSH: u64 = 1 << 24;
    #[inline(always)]
    pub fn read() -> u64 {
        let v: u64;
        // SAFETY: reads FPCR.
        unsafe { std::arch::asm!("mrs {}, fpcr", out(reg) v, options(nostack)) };
        v
    }
    #[inline(always)]
    pub fn write(v: u64) {
        // SAFETY: writes FPCR with only the flush bit changed.
        unsafe { std::arch::asm!("msr fpcr, {}", in(reg) v, options(nostack)) };
    }
}

#[cfg(not(any(target_arch = "x86_64", target_arch = "aarch64")))]
mod reg {
    pub const FLUSH: u64 = 0;
    pub fn read() -> u64 {
        0
    }
    pub fn write(_: u64) {}
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
pub fn standard<T, R>(input: T, f: impl FnOnce(T) -> R) -> R {
    with(false, input, f)
}

#[cfg(test)]
mod tests {
    use super::*;

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
