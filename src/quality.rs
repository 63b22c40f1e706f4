//! Element quality: the quad scaled Jacobian (Verdict's definition) and mesh statistics.
//!
//! Verdict measures each quad against its own normal, so a folded but convex quad scores as a
//! good element. In a planar mesh the reference normal is the mesh's (+z after orientation has
//! been made consistent and counter-clockwise, see [`crate::Mesh`]), so here the corner
//! value is the *signed* 2D cross product of the two normalized edges at that corner. It equals
//! Verdict's value for every counter-clockwise quad that is not folded; a corner turning the
//! wrong way makes the quad inverted (negative) even when the quad is convex.

use crate::power_of_two::{scale_point, unit_exponent};
use glam::DVec2;

/// Verdict (VTK 9.x) treats an edge as degenerate (quad value 0) when it is shorter than
/// this fraction of the diagonal of the quad's bounding box, so the cut-off scales with the
/// quad (measured against VTK 9.7.2's vtkMeshQuality, see tests/verdict.rs).
const DEGENERATE_EDGE_RELATIVE: f64 = 10.0 * f64::EPSILON;

/// Verdict's cut-off for a collapsed quad measured as a triangle, applied to edges scaled so
/// the largest component is in [1, 2) (Verdict applies it to the absolute edge lengths).
const DEGENERATE_TRIANGLE: f64 = 1.0e-30;

/// Signed scaled Jacobian at corner `p` of a quad, with `prev` and `next` its neighbours in
/// counter-clockwise order: cross(next - p, prev - p) / (|next - p| |prev - p|), in [-1, 1].
///
/// Returns 0 when one of the two edges is degenerate: zero, or shorter than
/// 10 f64::EPSILON times the longer one (the corner analogue of Verdict's relative test).
/// Computed on the three points scaled by a power of two (exact), so it is the same at any
/// finite scale.
#[inline]
pub fn corner_scaled_jacobian(prev: DVec2, p: DVec2, next: DVec2) -> f64 {
    let e = -unit_exponent(&[prev, p, next]);
    let (prev, p, next) = (scale_point(prev, e), scale_point(p, e), scale_point(next, e));
    let e1 = next - p;
    let e2 = prev - p;
    let (l1, l2) = (e1.length(), e2.length());
    let short = DEGENERATE_EDGE_RELATIVE * l1.max(l2);
    if l1 == 0.0 || l2 == 0.0 || l1 < short || l2 < short {
        return 0.0;
    }
    (e1.perp_dot(e2) / (l1 * l2)).clamp(-1.0, 1.0)
}

/// Scaled Jacobian of a quad whose corners are given counter-clockwise (the mesh's "up" side).
///
/// The minimum over the four corners of the signed cross product of the normalized edge
/// vectors; in `[-1, 1]`, 1 for a square, negative for an inverted quad. Degenerate edges give
/// 0 (an edge shorter than 10 f64::EPSILON times the bounding-box diagonal, Verdict's
/// relative test), and a quad collapsed to a triangle (last two corners identical) is measured
/// as that triangle, as Verdict's `quad_scaled_jacobian` does.
///
/// Scale-free: the corners are first scaled by a power of two (exact) so that the largest
/// coordinate is in [1, 2), so no edge length or product overflows or underflows for any
/// finite coordinates, and a quad scaled by `2^s` gets the same value bit for bit.
///
/// ```
/// use glam::DVec2;
/// let square = [DVec2::new(0.0, 0.0), DVec2::new(1.0, 0.0), DVec2::new(1.0, 1.0), DVec2::new(0.0, 1.0)];
/// assert!((quadopt::quality::scaled_jacobian(&square) - 1.0).abs() < 1e-15);
/// let huge = square.map(|p| p * 1e300);
/// assert!((quadopt::quality::scaled_jacobian(&huge) - 1.0).abs() < 1e-15);
/// ```
pub fn scaled_jacobian(q: &[DVec2; 4]) -> f64 {
    scaled_jacobian_inline(q)
}

/// [`scaled_jacobian`], inlined into the loops compiled for AVX2 ([`crate::simd`]); the rare
/// quad out of the exact range is scaled out of line.
#[inline(always)]
pub(crate) fn scaled_jacobian_inline(q: &[DVec2; 4]) -> f64 {
    if in_exact_range(q) { scaled_jacobian_in_range(q) } else { scaled_jacobian_scaled(q) }
}

