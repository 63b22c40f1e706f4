//! Element quality in 3D: the scaled Jacobian of quads and triangles of a surface mesh.
//!
//! Two measures, both in `[-1, 1]` and 1 for a square or an equilateral triangle:
//!
//! * [`verdict_scaled_jacobian`]: **Verdict's** 3D value, what VTK's `vtkMeshQuality` prints for
//!   a quad or a triangle with z coordinates (`quad_scaled_jacobian` / `tri_scaled_jacobian`).
//!   A quad's corners are measured against the quad's own *centre normal*
//!   `n = (e0 - e2) x (e1 - e3)` (`e_i` the edge from corner `i` to `i + 1`): corner `i` scores
//!   `n_hat . (e_(i-1) x e_i) / (|e_(i-1)| |e_i|)` and the quad its worst corner. The normal is
//!   the quad's own, so a quad folded across a diagonal still scores positive (a square folded
//!   by 175 degrees scores 0.0436) and a clockwise planar quad scores as its counter-clockwise
//!   twin. A triangle's value is unsigned: `|2 area| * 2/sqrt(3)` over the largest product of two
//!   edge lengths. This is the value to report next to other tools.
//! * [`signed_scaled_jacobian`]: the value the optimizer **ranks** by: each corner's cross
//!   product `e_(i-1) x e_i` measured against a *given* reference normal at that corner (the
//!   reference surface's normal, one per corner, or [`signed_scaled_jacobian_along`] with one per
//!   face), so a corner turned over with respect to the surface is negative and a folded quad
//!   counts as inverted where Verdict scores it positive. For a triangle the one cross product
//!   (twice its area, as a vector) is measured against each corner's normal and the worst
//!   counts. In the plane (z = 0) with the normal +z it is [`crate::quality::scaled_jacobian`]
//!   of the 2D corners: the same value, bit for bit except that a zero may come out as -0.0
//!   where the planar one gives +0.0 or the reverse (`==` holds always; tests/verdict_3d.rs).
//!
//! Both follow the planar measure's rules (src/quality.rs): an edge shorter than 10
//! `f64::EPSILON` times the diagonal of the face's bounding box makes the quad degenerate (0,
//! Verdict's relative test); a quad whose last two corners are bit-identical is measured as the
//! triangle of its first three (a triangle face is passed that way: [`corners`] repeats its last
//! corner, as [`crate::face::fourth_corner`] does); the corners are first scaled by a power of
//! two (exact) so that no product over- or underflows and a face scaled by `2^s` gets the same
//! value bit for bit. Values are clamped to `[-1, 1]` (Verdict's are not: it can give
//! 1.0000000000000002).
//!
//! Where quadopt's Verdict value departs from VTK 9.7.2's, deliberately (scale invariance, as in
//! the plane; tools/verdict_reference.py, "Faces in 3D"):
//!
//! * Verdict zeroes the centre normal when `|n| <= 20 f64::EPSILON`, an absolute threshold, so
//!   every quad with `|n|` (four times its projected area) below 4.4e-15 scores 0. quadopt
//!   applies that threshold to the edges scaled by a power of two so that their largest
//!   component is in [1, 2): it gives 0 only for a centre normal that vanishes relative to the
//!   quad's size (a symmetric bowtie, four collinear points), and a tiny quad gets the value of
//!   the same quad scaled up. At the other end, Verdict's `|n|` overflows for edges beyond
//!   about 1e77 (a unit square scaled by 2^255 scores 0 in VTK); quadopt's does not.
//! * Verdict's triangle gives 0 when the diagonal of its bounding box is below 2.2e-15 (absolute)
//!   and, for coordinates beyond about 1e154, when that diagonal overflows; quadopt's triangle
//!   gives 0 only for a triangle collapsed to a point.

use crate::face::Face;
use crate::power_of_two::{binary_exponent, scale_by_power_of_two};
use glam::DVec3;

