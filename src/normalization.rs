//! Coordinate normalization: the optimizer works on coordinates translated near the origin and
//! scaled by a power of two to the size of the mesh's bounding box, so that no result depends
//! on the units the mesh is given in and nothing overflows or underflows at any finite scale.
//!
//! - The scale is a power of two, so scaling is exact: a mesh scaled by `2^s` normalizes to
//!   the very same coordinates, bit for bit, and its result is the unit-scale result times
//!   `2^s`.
//! - The origin is the bounding box's centre rounded to a multiple of a power of two larger
//!   than the box, so it is zero whenever the box contains the origin (then normalizing is a
//!   pure, exact scaling). Otherwise subtracting it rounds each coordinate to the precision it
//!   has at the mesh's distance from the origin, which is all the precision the input has
//!   relative to the mesh's size: a translation by an offset `T` of a mesh of extent `L`
//!   changes results by about `T / L` units in the last place.
//! - Mapping back keeps the original coordinates, bit for bit, of every vertex whose
//!   normalized position did not change, so fixed vertices, corners and vertices that did not
//!   move never pick up a rounding error from the round trip.

use crate::alloc::try_copy;
use crate::error::Result;
use glam::DVec2;

/// `2^e` for `e` in the normal exponent range [-1022, 1023].
#[inline]
fn pow2(e: i32) -> f64 {
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

/// The map between a mesh's coordinates and the normalized ones the optimizer works on:
/// `normalized = (p - origin) * 2^-exponent`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Normalization {
    origin: DVec2,
    exponent: i32,
}

impl Normalization {
    /// The identity map.
    pub const IDENTITY: Normalization = Normalization { origin: DVec2::ZERO, exponent: 0 };

    /// The normalization of the vertices used by `quads` (finite coordinates): their bounding
    /// box maps into roughly [-3, 3]^2 with its larger half-extent in [0.5, 1).
    pub fn new(points: &[DVec2], quads: &[[u32; 4]]) -> Normalization {
        let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        for &v in quads.iter().flatten() {
            if let Some(&p) = points.get(v as usize) {
                lo = lo.min(p);
                hi = hi.max(p);
            }
        }
        if !(lo.is_finite() && hi.is_finite()) {
            return Normalization::IDENTITY;
        }
        // Halved before subtracting so that even a box spanning [-f64::MAX, f64::MAX] does not
        // overflow.
        let half_extent = (hi * 0.5 - lo * 0.5).max_element();
        if half_extent <= 0.0 {
            return Normalization::IDENTITY;
        }
        // half_extent in [2^(k-1), 2^k): scaled by 2^-k it lies in [0.5, 1).
        let exponent = binary_exponent(half_extent) + 1;
        let center = lo * 0.5 + hi * 0.5;
        // Round the centre towards zero to a multiple of 2^g > the extent: zero when the box
        // contains the origin, and few significant bits otherwise. Past 2^1023 no translation
        // is needed (the box is as large as the number range).
        let g = exponent + 1;
        let origin = if g > 1023 {
            DVec2::ZERO
        } else {
            let round = |c: f64| {
                let units = scale_by_power_of_two(c, -g);
                // |units| >= 2^52: c is already a multiple of 2^g.
                if units.abs() >= pow2(52) { c } else { scale_by_power_of_two(units.trunc(), g) }
            };
            DVec2::new(round(center.x), round(center.y))
        };
        Normalization { origin, exponent }
    }

    /// The origin subtracted before scaling.
    pub fn origin(&self) -> DVec2 {
        self.origin
    }

    /// The power of two the normalized coordinates are scaled by: `p = origin + q * 2^exponent`.
    pub fn exponent(&self) -> i32 {
        self.exponent
    }

    /// Normalized coordinates of `p`. A point far outside the mesh's bounding box (only a vertex
    /// used by no quad can be) that would overflow maps to the origin.
    #[inline]
    pub fn to_normalized(&self, p: DVec2) -> DVec2 {
        let d = p - self.origin;
        let q = DVec2::new(
            scale_by_power_of_two(d.x, -self.exponent),
            scale_by_power_of_two(d.y, -self.exponent),
        );
        if q.is_finite() { q } else { DVec2::ZERO }
    }

    /// The mesh coordinates of normalized `q` (not finite only far outside the number range).
    #[inline]
    pub fn to_original(&self, q: DVec2) -> DVec2 {
        DVec2::new(scale_by_power_of_two(q.x, self.exponent), scale_by_power_of_two(q.y, self.exponent))
            + self.origin
    }

    /// A normalized length in mesh units.
    #[inline]
    pub fn length_to_original(&self, length: f64) -> f64 {
        scale_by_power_of_two(length, self.exponent)
    }