/// [`scaled_jacobian`] of a quad out of the exact range: scaled by a power of two into it.
#[inline(never)]
fn scaled_jacobian_scaled(q: &[DVec2; 4]) -> f64 {
    let e = -unit_exponent(q);
    scaled_jacobian_in_range(&q.map(|p| scale_point(p, e)))
}

/// Whether `scaled_jacobian(q) < floor`, the same answer bit for bit, mostly without the
/// square roots and divisions: the guard of every sweep asks this of every star it tries.
///
/// Each corner is decided from squared quantities, `cross^2` against `floor^2 |a|^2 |b|^2`
/// (its two edges `a`, `b`), when they differ by more than a relative margin of 1e-9: the
/// rounding of either computation is below 1e-15 relative, so outside the margin both sides
/// of `scaled_jacobian`'s own comparison are known. A corner inside the margin, a short edge
/// (near Verdict's cut-off), a collapsed quad, extreme coordinates or a floor outside
/// [2^-60, 1] fall back to `scaled_jacobian` itself.
///
/// ```
/// use glam::DVec2;
/// let skewed = [DVec2::new(0.0, 0.0), DVec2::new(1.0, 0.0), DVec2::new(1.5, 1.0), DVec2::new(0.5, 1.0)];
/// let sj = quadopt::quality::scaled_jacobian(&skewed);
/// assert!(quadopt::quality::scaled_jacobian_below(&skewed, sj + 1e-12));
/// assert!(!quadopt::quality::scaled_jacobian_below(&skewed, sj));
/// ```
#[inline]
pub fn scaled_jacobian_below(q: &[DVec2; 4], floor: f64) -> bool {
    match below_from_squares(q, floor) {
        Some(below) => below,
        None => scaled_jacobian(q) < floor,
    }
}

/// Relative margin of [`below_from_squares`]'s comparisons: far above their rounding
/// (a few ulps, 1e-15) and far below any difference that matters.
const SQUARES_MARGIN: f64 = 1e-9;

/// Floors below 2^-60 (and above 1) are left to [`scaled_jacobian`]: with squared edges in
/// [2^-240, 2^240] every product below then stays a normal number.
const SQUARES_FLOOR_LOW: f64 = f64::from_bits((1023 - 60) << 52);
const SQUARES_EDGE_LOW: f64 = f64::from_bits((1023 - 240) << 52);
const SQUARES_EDGE_HIGH: f64 = f64::from_bits((1023 + 240) << 52);

/// [`scaled_jacobian_below`]'s decision from squared quantities, or `None` when it is not
/// certain. Mirrors [`scaled_jacobian_in_range`]: for a floor in (0, 1] the clamp does not
/// change the comparison, a quad with no short edge is not degenerate, and a corner with
/// `cross <= 0` is below any positive floor.
#[inline]
fn below_from_squares(q: &[DVec2; 4], floor: f64) -> Option<bool> {
    if !(SQUARES_FLOOR_LOW..=1.0).contains(&floor) || q[3] == q[2] || !in_exact_range(q) {
        return None;
    }
    let e = [q[1] - q[0], q[2] - q[1], q[3] - q[2], q[0] - q[3]];
    let s = [e[0].length_squared(), e[1].length_squared(), e[2].length_squared(), e[3].length_squared()];
    let shortest = s[0].min(s[1]).min(s[2]).min(s[3]);
    let longest = s[0].max(s[1]).max(s[2]).max(s[3]);
    // The bound scaled_jacobian_in_range uses: an edge clearly longer is not short there.
    let (clearly_long, _) = clearly_long_bound(q);
    if !(shortest >= SQUARES_EDGE_LOW
        && longest <= SQUARES_EDGE_HIGH
        && shortest >= clearly_long * clearly_long * (1.0 + SQUARES_MARGIN))
    {
        return None;
    }
    let floor2 = floor * floor;
    let mut certain = true;
    for i in 0..4 {
        let j = (i + 3) % 4;
        let cross = e[j].perp_dot(e[i]);
        if cross <= 0.0 {
            return Some(true);
        }
        let (x, y) = (cross * cross, floor2 * s[i] * s[j]);
        if x <= y * (1.0 - SQUARES_MARGIN) {
            return Some(true);
        }
        certain &= x >= y * (1.0 + SQUARES_MARGIN);
    }
    certain.then_some(false)
}

