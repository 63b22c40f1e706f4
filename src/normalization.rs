//! Coordinate normalization: the optimizer works on coordinates centred on the mesh's bounding
//! box, divided by its larger half-extent and rounded to a grid, so that no result depends on
//! the units or the position the mesh is given in and nothing overflows or underflows at any
//! finite scale.
//!
//! - Subtract the box's centre, scale by a power of two (exact, and safe over the whole number
//!   range), then divide by the remaining half-extent in [0.5, 1): the box maps onto [-1, 1]
//!   in its larger dimension. (A mesh with edges below 2^-20 of its size keeps, per axis, a
//!   zero origin when its box lies near zero, so its small part keeps the precision it has
//!   there; the box then maps into [-3, 3]^2.) A mesh scaled by any factor `s` (or
//!   translated) maps to the same coordinates up to a few units in the last place, the
//!   rounding of the input itself.
//! - Those last-place differences would be enough to send the optimizer's discrete choices
//!   (the guard, the best iterate, the max-min stage's greedy moves) down another path, so the
//!   normalized coordinates are rounded to a grid of `2^-20` of the shortest edge (a power of
//!   two, `Normalization::grid_exponent`). Rescaled copies then get the very same bits and the
//!   very same run, unless a coordinate lies within its rounding of a grid midpoint (about one
//!   coordinate in 10^8 for a mesh whose shortest edge is a thousandth of its size). Rounding
//!   moves a vertex by at most `2^-21` of the shortest edge, which changes a quad's scaled
//!   Jacobian by about that much. It never changes a quad's sign: a quad whose sign the grid
//!   would change (a corner within 1e-6 of straight) keeps its vertices off the grid.
//! - A power-of-two factor changes no bit at all: every step is exact.
//! - The optimizer's output is mapped back with the original coordinates, bit for bit, of
//!   every vertex that did not move (fixed vertices, corners); moved boundary vertices are
//!   re-evaluated on the original boundary polyline by the caller, so the grid never shows in
//!   the output.

use crate::alloc::try_copy;
use crate::error::Result;
use crate::face;
use crate::power_of_two::{binary_exponent, pow2, scale_by_power_of_two};
use crate::quality::{corners, sign_class};
use glam::DVec2;
use rayon::prelude::*;

/// The map between a mesh's coordinates and the normalized ones the optimizer works on:
/// `normalized = round_grid(((p - origin) * 2^-exponent) / unit)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Normalization {
    origin: DVec2,
    exponent: i32,
    /// The larger half-extent of the box after the power-of-two scaling, in [0.5, 1).
    unit: f64,
    /// Normalized coordinates are multiples of `2^-grid`.
    grid: i32,
    /// The origin of [`Normalization::without_grid`]: the box's centre rounded towards zero to
    /// a multiple of a power of two larger than the box (zero when the box contains zero).
    exact_origin: DVec2,
}

/// Bits of the shortest edge below which the normalized coordinates are rounded.
const GRID_BITS: i32 = 20;

/// The finest grid, 2^-1100: below the smallest subnormal, where rounding changes nothing. The
/// grid follows the shortest edge however small it is against the box (a mesh with one vertex
/// 1e298 away from the rest must keep the rest apart).
const FINEST_GRID: i32 = 1100;

impl Normalization {
    /// The identity map.
    pub const IDENTITY: Normalization = Normalization {
        origin: DVec2::ZERO,
        exponent: 0,
        unit: 1.0,
        grid: FINEST_GRID,
        exact_origin: DVec2::ZERO,
    };