    /// Replaces `points` by their normalized coordinates and returns the original ones, which
    /// [`Normalization::restore`] needs.
    pub fn normalize(&self, points: &mut [DVec2]) -> Result<Vec<DVec2>> {
        let original = try_copy(points, "original coordinates")?;
        if *self != Normalization::IDENTITY {
            for p in points.iter_mut() {
                *p = self.to_normalized(*p);
            }
        }
        Ok(original)
    }

    /// Maps normalized `points` back to mesh coordinates in place: a vertex whose normalized
    /// position is (bitwise) the one [`Normalization::normalize`] gave it gets its `original`
    /// coordinates back exactly; a moved vertex gets its mapped position (or its original one
    /// in the impossible case that this is not finite).
    pub fn restore(&self, points: &mut [DVec2], original: &[DVec2]) {
        let same = |a: DVec2, b: DVec2| a.x.to_bits() == b.x.to_bits() && a.y.to_bits() == b.y.to_bits();
        for (p, &o) in points.iter_mut().zip(original) {
            if same(*p, self.to_normalized(o)) {
                *p = o;
            } else {
                let back = self.to_original(*p);
                *p = if back.is_finite() { back } else { o };
            }
        }
    }
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

    fn square(scale: f64, offset: DVec2) -> (Vec<DVec2>, Vec<[u32; 4]>) {
        let p = [(0., 0.), (3., 0.), (3., 2.), (0., 2.)].map(|(x, y)| DVec2::new(x, y) * scale + offset);
        (p.to_vec(), vec![[0, 1, 2, 3]])
    }

    #[test]
    fn a_box_containing_the_origin_is_only_scaled() {
        // Half-extent 1.5 in [2^0, 2^1): exponent 1, so coordinates are halved.
        let (p, q) = square(1.0, DVec2::new(-1.0, -1.0));
        let n = Normalization::new(&p, &q);
        assert_eq!((n.origin(), n.exponent()), (DVec2::ZERO, 1));
        assert_eq!(n.to_normalized(DVec2::new(2.0, 1.0)), DVec2::new(1.0, 0.5));
    }

    #[test]
    fn power_of_two_scaled_meshes_normalize_to_identical_coordinates() {
        let offset = DVec2::new(1000.3, -77.1);
        let (p, q) = square(1.0, offset);
        let unit = Normalization::new(&p, &q);
        assert_ne!(unit.origin(), DVec2::ZERO);
        for s in [-1000, -1, 1, 1000] {
            let scaled: Vec<DVec2> = p.iter().map(|&x| scale_point(x, s)).collect();
            let n = Normalization::new(&scaled, &q);
            assert_eq!(n.exponent(), unit.exponent() + s);
            for (a, b) in p.iter().zip(&scaled) {
                assert_eq!(unit.to_normalized(*a), n.to_normalized(*b), "2^{s}");
            }
        }
    }

    #[test]
    fn extreme_boxes_stay_finite_and_round_trip() {
        for (scale, offset) in [
            (1e-300, DVec2::ZERO),
            (1e300, DVec2::ZERO),
            (5e307, DVec2::new(-f64::MAX / 2.0, 0.0)),
            (1e290, DVec2::new(1e300, -1e300)),
            (1e-310, DVec2::ZERO),
        ] {
            let (p, q) = square(scale, offset);
            let n = Normalization::new(&p, &q);
            for &x in &p {
                let y = n.to_normalized(x);
                assert!(y.abs().max_element() < 3.0, "{scale} {offset}: {x} -> {y}");
            }
            let mut work = p.clone();
            let original = n.normalize(&mut work).unwrap();
            work[1] += DVec2::new(0.0, 0.25);
            n.restore(&mut work, &original);
            assert_eq!(work[0], p[0]);
            assert_eq!(work[2..], p[2..]);
            assert!(work[1].is_finite() && work[1] != p[1], "{scale} {offset}");
        }
    }

    #[test]
    fn unmoved_vertices_come_back_bit_identical_and_moved_ones_map_back() {
        let (p, q) = square(0.1, DVec2::new(12345.678, 0.3));
        let n = Normalization::new(&p, &q);
        let mut work = p.clone();
        let original = n.normalize(&mut work).unwrap();
        let moved = work[2] * 0.5 + work[0] * 0.5;
        work[2] = moved;
        n.restore(&mut work, &original);
        assert_eq!([work[0], work[1], work[3]], [p[0], p[1], p[3]]);
        let centre = (p[0] + p[2]) * 0.5;
        assert!((work[2] - centre).length() < 1e-11, "{} vs {centre}", work[2]);
    }
}