/// Bounds of [`in_exact_range`]: 2^250 and 2^-250.
const RANGE_HIGH: f64 = f64::from_bits((1023 + 250) << 52);
const RANGE_LOW: f64 = f64::from_bits((1023 - 250) << 52);

/// Whether every coordinate of `q` is at most 2^250 in magnitude and every coordinate
/// difference along an edge is 0 or at least 2^-250. Then every product, square, square root
/// and quotient of [`scaled_jacobian_in_range`] is a normal number (or an exact difference)
/// both for `q` and for `q` scaled by the power of two that brings its largest coordinate
/// into [1, 2); each operation's result scales exactly, so both give the same value bit for
/// bit and the scaling can be skipped (the common case: the optimizer works in a normalized
/// frame).
#[inline(always)]
fn in_exact_range(q: &[DVec2; 4]) -> bool {
    let mut ok = true;
    for i in 0..4 {
        let (p, d) = (q[i], q[(i + 1) % 4] - q[i]);
        ok &= p.x.abs() <= RANGE_HIGH && p.y.abs() <= RANGE_HIGH;
        ok &= (d.x == 0.0 || d.x.abs() >= RANGE_LOW) && (d.y == 0.0 || d.y.abs() >= RANGE_LOW);
    }
    ok
}

/// A length every edge at least as long as is not short for Verdict's cut-off
/// ([`DEGENERATE_EDGE_RELATIVE`] times the diagonal of the quad's bounding box), and that box's
/// extent. The cut-off is DEGENERATE_EDGE_RELATIVE times the diagonal |hi - lo| <= dx + dy;
/// the computed diagonal exceeds dx + dy by at most 2 ulps, the bound falls short of it by at
/// most 3 and is raised by 4: the diagonal's square root is needed only for the rare quads
/// with a shorter edge.
#[inline(always)]
fn clearly_long_bound(q: &[DVec2; 4]) -> (f64, DVec2) {
    let lo = q[0].min(q[1]).min(q[2]).min(q[3]);
    let hi = q[0].max(q[1]).max(q[2]).max(q[3]);
    let d = hi - lo;
    (DEGENERATE_EDGE_RELATIVE * (d.x + d.y) * (1.0 + 4.0 * f64::EPSILON), d)
}

/// The scaled Jacobian of a quad whose coordinates are in a range where no step of the
/// computation over- or underflows (see [`in_exact_range`]).
#[inline(always)]
fn scaled_jacobian_in_range(q: &[DVec2; 4]) -> f64 {
    if q[3] == q[2] {
        return triangle_scaled_jacobian(q[0], q[1], q[2]);
    }
    // Edge i runs from corner i to corner i + 1.
    let e = [q[1] - q[0], q[2] - q[1], q[3] - q[2], q[0] - q[3]];
    let len = [e[0].length(), e[1].length(), e[2].length(), e[3].length()];
    let shortest = len[0].min(len[1]).min(len[2]).min(len[3]);
    let (clearly_long, d) = clearly_long_bound(q);
    if shortest == 0.0 || shortest < clearly_long {
        let short = DEGENERATE_EDGE_RELATIVE * d.length();
        if len.iter().any(|&l| l == 0.0 || l < short) {
            return 0.0;
        }
    }
    let mut min = f64::INFINITY;
    for i in 0..4 {
        // Edges out of corner i: e[i] to the next corner and -e[i - 1] to the previous one;
        // cross(e[i], -e[i - 1]) = cross(e[i - 1], e[i]), bit for bit.
        let j = (i + 3) % 4;
        min = min.min(e[j].perp_dot(e[i]) / (len[i] * len[j]));
    }
    // |cross| <= product of the lengths, up to rounding.
    min.clamp(-1.0, 1.0)
}

/// Verdict's triangle scaled Jacobian (signed against +z): twice the area over the largest
/// product of two edge lengths, scaled by 2/sqrt(3) so an equilateral triangle scores 1.
///
/// Verdict returns 0 for a tiny triangle (VTK 9.7.2: a bounding-box diagonal below about
/// 2.2e-15, an absolute cut-off) and for coordinates beyond about 1e154; here the
/// edges are first scaled by a power of two so that the longest is in [1, 2), which leaves
/// the largest product at least 1/2 unless the triangle is collapsed to a point: the result
/// does not depend on the scale.
fn triangle_scaled_jacobian(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    let (e0, e1, e2) = (b - a, c - b, a - c);
    let s = -unit_exponent(&[e0, e1, e2]);
    let (e0, e1, e2) = (scale_point(e0, s), scale_point(e1, s), scale_point(e2, s));
    let (l0, l1, l2) = (e0.length(), e1.length(), e2.length());
    let max_product = (l0 * l2).max(l0 * l1).max(l1 * l2);
    if max_product < DEGENERATE_TRIANGLE {
        return 0.0;
    }
    let jacobian = e0.perp_dot(-e2);
    (jacobian * 2.0 / 3.0_f64.sqrt() / max_product).clamp(-1.0, 1.0)
}