/// The planar measure's relative short-edge cut-off (`quality.rs`): an edge shorter than this
/// fraction of the diagonal of the face's bounding box is degenerate.
const DEGENERATE_EDGE_RELATIVE: f64 = 10.0 * f64::EPSILON;

/// The planar measure's cut-off for a collapsed triangle, on edges scaled so the largest
/// component is in [1, 2).
const DEGENERATE_TRIANGLE: f64 = 1.0e-30;

/// Verdict's `VerdictVector::normalize` sets a vector no longer than this to zero (20
/// `f64::EPSILON`); here applied to the centre normal of edges scaled into [1, 2).
const NORMAL_MIN: f64 = 20.0 * f64::EPSILON;

/// The exponent `e` that scales `v` by `2^-e` so the largest absolute component lies in [1, 2)
/// (0 when every component is 0).
#[inline]
fn unit_exponent3(v: &[DVec3]) -> i32 {
    let m = v.iter().fold(0.0f64, |m, p| m.max(p.x.abs()).max(p.y.abs()).max(p.z.abs()));
    if m > 0.0 { binary_exponent(m) } else { 0 }
}

/// `p * 2^e`, component-wise and exact (see [`scale_by_power_of_two`]).
#[inline]
fn scale3(p: DVec3, e: i32) -> DVec3 {
    DVec3::new(scale_by_power_of_two(p.x, e), scale_by_power_of_two(p.y, e), scale_by_power_of_two(p.z, e))
}

/// `q` scaled by the power of two that brings its largest coordinate into [1, 2).
#[inline]
fn scaled_corners(q: &[DVec3; 4]) -> [DVec3; 4] {
    let e = -unit_exponent3(q);
    q.map(|p| scale3(p, e))
}

/// The edges of a quad (edge `i` from corner `i` to corner `i + 1`) and their lengths, or `None`
/// when an edge is degenerate: zero, or shorter than [`DEGENERATE_EDGE_RELATIVE`] times the
/// diagonal of the quad's bounding box (the planar measure's rule, which is Verdict's).
#[inline]
fn quad_edges(q: &[DVec3; 4]) -> Option<([DVec3; 4], [f64; 4])> {
    let e = [q[1] - q[0], q[2] - q[1], q[3] - q[2], q[0] - q[3]];
    let len = e.map(|e| e.length());
    let lo = q[0].min(q[1]).min(q[2]).min(q[3]);
    let hi = q[0].max(q[1]).max(q[2]).max(q[3]);
    let short = DEGENERATE_EDGE_RELATIVE * (hi - lo).length();
    if len.iter().any(|&l| l == 0.0 || l < short) {
        return None;
    }
    Some((e, len))
}

/// Verdict's scaled Jacobian of a quad in 3D (VTK's `vtkMeshQuality`, quad measure
/// "ScaledJacobian"): the minimum over the corners of the corner's cross product against the
/// quad's unit centre normal, over the product of the corner's two edge lengths. A quad whose
/// last two corners are identical is Verdict's triangle ([`verdict_triangle_scaled_jacobian`]).
/// 0 for a degenerate edge and for a centre normal that vanishes relative to the quad's size;
/// see the module documentation for how this departs from VTK (scale invariance).
///
/// ```
/// use glam::DVec3;
/// // A square with one corner lifted by 1: sqrt(2 / (1 + 2)) (see tests/verdict_3d.rs).
/// let q = [DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 1.0), DVec3::Y];
/// let v = quadopt::quality3d::verdict_scaled_jacobian(&q);
/// assert!((v - (2.0f64 / 3.0).sqrt()).abs() < 1e-15);
/// ```
pub fn verdict_scaled_jacobian(q: &[DVec3; 4]) -> f64 {
    if q[3] == q[2] {
        return verdict_triangle_scaled_jacobian(q[0], q[1], q[2]);
    }
    let q = scaled_corners(q);
    let Some((e, len)) = quad_edges(&q) else {
        return 0.0;
    };
    // The centre normal from the edges scaled so their largest component is in [1, 2): the
    // scaling is exact, so the direction is Verdict's bit for bit, and the threshold relative.
    let s = -unit_exponent3(&e);
    let es = e.map(|e| scale3(e, s));
    let n = (es[0] - es[2]).cross(es[1] - es[3]);
    let ln = n.length();
    if ln <= NORMAL_MIN {
        return 0.0;
    }
    let n = n / ln;
    let mut min = f64::INFINITY;
    for i in 0..4 {
        let j = (i + 3) % 4;
        min = min.min(n.dot(e[j].cross(e[i])) / (len[i] * len[j]));
    }
    min.clamp(-1.0, 1.0)
}

