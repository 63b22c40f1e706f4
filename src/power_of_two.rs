//! Exact scaling by powers of two: multiplying by `2^e` changes only a float's exponent, so it
//! is exact over the whole number range (split in two steps where one factor would over- or
//! underflow). The normalization uses it to map meshes of any size onto the unit box, and the
//! quality measure to bring a quad's corners into [1, 2) before it computes anything, so that
//! no value depends on the scale a mesh is given at.

use glam::{DVec2, DVec3};

/// `2^e` for `e` in the normal exponent range [-1022, 1023].
#[inline]
pub(crate) fn pow2(e: i32) -> f64 {
    debug_assert!((-1022..=1023).contains(&e));
    f64::from_bits(((e + 1023) as u64) << 52)
}

/// `x * 2^e`, exact whenever the result is a normal number (or `x` is subnormal and `e > 0`):
/// the scaling is split in two steps so neither factor over- or underflows, and the
/// intermediate lies between `x` and the result.
#[inline]
pub fn scale_by_power_of_two(x: f64, e: i32) -> f64 {
    let e = e.clamp(-2200, 2200);
    let half = e / 2;
    x * pow2(half.clamp(-1022, 1023)) * pow2((e - half).clamp(-1022, 1023))
}

/// The exponent `k` with `2^k <= x < 2^(k+1)`, for a finite `x > 0` (subnormals included).
#[inline]
pub fn binary_exponent(x: f64) -> i32 {
    debug_assert!(x > 0.0 && x.is_finite());
    let biased = ((x.to_bits() >> 52) & 0x7ff) as i32;
    if biased == 0 {
        // Subnormal: bring it into the normal range first (exact).
        return binary_exponent(x * pow2(64)) - 64;
    }
    biased - 1023
}

/// The exponent `e` that scales the corners of `q` by `2^-e` so the largest absolute
/// coordinate lies in [1, 2) (0 for four corners at the origin).
#[inline]
pub fn unit_exponent(q: &[DVec2]) -> i32 {
    let m = q.iter().fold(0.0f64, |m, p| m.max(p.x.abs()).max(p.y.abs()));
    if m > 0.0 { binary_exponent(m) } else { 0 }
}

/// `p * 2^e`, component-wise (see [`scale_by_power_of_two`]).
#[inline]
pub fn scale_point(p: DVec2, e: i32) -> DVec2 {
    DVec2::new(scale_by_power_of_two(p.x, e), scale_by_power_of_two(p.y, e))
}

/// `p * 2^e`, component-wise (see [`scale_by_power_of_two`]).
#[inline]
pub fn scale_point3(p: DVec3, e: i32) -> DVec3 {
    DVec3::new(scale_by_power_of_two(p.x, e), scale_by_power_of_two(p.y, e), scale_by_power_of_two(p.z, e))
}

/// The exponent `e` that scales the bounding box of `points` by `2^-e` so its larger
/// half-extent lies in [0.5, 1) (0 for no point or all points equal). The half-extents are
/// computed halved first, so that nothing overflows at any finite coordinate.
pub fn extent_exponent3(points: impl IntoIterator<Item = DVec3>) -> i32 {
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for p in points {
        lo = lo.min(p);
        hi = hi.max(p);
    }
    let half = (hi * 0.5 - lo * 0.5).max_element();
    if half > 0.0 && half.is_finite() { binary_exponent(half) + 1 } else { 0 }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn power_of_two_scaling_is_exact_over_the_whole_range() {
        assert_eq!(scale_by_power_of_two(3.0, 4), 48.0);
        assert_eq!(scale_by_power_of_two(f64::MAX, -1023), f64::MAX / pow2(1023));
        assert_eq!(scale_by_power_of_two(scale_by_power_of_two(1.5, -1060), 1060), 1.5);
        assert_eq!(scale_by_power_of_two(f64::MIN_POSITIVE, 1022), 1.0);
        assert_eq!(binary_exponent(1.0), 0);
        assert_eq!(binary_exponent(0.75), -1);
        assert_eq!(binary_exponent(f64::MAX), 1023);
        assert_eq!(binary_exponent(f64::MIN_POSITIVE), -1022);
        assert_eq!(binary_exponent(f64::from_bits(1)), -1074);
        assert_eq!(binary_exponent(f64::from_bits(3)), -1073);
    }
}