    /// The normalization of the vertices used by `quads` (finite coordinates): their bounding
    /// box maps onto [-1, 1] in its larger dimension, centred on the origin (into [-3, 3]^2,
    /// not centred, for meshes with edges below 2^-20 of their size).
    pub fn new(points: &[DVec2], quads: &[[u32; 4]]) -> Normalization {
        // In parallel: minima and maxima do not depend on the order.
        let empty = || (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        let (lo, hi) = quads
            .par_iter()
            .with_min_len(crate::quality::PARALLEL_CHUNK)
            .fold(empty, |(lo, hi), q| {
                q.iter()
                    .filter_map(|&v| points.get(v as usize))
                    .fold((lo, hi), |(lo, hi), &p| (lo.min(p), hi.max(p)))
            })
            .reduce(empty, |(a, b), (c, d)| (a.min(c), b.max(d)));
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
        let unit = scale_by_power_of_two(half_extent, -exponent);
        let scaled = |p: DVec2| {
            DVec2::new(scale_by_power_of_two(p.x, -exponent), scale_by_power_of_two(p.y, -exponent)) / unit
        };
        // Halved first, so that no difference overflows.
        let shortest = 2.0 * shortest_edge(quads, |v| points.get(v as usize).map(|&p| scaled(p * 0.5)));
        // The origin is the box's centre, so that translated (and rescaled) copies of a mesh
        // normalize alike. Subtracting it costs coordinates near zero their precision, which
        // only matters when the mesh has edges below 2^-GRID_BITS of its box (one vertex 1e298
        // away from the rest): then, per axis, the origin is zero when the box lies within two
        // half-extents of it, keeping the small part apart. A rounded centre would not scale
        // with the mesh.
        let centre = lo * 0.5 + hi * 0.5;
        let near = |c: f64| c.abs() <= 2.0 * half_extent;
        // (shortest_edge gives a finite length, 0 when there is none.)
        let tiny_edges = shortest < scale_by_power_of_two(1.0, -GRID_BITS);
        let origin = DVec2::new(
            if tiny_edges && near(centre.x) { 0.0 } else { centre.x },
            if tiny_edges && near(centre.y) { 0.0 } else { centre.y },
        );
        // Round the centre towards zero to a multiple of 2^g > the extent: zero when the box
        // contains the origin, and few significant bits otherwise. Past 2^1023 no translation
        // is needed (the box is as large as the number range).
        let g = exponent + 1;
        let exact_origin = if g > 1023 {
            DVec2::ZERO
        } else {
            let round = |c: f64| {
                let units = scale_by_power_of_two(c, -g);
                // |units| >= 2^52: c is already a multiple of 2^g.
                if units.abs() >= pow2(52) { c } else { scale_by_power_of_two(units.trunc(), g) }
            };
            DVec2::new(round(centre.x), round(centre.y))
        };
        let mut n = Normalization { origin, exponent, unit, grid: FINEST_GRID, exact_origin };
        if shortest > 0.0 && shortest.is_finite() {
            n.grid = (GRID_BITS - binary_exponent(shortest)).min(FINEST_GRID);
        }
        n
    }

    /// The exact map of the same mesh, without the grid: a scaling by a power of two (exact)
    /// after subtracting a rounded origin (zero when the box contains zero, then the
    /// normalized coordinates are the mesh's own, exactly scaled). What the optimizer sees is
    /// then what the caller gets, to the bit, but rescaled copies of a mesh no longer run alike.
    pub fn without_grid(&self) -> Normalization {
        Normalization { origin: self.exact_origin, unit: 1.0, grid: FINEST_GRID, ..*self }
    }

    /// Whether the map is exact: no grid and a scaling by a power of two only (the identity, or
    /// [`Normalization::without_grid`]).
    pub fn is_exact(&self) -> bool {
        self.grid == FINEST_GRID && self.unit == 1.0
    }

    #[cfg(test)]
    /// The centre subtracted before scaling.
    pub fn origin(&self) -> DVec2 {
        self.origin
    }

    #[cfg(test)]
    /// The power of two the coordinates are scaled by before the division by
    /// [`Normalization::unit`].
    pub fn exponent(&self) -> i32 {
        self.exponent
    }

    #[cfg(test)]
    /// The box's larger half-extent after the power-of-two scaling, in [0.5, 1) (1 for the
    /// identity).
    pub fn unit(&self) -> f64 {
        self.unit
    }

    #[cfg(test)]
    /// Normalized coordinates are multiples of `2^-grid_exponent`.
    pub fn grid_exponent(&self) -> i32 {
        self.grid
    }

    /// `p` scaled and centred, before the rounding to the grid.
    #[inline]
    fn unrounded(&self, p: DVec2) -> DVec2 {
        let d = p - self.origin;
        DVec2::new(scale_by_power_of_two(d.x, -self.exponent), scale_by_power_of_two(d.y, -self.exponent))
            / self.unit
    }

    /// [`Normalization::unrounded`], or the origin where that overflows (as
    /// [`Normalization::to_normalized`]).
    #[inline]
    fn off_grid(&self, p: DVec2) -> DVec2 {
        let q = self.unrounded(p);
        if q.is_finite() { q } else { DVec2::ZERO }
    }

    /// Normalized coordinates of `p`. A point far outside the mesh's bounding box (only a vertex
    /// used by no quad can be) that would overflow maps to the origin.
    #[inline]
    pub fn to_normalized(self, p: DVec2) -> DVec2 {
        let q = self.unrounded(p);
        let round = |x: f64| {
            let units = scale_by_power_of_two(x, self.grid);
            // |units| >= 2^52: x is already a multiple of the grid (and not finite past it).
            if units.abs() < pow2(52) { scale_by_power_of_two(units.round(), -self.grid) } else { x }
        };
        let q = DVec2::new(round(q.x), round(q.y));
        if q.is_finite() { q } else { DVec2::ZERO }
    }

    /// The mesh coordinates of normalized `q` (not finite only far outside the number range).
    #[inline]
    pub fn to_original(self, q: DVec2) -> DVec2 {
        let q = q * self.unit;
        DVec2::new(scale_by_power_of_two(q.x, self.exponent), scale_by_power_of_two(q.y, self.exponent))
            + self.origin
    }

    /// A normalized length in mesh units.
    #[inline]
    pub fn length_to_original(&self, length: f64) -> f64 {
        scale_by_power_of_two(length * self.unit, self.exponent)
    }

    /// Replaces `points` (the vertices of `quads`) by their normalized coordinates and returns
    /// what [`Normalization::restore`] needs to map them back.
    ///
    /// The grid may not change any quad's sign class (valid, degenerate, inverted): a
    /// near-degenerate quad whose class the rounding would change keeps its vertices
    /// unrounded, so that what the optimizer sees inverted is what the caller sees inverted.
    /// After [`MAX_SIGN_PASSES`] passes that still find such quads every vertex is left
    /// unrounded (each pass unrounds more vertices; none unrounded is the usual case).
    pub fn normalize(&self, points: &mut [DVec2], quads: &[[u32; 4]]) -> Result<Normalized> {
        let original = try_copy(points, "original coordinates")?;
        let mut unrounded = Vec::new();
        if *self == Normalization::IDENTITY {
            return Ok(Normalized { original, unrounded, all_unrounded: false });
        }
        points
            .par_iter_mut()
            .with_min_len(crate::quality::PARALLEL_CHUNK)
            .for_each(|p| *p = self.to_normalized(*p));
        let at = |v: u32| original.get(v as usize).map_or(DVec2::ZERO, |&o| self.off_grid(o));
        for _ in 0..MAX_SIGN_PASSES {
            let points_now: &[DVec2] = points;
            let changed: Vec<u32> = quads
                .par_iter()
                .filter(|q| {
                    let fourth = crate::face::fourth_corner(q);
                    face::vertices(q).iter().all(|&v| (v as usize) < points_now.len())
                        && sign_class(&corners(points_now, q))
                            != sign_class(&[q[0], q[1], q[2], fourth].map(at))
                })
                .flat_map_iter(|q| face::vertices(q).iter().copied())
                .collect();
            let before = unrounded.len();
            for v in changed {
                let p = &mut points[v as usize];
                let exact = at(v);
                if p.x.to_bits() != exact.x.to_bits() || p.y.to_bits() != exact.y.to_bits() {
                    *p = exact;
                    unrounded.push(v);
                }
            }
            if unrounded.len() == before {
                unrounded.sort_unstable();
                return Ok(Normalized { original, unrounded, all_unrounded: false });
            }
        }
        for (p, &o) in points.iter_mut().zip(&original) {
            *p = self.off_grid(o);
        }
        Ok(Normalized { original, unrounded: Vec::new(), all_unrounded: true })
    }

    /// Where [`Normalization::normalize`] put vertex `v`.
    #[inline]
    fn given(&self, normalized: &Normalized, v: usize) -> DVec2 {
        let o = normalized.original[v];
        if normalized.all_unrounded || normalized.unrounded.binary_search(&(v as u32)).is_ok() {
            self.off_grid(o)
        } else {
            self.to_normalized(o)
        }
    }

    /// Whether normalized `p` is (bitwise) where [`Normalization::normalize`] put vertex `v`.
    #[inline]
    pub fn unmoved(&self, p: DVec2, normalized: &Normalized, v: usize) -> bool {
        let q = self.given(normalized, v);
        p.x.to_bits() == q.x.to_bits() && p.y.to_bits() == q.y.to_bits()
    }

    /// Maps normalized `points` back to mesh coordinates in place: a vertex whose normalized
    /// position is (bitwise) the one [`Normalization::normalize`] gave it gets its original
    /// coordinates back exactly; a moved vertex gets its mapped position (or its original one
    /// in the impossible case that this is not finite).
    pub fn restore(&self, points: &mut [DVec2], normalized: &Normalized) {
        // Vertex by vertex, in parallel: each depends on itself only.
        points.par_iter_mut().with_min_len(crate::quality::PARALLEL_CHUNK).enumerate().for_each(|(v, p)| {
            let o = normalized.original[v];
            if self.unmoved(*p, normalized, v) {
                *p = o;
            } else {
                let back = self.to_original(*p);
                *p = if back.is_finite() { back } else { o };
            }
        });
    }
}

/// Passes of [`Normalization::normalize`]'s sign check before it gives up the grid.
const MAX_SIGN_PASSES: usize = 8;

/// What [`Normalization::normalize`] replaced: the original coordinates, and the vertices it
/// left off the grid.
#[derive(Debug)]
pub struct Normalized {
    original: Vec<DVec2>,
    /// Sorted.
    unrounded: Vec<u32>,
    all_unrounded: bool,
}

impl Normalized {
    /// The coordinates as given.
    pub fn original(&self) -> &[DVec2] {
        &self.original
    }