/// Verdict's scaled Jacobian of a triangle in 3D (VTK's `vtkMeshQuality`, triangle measure
/// "ScaledJacobian"), unsigned: `|2 area| * 2/sqrt(3)` over the largest product of two edge
/// lengths, in [0, 1], 1 for an equilateral triangle. Computed on edges scaled by a power of two
/// (largest component in [1, 2)), so 0 only for a triangle collapsed to a point.
pub fn verdict_triangle_scaled_jacobian(a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let (e0, e2, max_product) = match scaled_triangle_edges(a, b, c) {
        Some(t) => t,
        None => return 0.0,
    };
    let jacobian = e0.cross(-e2).length();
    (jacobian * 2.0 / 3.0_f64.sqrt() / max_product).clamp(-1.0, 1.0)
}

/// A triangle's edges `b - a` and `a - c` scaled by a power of two so the largest component
/// of the three edges is in [1, 2), and the largest product of two edge lengths; `None` below
/// the planar measure's cut-off (a triangle collapsed to a point).
#[inline]
fn scaled_triangle_edges(a: DVec3, b: DVec3, c: DVec3) -> Option<(DVec3, DVec3, f64)> {
    let (e0, e1, e2) = (b - a, c - b, a - c);
    let s = -unit_exponent3(&[e0, e1, e2]);
    let (e0, e1, e2) = (scale3(e0, s), scale3(e1, s), scale3(e2, s));
    let (l0, l1, l2) = (e0.length(), e1.length(), e2.length());
    let max_product = (l0 * l2).max(l0 * l1).max(l1 * l2);
    (max_product >= DEGENERATE_TRIANGLE).then_some((e0, e2, max_product))
}

/// The signed scaled Jacobian of a quad in 3D against reference normals, one per corner
/// (nonzero, any length: they are normalized here): the minimum over the corners of
/// `n_i . (e_(i-1) x e_i) / (|e_(i-1)| |e_i|)`, in [-1, 1]. Negative when a corner turns the
/// wrong way with respect to its normal, so a quad folded over (convex or not) is inverted.
/// 0 for a degenerate edge (as in the plane). A quad whose last two corners are identical is
/// the signed triangle of its first three: its cross product `(p1 - p0) x (p2 - p0)` scaled by
/// 2/sqrt(3) over the largest product of two edge lengths, measured against each of
/// `normals[0..3]`, the worst counting.
///
/// With z = 0 and every normal +z it equals [`crate::quality::scaled_jacobian`] of the 2D
/// corners (up to the sign of a zero).
///
/// ```
/// use glam::DVec3;
/// let q = [DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 1.0), DVec3::Y];
/// // Against +z: the lifted corner's edges are sqrt(2) long, its cross product (-1, -1, 1).
/// let v = quadopt::quality3d::signed_scaled_jacobian(&q, &[DVec3::Z; 4]);
/// assert!((v - 0.5).abs() < 1e-15);
/// // Against -z the quad is inverted.
/// assert!(quadopt::quality3d::signed_scaled_jacobian_along(&q, -DVec3::Z) < 0.0);
/// ```
pub fn signed_scaled_jacobian(q: &[DVec3; 4], normals: &[DVec3; 4]) -> f64 {
    debug_assert!(normals.iter().all(|n| n.is_finite() && n.length_squared() > 0.0), "{normals:?}");
    signed_scaled_jacobian_unit(q, &normals.map(|n| n / n.length()))
}