/// Summary of the quality of a set of quads.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QualityStats {
    /// Smallest scaled Jacobian (worst quad).
    pub min: f64,
    /// Mean scaled Jacobian.
    pub avg: f64,
    /// Largest scaled Jacobian.
    pub max: f64,
    /// Number of quads with a scaled Jacobian <= 0 (inverted or degenerate).
    pub inverted: usize,
}

impl QualityStats {
    /// Statistics of a list of per-quad values. An empty list gives NaN statistics.
    pub fn from_values(values: &[f64]) -> Self {
        if values.is_empty() {
            return QualityStats { min: f64::NAN, avg: f64::NAN, max: f64::NAN, inverted: 0 };
        }
        let (mut min, mut max, mut sum, mut inverted) = (f64::INFINITY, f64::NEG_INFINITY, 0.0, 0);
        for &v in values {
            min = min.min(v);
            max = max.max(v);
            sum += v;
            inverted += usize::from(v <= 0.0);
        }
        QualityStats { min, avg: sum / values.len() as f64, max, inverted }
    }

    /// Orders two results by (inverted count, minimum, average): `true` when `self` is
    /// strictly better than `other`.
    pub fn better_than(&self, other: &QualityStats) -> bool {
        self.better_than_with_tie(other, 0.0)
    }

    /// The one ranking rule of results, the optimizer's included: fewer inverted quads win,
    /// then a minimum higher by more than `tie`, then (minima within `tie`, a tie) the higher
    /// average. `tie = 0` is [`better_than`](Self::better_than).
    pub fn better_than_with_tie(&self, other: &QualityStats, tie: f64) -> bool {
        if self.inverted != other.inverted {
            return self.inverted < other.inverted;
        }
        let min_differs = if tie == 0.0 { self.min != other.min } else { (self.min - other.min).abs() > tie };
        if min_differs {
            return self.min > other.min;
        }
        self.avg > other.avg
    }
}

/// Quality statistics of the quads and of the triangles of a mesh apart.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ByFaceKind {
    /// Number of quads.
    pub quad_count: usize,
    /// Statistics over the quads (`None` when there are none).
    pub quads: Option<QualityStats>,
    /// Number of triangles.
    pub triangle_count: usize,
    /// Statistics over the triangles (`None` when there are none).
    pub triangles: Option<QualityStats>,
}

impl ByFaceKind {
    /// A mesh of `quad_count` quads whose statistics are `stats`, and no triangle.
    pub fn quads_only(quad_count: usize, stats: QualityStats) -> ByFaceKind {
        ByFaceKind { quad_count, quads: Some(stats), triangle_count: 0, triangles: None }
    }

    /// The statistics of `values`, one per face of `faces`, split by kind.
    pub fn new(faces: &[[u32; 4]], values: &[f64]) -> ByFaceKind {
        let mut quads = Vec::with_capacity(faces.len());
        let mut triangles = Vec::new();
        for (f, &v) in faces.iter().zip(values) {
            if crate::face::is_triangle(f) { triangles.push(v) } else { quads.push(v) }
        }
        let stats = |v: &[f64]| (!v.is_empty()).then(|| QualityStats::from_values(v));
        ByFaceKind {
            quad_count: quads.len(),
            quads: stats(&quads),
            triangle_count: triangles.len(),
            triangles: stats(&triangles),
        }
    }
}

/// The faces of `values` by the bins `quadopt quality` prints: `counts[0]` those at or below 0
/// (the inverted ones, as [`QualityStats::inverted`] counts them, and NaN), then `counts[k]`
/// those in `((k - 1) / 10, k / 10]` for k = 1..10.
pub fn histogram(values: &[f64]) -> [usize; 11] {
    let mut counts = [0; 11];
    for &v in values {
        let bin = if v <= 0.0 || v.is_nan() { 0 } else { ((v * 10.0).ceil() as usize).clamp(1, 10) };
        counts[bin] += 1;
    }
    counts
}

