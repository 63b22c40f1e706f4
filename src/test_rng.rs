//! Deterministic pseudo-random numbers for the unit tests.

/// Xorshift64 from `state`: numbers in [-1, 1) (half of one is bit for bit the classic
/// `(state >> 11) / 2^53 - 0.5`).
pub(crate) fn xorshift(mut state: u64) -> impl FnMut() -> f64 {
    move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}
