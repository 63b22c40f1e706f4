//! Helpers shared by the integration tests. Each test crate uses only some of them.
#![allow(dead_code)]

pub mod grids;
pub mod hard;
pub mod samples;
pub mod shared;
pub mod surfaces;

/// Deterministic pseudo-random numbers in [-1, 1) (SplitMix64): the same sequence on every
/// platform, so generated test meshes never change.
pub struct Rng(pub u64);

impl Rng {
    /// The next number in [-1, 1).
    pub fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}