/// [`signed_scaled_jacobian`] against normals that are unit already (the optimizer's, which it
/// evaluates for every candidate: normalizing them again is a tenth of the time).
pub(crate) fn signed_scaled_jacobian_unit(q: &[DVec3; 4], n: &[DVec3; 4]) -> f64 {
    debug_assert!(n.iter().all(|n| (n.length() - 1.0).abs() < 1e-9 || *n == DVec3::ZERO), "{n:?}");
    let q = scaled_corners(q);
    if q[3] == q[2] {
        return signed_triangle(q[0], q[1], q[2], [n[0], n[1], n[2]]);
    }
    let Some((e, len)) = quad_edges(&q) else {
        return 0.0;
    };
    let mut min = f64::INFINITY;
    for i in 0..4 {
        // As in the plane: edges out of corner i are e[i] and -e[i - 1], and
        // cross(e[i], -e[i - 1]) = cross(e[i - 1], e[i]).
        let j = (i + 3) % 4;
        min = min.min(n[i].dot(e[j].cross(e[i])) / (len[i] * len[j]));
    }
    min.clamp(-1.0, 1.0)
}

/// A quad one of whose corners is about to be tried at many positions (a vertex's candidates,
/// with its star's other corners where they are): what [`signed_scaled_jacobian_unit`] needs of
/// the three others, computed once, so that a position costs the two edges at the moving
/// corner and three corners' values instead of four edges and four corners. The value is
/// [`signed_scaled_jacobian_unit`]'s bit for bit: the same scaled corners, edges and
/// operations, the fourth corner's (both of whose edges are fixed) computed ahead; a position
/// that changes the quad's scaling exponent, and a triangle, take the full computation.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct MovingCorner {
    /// Which corner moves.
    k: usize,
    /// The corners as given (`q[k]` where it is now) and their unit normals.
    q: [DVec3; 4],
    n: [DVec3; 4],
    /// The fixed corners' scaling exponent (the quad's, if the moving corner does not change
    /// it) and the bound below which a coordinate leaves it unchanged: 0 if none applies.
    exponent: i32,
    below: f64,
    /// Scaled: the corners before and after the moving one, the two fixed edges' vectors and
    /// lengths (edge `i` from corner `i` to `i + 1`), the fixed corners' bounding box, and the
    /// value of the corner opposite the moving one.
    prev: DVec3,
    next: DVec3,
    e: [DVec3; 4],
    len: [f64; 4],
    lo: DVec3,
    hi: DVec3,
    opposite: f64,
}

impl MovingCorner {
    /// Quad `q` with unit normals `n`, corner `k` to move.
    pub(crate) fn new(q: &[DVec3; 4], n: &[DVec3; 4], k: usize) -> MovingCorner {
        let fixed = [q[(k + 1) % 4], q[(k + 2) % 4], q[(k + 3) % 4]];
        let m = fixed.iter().fold(0.0f64, |m, p| m.max(p.x.abs()).max(p.y.abs()).max(p.z.abs()));
        let mut c = MovingCorner { k, q: *q, n: *n, ..MovingCorner::default() };
        // A triangle (last two corners equal) or corners at the origin: the full computation.
        if q[3] == q[2] || !(m > 0.0 && m.is_finite()) {
            return c;
        }
        let unit = binary_exponent(m);
        c.exponent = -unit;
        c.below = scale_by_power_of_two(2.0, unit);
        let s = fixed.map(|p| scale3(p, c.exponent));
        (c.next, c.prev) = (s[0], s[2]);
        let (a, b) = ((k + 1) % 4, (k + 2) % 4);
        (c.e[a], c.e[b]) = (s[1] - s[0], s[2] - s[1]);
        (c.len[a], c.len[b]) = (c.e[a].length(), c.e[b].length());
        c.lo = s[0].min(s[1]).min(s[2]);
        c.hi = s[0].max(s[1]).max(s[2]);
        c.opposite = n[b].dot(c.e[a].cross(c.e[b])) / (c.len[b] * c.len[a]);
        c
    }