/// Whether a quad with corners `c` is valid, degenerate or inverted: its scaled Jacobian
/// against zero (`None` for NaN).
#[inline]
pub fn sign_class(c: &[DVec2; 4]) -> Option<std::cmp::Ordering> {
    scaled_jacobian(c).partial_cmp(&0.0)
}

/// Per-quad scaled Jacobians of `quads` (counter-clockwise, indices into `points`).
pub fn quad_values(points: &[DVec2], quads: &[[u32; 4]]) -> Vec<f64> {
    let mut values = vec![0.0; quads.len()];
    values_into(points, quads, &mut values);
    values
}

/// [`quad_values`] into `values` (as long as `quads`): in parallel, chunk by chunk, each
/// compiled for AVX2 where the CPU has it; the same values on any thread count and CPU.
pub(crate) fn values_into(points: &[DVec2], quads: &[[u32; 4]], values: &mut [f64]) {
    use rayon::prelude::*;
    quads
        .par_chunks(PARALLEL_CHUNK)
        .zip(values.par_chunks_mut(PARALLEL_CHUNK))
        .for_each(|(quads, values)| chunk_values(points, quads, values));
}

crate::simd::avx2_twin! {
    /// The scaled Jacobians of `quads` into `values` (as long).
    fn chunk_values(points: &[DVec2], quads: &[[u32; 4]], values: &mut [f64]) {
        for (q, value) in quads.iter().zip(values.iter_mut()) {
            *value = scaled_jacobian_inline(&corners(points, q));
        }
    }
}

/// Faces or vertices per parallel task in the whole-mesh passes (quality, energy, lengths):
/// a rayon task costs about a microsecond, a face a few nanoseconds.
pub(crate) const PARALLEL_CHUNK: usize = 4096;

/// The four corner positions of a face; a triangle's last corner twice, which
/// [`scaled_jacobian`] measures as the triangle (see [`crate::face::fourth_corner`]).
#[inline(always)]
pub fn corners(points: &[DVec2], q: &[u32; 4]) -> [DVec2; 4] {
    let d = crate::face::fourth_corner(q);
    [points[q[0] as usize], points[q[1] as usize], points[q[2] as usize], points[d as usize]]
}

#[cfg(test)]
mod tests {
    #[test]
    fn skipping_the_scaling_in_range_gives_the_same_bits() {
        // Random quads (convex, folded, nearly degenerate, triangles) at scales and offsets
        // across the range: the unscaled evaluation, where it is taken, equals the scaled one.
        let mut rnd = crate::test_rng::xorshift(0x9e37_79b9_7f4a_7c15u64);
        let mut next = || 0.5 * rnd();
        let mut fast = 0;
        for k in 0..200_000 {
            let scale = 2f64.powf(600.0 * next());
            let offset = DVec2::new(next(), next()) * 2f64.powf(600.0 * next());
            let spread = if k % 7 == 0 { 1e-9 } else { 1.0 };
            let mut q =
                [DVec2::new(0.0, 0.0), DVec2::new(1.0, 0.0), DVec2::new(1.0, 1.0), DVec2::new(0.0, 1.0)]
                    .map(|p| (p + spread * DVec2::new(next(), next())) * scale + offset);
            if k % 11 == 0 {
                q[3] = q[2];
            }
            let slow = scaled_jacobian_in_range(&q.map(|p| scale_point(p, -unit_exponent(&q))));
            if in_exact_range(&q) {
                fast += 1;
            }
            let value = scaled_jacobian(&q);
            assert!(value.to_bits() == slow.to_bits(), "{q:?}: {value} vs {slow}");
        }
        assert!(fast > 50_000, "the unscaled path was taken {fast} times");
    }

    /// The degenerate-edge rule as Verdict states it: the diagonal's square root always taken.
    fn reference_in_range(q: &[DVec2; 4]) -> f64 {
        let lo = q[0].min(q[1]).min(q[2]).min(q[3]);
        let hi = q[0].max(q[1]).max(q[2]).max(q[3]);
        let short = DEGENERATE_EDGE_RELATIVE * (hi - lo).length();
        let e = [q[1] - q[0], q[2] - q[1], q[3] - q[2], q[0] - q[3]];
        let len = e.map(|e| e.length());
        if len.iter().any(|&l| l == 0.0 || l < short) {
            return 0.0;
        }
        (0..4)
            .map(|i| e[(i + 3) % 4].perp_dot(e[i]) / (len[i] * len[(i + 3) % 4]))
            .fold(f64::INFINITY, f64::min)
            .clamp(-1.0, 1.0)
    }

