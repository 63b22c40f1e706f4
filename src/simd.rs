//! Hot loops compiled for the vector width of the CPU they run on, chosen at run time.
//!
//! The crate is built for baseline x86-64 (SSE2: two f64 lanes), which every user's machine
//! runs. A hot loop that gains from four lanes is defined with [`avx2_twin!`]: a second copy
//! compiled with `#[target_feature(enable = "avx2")]`, entered when [`has_avx2`]. What it calls
//! must be `#[inline(always)]` down to the arithmetic (code called out of line keeps the
//! baseline compilation). Only IEEE arithmetic is vectorized (no fused multiply-add: Rust
//! never contracts `a * b + c`), so both copies give the same bits, and a run is the same on
//! every machine.

/// Defines a function whose body runs compiled with AVX2 where the CPU has it, else as
/// built: `avx2_twin! { fn name(arg: Type, ...) -> Ret { body } }` (no `self`, no generics).
macro_rules! avx2_twin {
    ($(#[$meta:meta])* $vis:vis fn $name:ident($($arg:ident: $ty:ty),* $(,)?) $(-> $ret:ty)? $body:block) => {
        $(#[$meta])*
        $vis fn $name($($arg: $ty),*) $(-> $ret)? {
            #[inline(always)]
            fn body($($arg: $ty),*) $(-> $ret)? $body
            /// The body compiled with AVX2. Safety: the CPU must have AVX2.
            #[cfg(target_arch = "x86_64")]
            #[allow(unsafe_code)]
            #[target_feature(enable = "avx2")]
            unsafe fn wide($($arg: $ty),*) $(-> $ret)? {
                body($($arg),*)
            }
            #[cfg(target_arch = "x86_64")]
            if $crate::simd::has_avx2() {
                // SAFETY: the CPU has AVX2, checked just above.
                #[allow(unsafe_code)]
                return unsafe { wide($($arg),*) };
            }
            body($($arg),*)
        }
    };
}
pub(crate) use avx2_twin;

/// Whether this CPU has AVX2 (a cached load after the first call); in the crate's tests,
/// `false` while [`tests::BASELINE_ONLY`] is set.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
pub fn has_avx2() -> bool {
    #[cfg(test)]
    if tests::BASELINE_ONLY.load(std::sync::atomic::Ordering::Relaxed) {
        return false;
    }
    std::arch::is_x86_feature_detected!("avx2")
}

#[cfg(test)]
pub(crate) mod tests {
    use crate::synthetic::Synthetic;
    use crate::{Optimizer, Options};
    use std::sync::atomic::{AtomicBool, Ordering};

    /// Set: the hot loops take their baseline compilation (other tests running meanwhile get
    /// the same bits either way).
    pub(crate) static BASELINE_ONLY: AtomicBool = AtomicBool::new(false);

    #[test]
    fn both_compilations_give_the_same_run() {
        let mesh = Synthetic::with_quads(20_000).generate();
        let optimizer = Optimizer::new(&mesh);
        let run = |baseline: bool| {
            BASELINE_ONLY.store(baseline, Ordering::Relaxed);
            let mut m = mesh.clone();
            let report = optimizer.run(&mut m, &Options::default(), None).unwrap();
            BASELINE_ONLY.store(false, Ordering::Relaxed);
            (m, report)
        };
        let (wide, wide_report) = run(false);
        let (baseline, baseline_report) = run(true);
        assert!(wide_report.iterations > 1 && wide_report.output.min > wide_report.input.min);
        assert_eq!(wide_report.iterations, baseline_report.iterations);
        for (a, b) in wide.points().iter().zip(baseline.points()) {
            assert_eq!((a.x.to_bits(), a.y.to_bits()), (b.x.to_bits(), b.y.to_bits()));
        }
    }
}