    /// The moving corner's number in the quad.
    #[inline]
    pub(crate) fn corner(&self) -> usize {
        self.k
    }

    /// The quad's [`signed_scaled_jacobian_unit`] with the moving corner at `p`, its normal
    /// `normal`.
    #[inline]
    pub(crate) fn value(&self, p: DVec3, normal: DVec3) -> f64 {
        let k = self.k;
        let largest = p.x.abs().max(p.y.abs()).max(p.z.abs());
        // Beyond the fixed corners' binade the quad's scaling changes; on the corner after or
        // before it (corners 2 and 3) the quad becomes a triangle.
        let triangle = (k == 2 && p == self.q[3]) || (k == 3 && p == self.q[2]);
        if !(self.below > 0.0 && largest < self.below) || triangle {
            let (mut q, mut n) = (self.q, self.n);
            (q[k], n[k]) = (p, normal);
            return signed_scaled_jacobian_unit(&q, &n);
        }
        let prev = (k + 3) % 4;
        let x = scale3(p, self.exponent);
        let (mut e, mut len) = (self.e, self.len);
        // The fixed corners are scaled exactly as the full computation scales them.
        e[prev] = x - self.prev;
        e[k] = self.next - x;
        (len[prev], len[k]) = (e[prev].length(), e[k].length());
        let short = DEGENERATE_EDGE_RELATIVE * (self.hi.max(x) - self.lo.min(x)).length();
        if len.iter().any(|&l| l == 0.0 || l < short) {
            return 0.0;
        }
        let mut n = self.n;
        n[k] = normal;
        let corner = |i: usize| {
            let j = (i + 3) % 4;
            n[i].dot(e[j].cross(e[i])) / (len[i] * len[j])
        };
        // In corner order, as the full computation takes the minimum (a signed zero's sign
        // depends on it).
        let mut min = f64::INFINITY;
        for i in 0..4 {
            min = min.min(if i == (k + 2) % 4 { self.opposite } else { corner(i) });
        }
        min.clamp(-1.0, 1.0)
    }
}

/// [`signed_scaled_jacobian`] with one reference normal for the whole face.
#[inline]
pub fn signed_scaled_jacobian_along(q: &[DVec3; 4], normal: DVec3) -> f64 {
    signed_scaled_jacobian(q, &[normal; 4])
}

/// The signed triangle of [`signed_scaled_jacobian`], on corners already scaled (unit normals).
fn signed_triangle(a: DVec3, b: DVec3, c: DVec3, normals: [DVec3; 3]) -> f64 {
    let (e0, e2, max_product) = match scaled_triangle_edges(a, b, c) {
        Some(t) => t,
        None => return 0.0,
    };
    let cross = e0.cross(-e2);
    let jacobian = normals[0].dot(cross).min(normals[1].dot(cross)).min(normals[2].dot(cross));
    (jacobian * 2.0 / 3.0_f64.sqrt() / max_product).clamp(-1.0, 1.0)
}

/// The four corner positions of a face in 3D; a triangle's last corner twice, which both
/// measures read as the triangle (see [`crate::face::fourth_corner`]).
#[inline]
pub fn corners(points: &[DVec3], f: &Face) -> [DVec3; 4] {
    let d = crate::face::fourth_corner(f);
    [points[f[0] as usize], points[f[1] as usize], points[f[2] as usize], points[d as usize]]
}