    #[test]
    fn the_short_edge_test_without_the_diagonal_agrees_at_the_cut_off() {
        // Quads with one edge within a few ulps of the cut-off (10 eps times the diagonal),
        // shorter and longer, in every direction: the same bits as the reference.
        let mut rnd = crate::test_rng::xorshift(0x51ed_2701_aa3c_9e11u64);
        let (mut zero, mut nonzero) = (0, 0);
        for _ in 0..200_000 {
            let angle = 3.2 * rnd();
            let q0 = DVec2::new(rnd(), rnd());
            let q2 = DVec2::new(1.0 + rnd(), 1.0 + rnd()) * 4.0;
            let q3 = DVec2::new(rnd(), 3.0 + rnd());
            let lo = q0.min(q2).min(q3);
            let hi = q0.max(q2).max(q3);
            // An edge q0 -> q1 of about the cut-off's length (q1 stays inside the box).
            let cut = DEGENERATE_EDGE_RELATIVE * (hi - lo).length();
            let q1 = q0 + DVec2::from_angle(angle) * cut * (1.0 + 8.0 * f64::EPSILON * rnd());
            let q = [q0, q1, q2, q3];
            let (got, want) = (scaled_jacobian_in_range(&q), reference_in_range(&q));
            assert_eq!(got.to_bits(), want.to_bits(), "{q:?}");
            if want == 0.0 { zero += 1 } else { nonzero += 1 }
        }
        // Both sides of the cut-off were exercised.
        assert!(zero > 1000 && nonzero > 1000, "{zero} degenerate, {nonzero} not");
        // Thin rectangles at the origin (so the short sides are exact), where the diagonal is
        // nearly dx + dy and the bound is tight: a height within ulps of the cut-off.
        let (mut zero, mut nonzero) = (0, 0);
        for k in 0..100_000 {
            let width = 1.0 + rnd().abs();
            let ulps = (k % 33) as f64 - 16.0;
            let height = DEGENERATE_EDGE_RELATIVE * width * (1.0 + ulps * f64::EPSILON);
            let q = [DVec2::ZERO, DVec2::new(width, 0.0), DVec2::new(width, height), DVec2::new(0.0, height)];
            let (got, want) = (scaled_jacobian_in_range(&q), reference_in_range(&q));
            assert_eq!(got.to_bits(), want.to_bits(), "{q:?}");
            if want == 0.0 { zero += 1 } else { nonzero += 1 }
        }
        assert!(zero > 1000 && nonzero > 1000, "thin: {zero} degenerate, {nonzero} not");
    }

    use super::*;

    fn quad(c: [(f64, f64); 4]) -> [DVec2; 4] {
        c.map(|(x, y)| DVec2::new(x, y))
    }

    #[test]
    fn square_and_rectangle_score_one() {
        assert_eq!(scaled_jacobian(&quad([(0., 0.), (1., 0.), (1., 1.), (0., 1.)])), 1.0);
        assert_eq!(scaled_jacobian(&quad([(0., 0.), (5., 0.), (5., 0.1), (0., 0.1)])), 1.0);
    }

    #[test]
    fn rhombus_scores_sine_of_its_angle() {
        // 60 degree rhombus: every corner has |sin| = sin 60.
        let s = 3f64.sqrt() / 2.0;
        let q = quad([(0., 0.), (1., 0.), (1.5, s), (0.5, s)]);
        assert!((scaled_jacobian(&q) - s).abs() < 1e-15);
    }

    #[test]
    fn reflex_corner_is_negative() {
        // Dart: the corner at (0.5, 0.2) has an interior angle above 180 degrees.
        // Hand computation: e1 = (0,1)-(0.5,0.2) = (-0.5,0.8), e2 = (1,0)-(0.5,0.2) = (0.5,-0.2)
        // cross(e1, e2) = -0.5*-0.2 - 0.8*0.5 = -0.3; lengths sqrt(0.89), sqrt(0.29).
        let q = quad([(0., 0.), (1., 0.), (0.5, 0.2), (0., 1.)]);
        let expected = -0.3 / (0.89f64.sqrt() * 0.29f64.sqrt());
        assert!((scaled_jacobian(&q) - expected).abs() < 1e-15);
    }