    #[cfg(test)]
    /// How many vertices were left off the grid to keep a quad's sign (all of them when the
    /// check gave up).
    pub fn unrounded_count(&self) -> usize {
        if self.all_unrounded { self.original.len() } else { self.unrounded.len() }
    }
}

/// The shortest non-zero edge of `quads` at the positions `at` gives (0 when there is none).
fn shortest_edge(quads: &[[u32; 4]], at: impl Fn(u32) -> Option<DVec2> + Sync) -> f64 {
    // In parallel: a minimum does not depend on the order.
    let shortest_of = |shortest: f64, q: &[u32; 4]| {
        let n = face::corner_count(q);
        (0..n).fold(shortest, |shortest, i| match (at(q[i]), at(q[(i + 1) % n])) {
            (Some(a), Some(b)) => {
                // hypot: the squares of edges near 1e-300 of the box would underflow.
                let d = b - a;
                let l = d.x.hypot(d.y);
                if l > 0.0 && l < shortest { l } else { shortest }
            }
            _ => shortest,
        })
    };
    let shortest = quads
        .par_iter()
        .with_min_len(crate::quality::PARALLEL_CHUNK)
        .fold(|| f64::INFINITY, shortest_of)
        .reduce(|| f64::INFINITY, f64::min);
    if shortest.is_finite() { shortest } else { 0.0 }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::power_of_two::scale_point;

    fn square(scale: f64, offset: DVec2) -> (Vec<DVec2>, Vec<[u32; 4]>) {
        let p = [(0., 0.), (3., 0.), (3., 2.), (0., 2.)].map(|(x, y)| DVec2::new(x, y) * scale + offset);
        (p.to_vec(), vec![[0, 1, 2, 3]])
    }

    #[test]
    fn the_box_maps_onto_the_unit_square_centred_on_the_origin() {
        // Box [-1, 2] x [-1, 1]: half-extent 1.5 in [2^0, 2^1), exponent 1 and unit 0.75, so
        // coordinates are divided by 1.5 after subtracting the centre (0.5, 0).
        let on_grid = |x: f64| (x * (1 << 20) as f64).round() / (1 << 20) as f64;
        let (p, q) = square(1.0, DVec2::new(-1.0, -1.0));
        let n = Normalization::new(&p, &q);
        assert_eq!((n.origin(), n.exponent(), n.unit()), (DVec2::new(0.5, 0.0), 1, 0.75));
        assert_eq!(n.to_normalized(DVec2::new(2.0, 1.0)), DVec2::new(1.0, on_grid(1.0 / 1.5)));
        // Shortest edge 2 / 1.5 in [1, 2): the grid is 2^-20.
        assert_eq!(n.grid_exponent(), 20);
        assert_eq!(n.to_normalized(DVec2::new(0.5, 0.3)), DVec2::new(0.0, on_grid(0.3 / 1.5)));
    }

    #[test]
    fn a_mesh_with_a_far_vertex_keeps_its_small_part_apart() {
        // Unit quads next to the origin and one vertex 8e298 away: centring would round every
        // small coordinate to the same value. The x origin stays zero (the box lies within two
        // half-extents of it), the grid follows the unit edges.
        let p = [(-8e298, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0), (2.0, 0.0), (2.0, 1.0)]
            .map(|(x, y)| DVec2::new(x, y));
        let q = [[0, 1, 2, 3], [1, 4, 5, 2]];
        let n = Normalization::new(&p, &q);
        assert_eq!(n.origin().x, 0.0);
        let small: Vec<DVec2> = p[1..].iter().map(|&x| n.to_normalized(x)).collect();
        for (i, a) in small.iter().enumerate() {
            for b in &small[i + 1..] {
                assert_ne!(a, b, "two vertices of the small part normalize to one point");
            }
        }
    }

    #[test]
    fn rescaled_meshes_normalize_to_identical_coordinates() {
        // Not powers of two: the inputs differ in their last bits, the grid absorbs that.
        let (p, q) = square(1.0, DVec2::new(0.37, -0.11));
        let p: Vec<DVec2> =
            p.iter().enumerate().map(|(i, &x)| x + DVec2::new(0.013, 0.007) * i as f64).collect();
        let unit = Normalization::new(&p, &q);
        for factor in [1e-300, 1e-17, 0.3, 7.0, 1e10, 1e300] {
            let scaled: Vec<DVec2> = p.iter().map(|&x| x * factor).collect();
            let n = Normalization::new(&scaled, &q);
            assert_eq!(n.grid_exponent(), unit.grid_exponent(), "x{factor:e}");
            for (a, b) in p.iter().zip(&scaled) {
                assert_eq!(unit.to_normalized(*a), n.to_normalized(*b), "x{factor:e}");
            }
        }
    }

    #[test]
    fn the_grid_follows_the_shortest_edge() {
        // A sliver: one edge a millionth of the box. The grid is 2^-20 of it.
        let p = [(0., 0.), (1., 0.), (1., 1e-6), (0., 1e-6)].map(|(x, y)| DVec2::new(x, y));
        let n = Normalization::new(&p, &[[0, 1, 2, 3]]);
        let shortest = (n.to_normalized(p[2]) - n.to_normalized(p[1])).length();
        let grid = scale_by_power_of_two(1.0, -n.grid_exponent());
        assert!(
            grid <= shortest * 2f64.powi(-20) && grid > shortest * 2f64.powi(-21),
            "{grid:e} {shortest:e}"
        );
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
            let original = n.normalize(&mut work, &q).unwrap();
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
        let original = n.normalize(&mut work, &q).unwrap();
        let moved = work[2] * 0.5 + work[0] * 0.5;
        work[2] = moved;
        n.restore(&mut work, &original);
        assert_eq!([work[0], work[1], work[3]], [p[0], p[1], p[3]]);
        let centre = (p[0] + p[2]) * 0.5;
        assert!((work[2] - centre).length() < 1e-11, "{} vs {centre}", work[2]);
    }

    #[test]
    fn rounding_never_changes_a_quads_sign() {
        // A quad with a corner 2e-9 short of straight, next to a plain one: on the grid (2^-20
        // of the shortest edge, about 1e-6) the corner would become straight, the quad
        // degenerate.
        let p =
            [(0., 0.), (1., -1e-9), (2., 0.), (1., 1.), (3., 0.), (3., 1.)].map(|(x, y)| DVec2::new(x, y));
        let q = [[0, 1, 2, 3], [2, 4, 5, 3]];
        let before: Vec<_> = q.iter().map(|q| sign_class(&corners(&p, q))).collect();
        let n = Normalization::new(&p, &q);
        let rounded: Vec<DVec2> = p.iter().map(|&x| n.to_normalized(x)).collect();
        let naive: Vec<_> = q.iter().map(|q| sign_class(&corners(&rounded, q))).collect();
        assert_ne!(naive, before, "the test needs a quad whose sign the plain rounding changes");
        let mut work = p.to_vec();
        let normalized = n.normalize(&mut work, &q).unwrap();
        let after: Vec<_> = q.iter().map(|q| sign_class(&corners(&work, q))).collect();
        assert_eq!(after, before);
        assert!(normalized.unrounded_count() > 0 && normalized.unrounded_count() < p.len());
        // Unmoved, every vertex comes back bit-identical, rounded or not.
        n.restore(&mut work, &normalized);
        assert_eq!(work, p.to_vec());
    }
}