/// The reference normals at the four corners of a face, from one normal per vertex (a
/// triangle's last normal twice, as in [`corners`]).
#[inline]
pub fn corner_normals(vertex_normals: &[DVec3], f: &Face) -> [DVec3; 4] {
    corners(vertex_normals, f)
}

/// Verdict's 3D scaled Jacobian of every face of `faces` (indices into `points`).
pub fn verdict_values(points: &[DVec3], faces: &[Face]) -> Vec<f64> {
    faces.iter().map(|f| verdict_scaled_jacobian(&corners(points, f))).collect()
}

/// The signed scaled Jacobian of every face against the reference normal at each of its
/// vertices (`vertex_normals`, one per point, nonzero).
pub fn signed_values(points: &[DVec3], faces: &[Face], vertex_normals: &[DVec3]) -> Vec<f64> {
    faces
        .iter()
        .map(|f| signed_scaled_jacobian(&corners(points, f), &corner_normals(vertex_normals, f)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scaling_by_a_power_of_two_keeps_the_bits() {
        let mut rnd = crate::test_rng::xorshift(0x3d3d_0badc0de_u64);
        for k in 0..20_000 {
            let q: [DVec3; 4] = std::array::from_fn(|_| DVec3::new(rnd(), rnd(), rnd()));
            let mut q = q;
            if k % 9 == 0 {
                q[3] = q[2];
            }
            let n: [DVec3; 4] = std::array::from_fn(|_| DVec3::new(rnd(), rnd(), 1.0));
            let s = k % 400 - 200;
            let big = q.map(|p| scale3(p, s));
            assert_eq!(verdict_scaled_jacobian(&q).to_bits(), verdict_scaled_jacobian(&big).to_bits());
            assert_eq!(signed_scaled_jacobian(&q, &n).to_bits(), signed_scaled_jacobian(&big, &n).to_bits());
        }
    }

    #[test]
    fn a_moving_corner_gives_the_full_computation_bit_for_bit() {
        let mut rnd = crate::test_rng::xorshift(0x600d_cafe_u64);
        let mut fast = 0;
        for t in 0..40_000 {
            // Quads around the origin and far from it, tiny and huge, with degenerate edges,
            // triangles, and positions that change the scaling exponent.
            let scale = [1.0, 1e-12, 3e8, 1e150, 1e-150][t % 5];
            let offset = DVec3::new(rnd(), rnd(), rnd()) * [0.0, 1.0, 1e6][t % 3];
            let mut q: [DVec3; 4] =
                std::array::from_fn(|_| DVec3::new(rnd(), rnd(), 0.2 * rnd()) * scale + offset);
            if t % 11 == 0 {
                q[3] = q[2];
            }
            if t % 13 == 0 {
                q[1] = q[0] + DVec3::splat(1e-17 * scale);
            }
            let n: [DVec3; 4] =
                std::array::from_fn(|_| DVec3::new(0.3 * rnd(), 0.3 * rnd(), 1.0).normalize());
            let k = t % 4;
            let corner = MovingCorner::new(&q, &n, k);
            for _ in 0..4 {
                let p = match t % 7 {
                    0 => q[(k + 1) % 4],
                    1 => q[k] * 4.0,
                    _ => q[k] + DVec3::new(rnd(), rnd(), 0.1 * rnd()) * scale * 0.5,
                };
                let normal = DVec3::new(0.2 * rnd(), 0.2 * rnd(), 1.0).normalize();
                let (mut full_q, mut full_n) = (q, n);
                (full_q[k], full_n[k]) = (p, normal);
                let expected = signed_scaled_jacobian_unit(&full_q, &full_n);
                assert_eq!(
                    corner.value(p, normal).to_bits(),
                    expected.to_bits(),
                    "{full_q:?} {full_n:?} corner {k}"
                );
                fast += usize::from(corner.below > 0.0 && p.abs().max_element() < corner.below);
            }
        }
        // Most positions take the shortcut (the test would pass vacuously otherwise).
        assert!(fast > 80_000, "{fast}");
    }
}