    #[test]
    fn clockwise_quad_is_inverted_against_the_mesh_normal() {
        assert_eq!(scaled_jacobian(&quad([(0., 0.), (0., 1.), (1., 1.), (1., 0.)])), -1.0);
    }

    #[test]
    fn degenerate_edge_scores_zero() {
        assert_eq!(scaled_jacobian(&quad([(0., 0.), (0., 0.), (1., 1.), (0., 1.)])), 0.0);
    }

    #[test]
    fn collapsed_quad_is_measured_as_its_triangle() {
        let h = 3f64.sqrt() / 2.0;
        let q = quad([(0., 0.), (1., 0.), (0.5, h), (0.5, h)]);
        assert!((scaled_jacobian(&q) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn stats_count_inverted_and_order_results() {
        let s = QualityStats::from_values(&[0.5, -0.25, 1.0, 0.0]);
        assert_eq!((s.min, s.max, s.inverted), (-0.25, 1.0, 2));
        assert!((s.avg - 0.3125).abs() < 1e-15);
        let t = QualityStats::from_values(&[0.1, 0.2]);
        assert!(t.better_than(&s));
        assert!(!s.better_than(&t));
        // Minima within the tie: the average decides; beyond it, the minimum.
        let a = QualityStats { min: 0.5, avg: 0.7, max: 1.0, inverted: 0 };
        let b = QualityStats { min: 0.5005, avg: 0.6, max: 1.0, inverted: 0 };
        assert!(b.better_than(&a) && !a.better_than(&b));
        assert!(a.better_than_with_tie(&b, 1e-3) && !b.better_than_with_tie(&a, 1e-3));
        assert!(b.better_than_with_tie(&a, 1e-4));
        let inverted = QualityStats { inverted: 1, min: 0.9, avg: 0.95, ..a };
        assert!(a.better_than_with_tie(&inverted, 1e-3) && a.better_than(&inverted));
    }

    #[test]
    fn below_decides_as_the_scaled_jacobian_does_and_mostly_without_it() {
        // Random quads (convex, folded, nearly degenerate, collapsed, extreme scales) against
        // floors across the range, most of them within a few ulps of the quad's own value: the
        // answer is always `scaled_jacobian(q) < floor`.
        let mut rnd = crate::test_rng::xorshift(0x2545_f491_4f6c_dd1d);
        let mut next = || 0.5 * rnd();
        let (mut decided, mut far, mut total, mut below) = (0, 0, 0, 0);
        for k in 0..400_000 {
            let scale = if k % 5 == 0 { 2f64.powf(600.0 * next()) } else { 1.0 + next() };
            let spread = match k % 11 {
                0 => 1e-14,
                1 => 2.0,
                _ => 0.3,
            };
            let mut q =
                [DVec2::new(0.0, 0.0), DVec2::new(1.0, 0.0), DVec2::new(1.0, 1.0), DVec2::new(0.0, 1.0)]
                    .map(|p| (p + spread * DVec2::new(next(), next())) * scale);
            if k % 97 == 0 {
                q[3] = q[2];
            }
            let sj = scaled_jacobian(&q);
            let floor = match k % 6 {
                0 => next() + 0.5,
                1 => sj,
                2 => f64::from_bits(sj.to_bits().wrapping_add((k % 9) as u64).wrapping_sub(4)),
                3 => sj * (1.0 + 1e-10 * next()),
                4 => [f64::NAN, 0.0, -0.5, 1.0, 1.5, 1e-30, f64::INFINITY][k / 6 % 7],
                _ => 0.05,
            };
            let want = sj < floor;
            assert_eq!(scaled_jacobian_below(&q, floor), want, "{q:?} {floor} {sj}");
            total += 1;
            below += usize::from(want);
            if k % 6 == 0 || k % 6 == 5 {
                far += 1;
                decided += usize::from(super::below_from_squares(&q, floor).is_some());
            }
        }
        // A floor not within rounding of the quad's value is decided without the scaled
        // Jacobian (but for the collapsed, nearly degenerate and extreme quads).
        assert!(decided * 10 > far * 7, "{decided} of {far}");
        assert!(below > total / 5 && below < total * 4 / 5, "{below} of {total}");
    }
}
