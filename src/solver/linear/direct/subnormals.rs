//! Subnormal numbers flushed to zero while a factor is formed or applied.
//!
//! Why: Levenberg-Marquardt damping of 10 to 100 times the mean diagonal
//! (what Newton reaches while a step stalls) makes the matrix strongly
//! diagonally dominant, and the Cholesky fill of such a matrix decays
//! geometrically along the elimination tree until it is subnormal. x86
//! runs every operation on a subnormal through microcode, tens of times
//! slower. Measured on the 40x40 linen stitch's second relaxation step
//! (a scratch example timing every factorization; docs/RELAX.md,
//! "Subnormals"): the damped
//! numeric factorizations took 0.30 to 0.38 s against 0.12 to 0.16 s for
//! the same pattern undamped, and 0.12 to 0.16 s damped with flushing;
//! every iterate was the same to the printed digits. The values lost are
//! below `f64::MIN_POSITIVE` (2.2e-308), far under any rounding error of
//! the factor.
//!
//! The setting is per thread (the x86 `MXCSR` register), so it is set by
//! whoever factors or solves and put back when the guard drops; nothing
//! else in the process sees it. Elsewhere than on x86-64 the guard does
//! nothing.

/// While alive, this thread flushes subnormal results to zero (FTZ) and
/// reads subnormal inputs as zero (DAZ).
pub struct FlushSubnormals {
    #[cfg(target_arch = "x86_64")]
    saved: u32,
}

#[cfg(target_arch = "x86_64")]
mod mxcsr {
    /// Flush to zero (bit 15) and denormals are zero (bit 6).
    pub const FTZ_DAZ: u32 = 0x8040;

    pub fn read() -> u32 {
        let mut value: u32 = 0;
        // SAFETY: `stmxcsr` stores the 32-bit MXCSR register to the given
        // address, which is a live, aligned `u32`.
        unsafe { std::arch::asm!("stmxcsr [{}]", in(reg) &mut value, options(nostack)) };
        value
    }

    pub fn write(value: u32) {
        // SAFETY: `ldmxcsr` loads MXCSR from a live `u32`. Callers only
        // pass a value read from MXCSR, possibly with the FTZ and DAZ bits
        // set, which changes rounding of subnormals only.
        unsafe { std::arch::asm!("ldmxcsr [{}]", in(reg) &value, options(nostack, readonly)) };
    }
}

impl FlushSubnormals {
    pub fn new() -> Self {
        #[cfg(target_arch = "x86_64")]
        {
            let saved = mxcsr::read();
            mxcsr::write(saved | mxcsr::FTZ_DAZ);
            FlushSubnormals { saved }
        }
        #[cfg(not(target_arch = "x86_64"))]
        FlushSubnormals {}
    }
}

impl Drop for FlushSubnormals {
    fn drop(&mut self) {
        #[cfg(target_arch = "x86_64")]
        mxcsr::write(self.saved);
    }
}

#[cfg(all(test, target_arch = "x86_64"))]
mod tests {
    use super::*;
    use std::hint::black_box;

    fn quarter_of_smallest_normal() -> f64 {
        black_box(f64::MIN_POSITIVE) * black_box(0.25)
    }

    #[test]
    fn subnormals_flush_only_while_the_guard_lives() {
        assert!(quarter_of_smallest_normal() > 0.0, "subnormals before");
        {
            let _guard = FlushSubnormals::new();
            assert_eq!(quarter_of_smallest_normal(), 0.0);
            // A subnormal input reads as zero.
            let tiny = black_box(f64::from_bits(1));
            assert_eq!(tiny * black_box(1.0e300), 0.0);
        }
        assert!(quarter_of_smallest_normal() > 0.0, "subnormals after");
        assert_eq!(f64::from_bits(1) * black_box(1.0), f64::from_bits(1));
    }
}
