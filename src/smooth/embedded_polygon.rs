//! The embedded polygon update of an interior vertex (Sections 3.1-3.2).
//!
//! Readings of the paper's formulas (measured, see docs/method.md, "Embedded polygon of an
//! interior vertex", "Target point of the embedded polygon" and "Weights and step of Eqs. 6-8"):
//! - Embedded polygon: the edge-neighbours of v in counter-clockwise order (valence n gives n
//!   corners); adding the quads' diagonal vertices is markedly less robust.
//! - Eqs. 4-5: at corner P with a = v - P, b = (previous neighbour) - P and c = (next
//!   neighbour) - P, the interior angle is the counter-clockwise sweep from c to b. theta is the *signed*
//!   rotation turning a onto that angle's bisector, and the candidate is v rotated about P by
//!   theta (so |a_i - P| = |v - P|). This equals Eq. 4 while the spoke is inside the angle and
//!   keeps its sign on tangled input, where Eq. 4's difference of arccosines loses it.
//! - Eq. 7 as printed, w_i = 1 - |theta_i| / sum |theta_j|, normalized by sum w_i. It damps
//!   the update; weights proportional to |theta| blow up on graded meshes.
//! - Eq. 8 as v' = v + lambda (sum w_i a_i / sum w_i - v): read literally it collapses the
//!   mesh in one sweep. The lambda step is applied by the caller.

use glam::DVec2;

/// Unit bisector of the counter-clockwise sweep from direction `c` to direction `b` (both
/// non-zero), without trigonometry. Half the sum of the unit vectors when they make an acute
/// angle (negated when the sweep is reflex, i.e. nearly a full turn), else the clockwise
/// perpendicular of their difference: each form is used where it is well conditioned (its
/// length is at least sqrt(2) before normalizing).
#[inline(always)]
fn bisector(c: DVec2, b: DVec2) -> DVec2 {
    unit_bisector(c / c.length(), b / b.length())
}

/// [`bisector`] of the unit directions `c` and `b`.
#[inline(always)]
fn unit_bisector(c: DVec2, b: DVec2) -> DVec2 {
    if c.dot(b) > 0.0 {
        let sum = c + b;
        let sum = sum / sum.length();
        if c.perp_dot(b) >= 0.0 { sum } else { -sum }
    } else {
        let d = b - c;
        DVec2::new(d.y, -d.x) / d.length()
    }
}

/// tan(pi / 8): above it, [`abs_rotation`] works with the angle's difference from pi / 4.
const TAN_PI_8: f64 = 0.414_213_562_373_095_03;

/// Coefficients of atan(u) = u + u^3 (c0 + c1 u^2 + ... + c9 u^18) on |u| <= tan(pi / 8):
/// a least-squares fit of the relative error on Chebyshev nodes (in 50-digit arithmetic);
/// evaluated in f64 it is within 1 ulp of atan there.
const ATAN_COEFFICIENTS: [f64; 10] = [
    -0.333_333_333_333_299_4,
    0.199_999_999_990_457_17,
    -0.142_857_141_920_660_68,
    0.111_111_065_346_641_04,
    -0.090_907_798_689_403_32,
    0.076_900_351_150_696_28,
    -0.066_408_526_597_346_61,
    0.056_912_234_889_686_05,
    -0.043_555_219_035_647_214,
    0.021_218_539_805_649_1,
];

/// `a` where `condition` holds, else `b`, by bit masks: a select the compiler keeps as one
/// (a branch on the rotation's octant mispredicts often, and blocks vectorization).
#[inline(always)]
fn select(condition: bool, a: f64, b: f64) -> f64 {
    let mask = u64::from(condition).wrapping_neg();
    f64::from_bits((a.to_bits() & mask) | (b.to_bits() & !mask))
}

/// The magnitude of a rotation given its sine and cosine up to a common positive factor:
/// atan2(|sine|, cosine) in [0, pi], with one division and a polynomial instead of libm's
/// atan2 (the target needs |theta| only: Eq. 7's weights and the energy). Within 1e-15
/// of atan2, absolute, and within 2 ulps of it relative to the angle (tested); 0 for a zero
/// vector.
///
/// With t = min(y, |x|) / max(y, |x|) in [0, 1], atan(t) is atan(u) + (0 or pi/4) with
/// u = t or (t - 1) / (t + 1) in [-tan(pi/8), tan(pi/8)], taken with one division as
/// (n - d) / (n + d); then pi/2 - r when y > |x| and pi - r when x < 0.
#[inline(always)]
fn abs_rotation(sine: f64, cosine: f64) -> f64 {
    use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};
    // Selects rather than branches, and the polynomial by Estrin's scheme: independent calls
    // overlap, and four vertices' calls vectorize ([`targets_of_four`]).
    let (y, x) = (sine.abs(), cosine.abs());
    let (n, d) = (select(y < x, y, x), select(y > x, y, x));
    let reduced = n > TAN_PI_8 * d;
    let (num, den) = (select(reduced, n - d, n), select(reduced, n + d, d));
    let u = select(d == 0.0, 0.0, num / den);
    let c = &ATAN_COEFFICIENTS;
    let s = u * u;
    let s2 = s * s;
    let s4 = s2 * s2;
    let low = (c[0] + c[1] * s) + s2 * (c[2] + c[3] * s);
    let high = (c[4] + c[5] * s) + s2 * (c[6] + c[7] * s);
    let p = low + s4 * high + s4 * s4 * (c[8] + c[9] * s);
    let r = u + u * s * p + select(reduced, FRAC_PI_4, 0.0);
    let r = select(y > x, FRAC_PI_2 - r, r);
    select(cosine < 0.0, PI - r, r)
}

/// Signed rotation about `p` that turns `v - p` onto the bisector of the interior angle at
/// `p`, which is the counter-clockwise sweep from `next - p` to `prev - p` (Eq. 4), and `v`
/// rotated by it (Eq. 5): the point on that bisector at distance |v - p| from `p`. `None`
/// when an edge is degenerate.
#[inline]
pub fn bisect(v: DVec2, p: DVec2, prev: DVec2, next: DVec2) -> Option<(f64, DVec2)> {
    let a = v - p;
    let b = prev - p;
    let c = next - p;
    if a == DVec2::ZERO || b == DVec2::ZERO || c == DVec2::ZERO {
        return None;
    }
    let bis = bisector(c, b);
    Some((a.perp_dot(bis).atan2(a.dot(bis)), p + a.length() * bis))
}

/// The sine and cosine (times |v - p|) of the rotation of [`bisect`], `None` when an edge is
/// degenerate.
#[inline(always)]
fn bisecting_sine_cosine(v: DVec2, p: DVec2, prev: DVec2, next: DVec2) -> Option<(f64, f64)> {
    let a = v - p;
    let b = prev - p;
    let c = next - p;
    if a == DVec2::ZERO || b == DVec2::ZERO || c == DVec2::ZERO {
        return None;
    }
    let bis = bisector(c, b);
    Some((a.perp_dot(bis), a.dot(bis)))
}

/// The rotation of [`bisect`] alone.
#[inline]
pub fn bisecting_rotation(v: DVec2, p: DVec2, prev: DVec2, next: DVec2) -> Option<f64> {
    bisecting_sine_cosine(v, p, prev, next).map(|(sine, cosine)| sine.atan2(cosine))
}

/// The magnitude of the rotation of [`bisect`], by [`abs_rotation`] (within 2 ulps of
/// atan2's): what the energy needs, at a fraction of atan2's cost.
#[inline(always)]
pub fn bisecting_rotation_magnitude(v: DVec2, p: DVec2, prev: DVec2, next: DVec2) -> Option<f64> {
    bisecting_sine_cosine(v, p, prev, next).map(|(sine, cosine)| abs_rotation(sine, cosine))
}

/// The unit direction from `p` that bisects the angle between `prev` and `next` (the
/// direction [`bisecting_rotation`] measures against), `None` when either is at `p`.
#[inline]
pub fn bisector_direction(p: DVec2, prev: DVec2, next: DVec2) -> Option<DVec2> {
    let (b, c) = (prev - p, next - p);
    if b == DVec2::ZERO || c == DVec2::ZERO {
        return None;
    }
    Some(bisector(c, b))
}

/// Eq. 5: `v` rotated about `p` by `theta` (the code folds it into the target point; the
/// tests check the fold against it).
#[cfg(test)]
pub fn rotate_about(v: DVec2, p: DVec2, theta: f64) -> DVec2 {
    p + DVec2::from_angle(theta).rotate(v - p)
}

/// Where an interior vertex's method sends it, with its energy where it is now.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Target {
    /// The target position: the weighted mean of the bisector candidates (Eqs. 4-8 with
    /// lambda = 1); the caller takes the lambda step towards it.
    pub point: DVec2,
    /// The vertex's torsion-spring energy (Eq. 1 with K = 1) at the current positions, before
    /// the move: the sum of 1/2 theta_i^2 over the corners of its embedded polygon.
    pub energy: f64,
}

/// The weighted bisector position of interior vertex `v` (Eqs. 4-8 with lambda = 1) and its
/// torsion energy (Eq. 1 with K = 1) at the current positions.
pub fn target(points: &[DVec2], v: usize, ring: &[u32]) -> Target {
    // Valence is small (typically 3-6): fixed-size scratch, no allocation, and the scratch of
    // the usual valences small enough that clearing it costs little.
    if ring.len() <= 8 { target_up_to::<8>(points, v, ring) } else { target_up_to::<32>(points, v, ring) }
}

/// [`target`] with scratch for valences up to `MAX`.
fn target_up_to<const MAX: usize>(points: &[DVec2], v: usize, ring: &[u32]) -> Target {
    let n = ring.len();
    let p = points[v];
    if !(2..=MAX).contains(&n) {
        return Target { point: p, energy: 0.0 };
    }
    let mut cand = [DVec2::ZERO; MAX];
    let mut theta = [f64::NAN; MAX];
    let mut cosine = [0.0; MAX];
    // The polygon's edges, from corner i to corner i + 1, and their unit directions: corner
    // i's next edge is edge i, its previous one edge i - 1 reversed (-d / l is -(d / l) bit for
    // bit), so each is normalized once; `bisect` gives the same bits.
    let mut edge = [DVec2::ZERO; MAX];
    let mut unit = [DVec2::ZERO; MAX];
    for i in 0..n {
        edge[i] = points[ring[(i + 1) % n] as usize] - points[ring[i] as usize];
        unit[i] = edge[i] / edge[i].length();
    }
    let (mut sum_abs, mut energy) = (0.0, 0.0);
    for i in 0..n {
        let corner = points[ring[i] as usize];
        let a = p - corner;
        let j = (i + n - 1) % n;
        if a == DVec2::ZERO || edge[i] == DVec2::ZERO || edge[j] == DVec2::ZERO {
            continue;
        }
        let bis = unit_bisector(unit[i], -unit[j]);
        // Only |theta| is used below; its sine and cosine (times |a|) for now.
        theta[i] = a.perp_dot(bis);
        cosine[i] = a.dot(bis);
        cand[i] = corner + a.length() * bis;
    }
    // The rotations apart: independent calls, which overlap.
    for i in 0..n {
        if !theta[i].is_nan() {
            let t = abs_rotation(theta[i], cosine[i]);
            theta[i] = t;
            sum_abs += t;
            energy += 0.5 * t * t;
        }
    }
    if sum_abs == 0.0 {
        return Target { point: p, energy };
    }
    let (mut acc, mut wsum) = (DVec2::ZERO, 0.0);
    for i in 0..n {
        if theta[i].is_nan() {
            continue;
        }
        let w = 1.0 - theta[i] / sum_abs;
        acc += w * cand[i];
        wsum += w;
    }
    // A single usable corner has weight 0: follow its candidate alone.
    if wsum <= f64::EPSILON {
        let count = theta[..n].iter().filter(|t| !t.is_nan()).count() as f64;
        let mean = (0..n).filter(|&i| !theta[i].is_nan()).map(|i| cand[i]).sum::<DVec2>() / count;
        return Target { point: mean, energy };
    }
    Target { point: acc / wsum, energy }
}

/// Vertices whose targets [`targets_of_four`] computes together.
pub const BATCH: usize = 4;

/// Per corner of [`BATCH`] valence-4 vertices (corner `l` of vertex `j` at index `[l][j]`):
/// |theta| (NaN when degenerate) and the candidate, as [`target`] computes them.
struct Corners {
    theta: [[f64; BATCH]; 4],
    cx: [[f64; BATCH]; 4],
    cy: [[f64; BATCH]; 4],
}

/// The [`Corners`] of [`targets_of_four`] and [`energies_of_four`].
#[inline(always)]
fn corners_of_four(points: &[DVec2], vertices: [usize; BATCH], rings: [&[u32; 4]; BATCH]) -> Corners {
    const B: usize = BATCH;
    // Corner l of vertex j is at (x[l][j], y[l][j]); edge l runs from corner l to corner l + 1.
    let (mut px, mut py) = ([0.0; B], [0.0; B]);
    let (mut x, mut y) = ([[0.0; B]; 4], [[0.0; B]; 4]);
    for j in 0..B {
        (px[j], py[j]) = (points[vertices[j]].x, points[vertices[j]].y);
        for l in 0..4 {
            let q = points[rings[j][l] as usize];
            (x[l][j], y[l][j]) = (q.x, q.y);
        }
    }
    let (mut ex, mut ey, mut length) = ([[0.0; B]; 4], [[0.0; B]; 4], [[0.0; B]; 4]);
    for l in 0..4 {
        let m = (l + 1) % 4;
        for j in 0..B {
            (ex[l][j], ey[l][j]) = (x[m][j] - x[l][j], y[m][j] - y[l][j]);
            length[l][j] = (ex[l][j] * ex[l][j] + ey[l][j] * ey[l][j]).sqrt();
        }
    }
    // Per corner, as in `target`: |theta| (NaN when degenerate) and the candidate.
    let (mut theta, mut cx, mut cy) = ([[0.0; B]; 4], [[0.0; B]; 4], [[0.0; B]; 4]);
    for l in 0..4 {
        let k = (l + 3) % 4;
        for j in 0..B {
            // unit_bisector(c, b) of the next edge's direction c and the previous edge's
            // reversed b (-(d / l) is (-d) / l bit for bit): the vector it normalizes is
            // selected, then normalized. Written out on scalars: with unit_bisector itself
            // on DVec2 lanes the 1M sweep measured 10% slower.
            let c = (ex[l][j] / length[l][j], ey[l][j] / length[l][j]);
            let b = (-(ex[k][j] / length[k][j]), -(ey[k][j] / length[k][j]));
            let acute = c.0 * b.0 + c.1 * b.1 > 0.0;
            let turn = c.0 * b.1 - c.1 * b.0 >= 0.0;
            let (sx, sy) = (c.0 + b.0, c.1 + b.1);
            let (dx, dy) = (b.0 - c.0, b.1 - c.1);
            let rx = select(acute, select(turn, sx, -sx), dy);
            let ry = select(acute, select(turn, sy, -sy), -dx);
            let bisector_length = (rx * rx + ry * ry).sqrt();
            let (hx, hy) = (rx / bisector_length, ry / bisector_length);
            let (ax, ay) = (px[j] - x[l][j], py[j] - y[l][j]);
            let sine = ax * hy - ay * hx;
            let cosine = ax * hx + ay * hy;
            let spoke = (ax * ax + ay * ay).sqrt();
            (cx[l][j], cy[l][j]) = (x[l][j] + spoke * hx, y[l][j] + spoke * hy);
            let zero = |x: f64, y: f64| x == 0.0 && y == 0.0;
            let degenerate = zero(ax, ay) || zero(ex[l][j], ey[l][j]) || zero(ex[k][j], ey[k][j]);
            theta[l][j] = select(degenerate || sine.is_nan(), f64::NAN, abs_rotation(sine, cosine));
        }
    }
    Corners { theta, cx, cy }
}

/// The torsion energies ([`super::energy::vertex_energy`], the same bits) of [`BATCH`]
/// interior vertices of valence 4, four lanes at a time; `None` for a vertex with a degenerate
/// corner, which `vertex_energy` measures itself.
#[inline(always)]
pub fn energies_of_four(
    points: &[DVec2],
    vertices: [usize; BATCH],
    rings: [&[u32; 4]; BATCH],
) -> [Option<f64>; BATCH] {
    let Corners { theta, .. } = corners_of_four(points, vertices, rings);
    let mut energy = [0.0; BATCH];
    for corner in &theta {
        for j in 0..BATCH {
            energy[j] += 0.5 * corner[j] * corner[j];
        }
    }
    std::array::from_fn(|j| (!theta.iter().any(|corner| corner[j].is_nan())).then_some(energy[j]))
}

/// [`target`] of [`BATCH`] interior vertices of valence 4 (a quad mesh's regular interior
/// vertices, most of any mesh), the same bits as one call each.
///
/// One vertex's target is a long chain of dependent square roots and divisions that the
/// processor cannot overlap with the next vertex's: computed in lanes across vertices, the
/// chains run side by side and the arithmetic vectorizes (measured 1.6x on 1M quads). A vertex
/// with a degenerate corner, or whose rotations sum to zero, takes [`target`] itself.
#[inline(always)]
pub fn targets_of_four(
    points: &[DVec2],
    vertices: [usize; BATCH],
    rings: [&[u32; 4]; BATCH],
) -> [Target; BATCH] {
    const B: usize = BATCH;
    let Corners { theta, cx, cy } = corners_of_four(points, vertices, rings);
    let (mut sum_abs, mut energy) = ([0.0; B], [0.0; B]);
    for corner in &theta {
        for j in 0..B {
            sum_abs[j] += corner[j];
            energy[j] += 0.5 * corner[j] * corner[j];
        }
    }
    let (mut acc_x, mut acc_y, mut wsum) = ([0.0; B], [0.0; B], [0.0; B]);
    for l in 0..4 {
        for j in 0..B {
            let w = 1.0 - theta[l][j] / sum_abs[j];
            acc_x[j] += w * cx[l][j];
            acc_y[j] += w * cy[l][j];
            wsum[j] += w;
        }
    }
    std::array::from_fn(|j| {
        // A NaN (a degenerate corner) fails both comparisons.
        if sum_abs[j] > 0.0 && wsum[j] > f64::EPSILON {
            Target { point: DVec2::new(acc_x[j] / wsum[j], acc_y[j] / wsum[j]), energy: energy[j] }
        } else {
            target(points, vertices[j], rings[j])
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{FRAC_PI_4, TAU};

    #[test]
    fn abs_rotation_is_atan2_of_the_magnitude() {
        let mut rnd = crate::test_rng::xorshift(0x853c_49e6_748f_ea9b);
        let check = |y: f64, x: f64| {
            let want = y.abs().atan2(x);
            let got = abs_rotation(y, x);
            let err = (got - want).abs();
            assert!(err <= 1.0e-15 && err <= 2.0 * f64::EPSILON * want, "atan2({y}, {x}): {got} vs {want}");
        };
        // Every direction, densely, at many scales; near the axes and the reduction's switch.
        for k in 0..200_000 {
            let angle = (k as f64 + 0.5) * TAU / 200_000.0;
            let r = 10f64.powf(20.0 * rnd());
            check(r * angle.sin(), r * angle.cos());
        }
        for e in 1..300 {
            let tiny = 2f64.powi(-e);
            for (y, x) in [(tiny, 1.0), (1.0, tiny), (tiny, -1.0), (-tiny, 1.0), (1.0, -tiny)] {
                check(y, x);
            }
        }
        for k in -1000..1000 {
            let t = TAN_PI_8 + k as f64 * f64::EPSILON;
            check(t, 1.0);
            check(1.0, t);
            check(t, -1.0);
        }
        assert_eq!(abs_rotation(0.0, 0.0), 0.0);
        assert_eq!(abs_rotation(0.0, 2.0), 0.0);
        assert_eq!(abs_rotation(0.0, -2.0), std::f64::consts::PI);
    }

    #[test]
    fn rotation_bisects_the_interior_angle() {
        // Corner at origin, next neighbour on +x, previous on +y: the bisector is at 45 degrees.
        let p = DVec2::ZERO;
        let next = DVec2::new(1.0, 0.0);
        let prev = DVec2::new(0.0, 1.0);
        let v = DVec2::new(1.0, 0.2);
        let t = bisecting_rotation(v, p, prev, next).unwrap();
        let expected = FRAC_PI_4 - 0.2f64.atan();
        assert!((t - expected).abs() < 1e-14);
        let r = rotate_about(v, p, t);
        assert!((r.x - r.y).abs() < 1e-14 && (r.length() - v.length()).abs() < 1e-14);
    }

    #[test]
    fn rotation_keeps_its_sign_outside_the_angle() {
        // Spoke below the next edge (a tangled configuration): rotate counter-clockwise.
        let t = bisecting_rotation(DVec2::new(1.0, -0.5), DVec2::ZERO, DVec2::Y, DVec2::X).unwrap();
        assert!((t - (FRAC_PI_4 + 0.5f64.atan())).abs() < 1e-14);
    }

    #[test]
    fn four_targets_together_are_the_bits_of_one_by_one() {
        let mut rnd = crate::test_rng::xorshift(0x2545_f491_4f6c_dd1d);
        for case in 0..4000 {
            // BATCH stars of valence 4: near-regular, tangled, or with a degenerate spoke or
            // edge, or a vertex at the centre of a regular star (all rotations zero).
            let mut points = Vec::new();
            for _ in 0..BATCH {
                let centre = DVec2::new(rnd(), rnd()) * 10f64.powf(3.0 * rnd());
                let scale = 10f64.powf(3.0 * rnd());
                let spread = match case % 4 {
                    0 => 0.1,
                    1 => 0.6,
                    _ => 1.5,
                };
                let mut star = vec![centre + DVec2::new(rnd(), rnd()) * scale * spread];
                for k in 0..4 {
                    let angle = k as f64 * TAU / 4.0 + spread * rnd();
                    star.push(centre + DVec2::from_angle(angle) * scale * (1.0 + spread * rnd()));
                }
                match (case / 4) % 8 {
                    0 => star[0] = star[2],
                    1 => star[3] = star[4],
                    2 => {
                        star[0] = centre;
                        for k in 0..4 {
                            star[k + 1] = centre + DVec2::from_angle(k as f64 * TAU / 4.0) * scale;
                        }
                    }
                    _ => {}
                }
                points.extend(star);
            }
            let vertices: [usize; BATCH] = std::array::from_fn(|j| 5 * j);
            let rings: Vec<[u32; 4]> =
                (0..BATCH).map(|j| std::array::from_fn(|k| (5 * j + 1 + k) as u32)).collect();
            let together = targets_of_four(&points, vertices, std::array::from_fn(|j| &rings[j]));
            for j in 0..BATCH {
                let Target { point: t, energy: e } = target(&points, vertices[j], &rings[j]);
                let Target { point: u, energy: f } = together[j];
                assert_eq!(
                    (t.x.to_bits(), t.y.to_bits(), e.to_bits()),
                    (u.x.to_bits(), u.y.to_bits(), f.to_bits())
                );
            }
        }
    }

    #[test]
    fn energies_of_four_are_vertex_energy_bit_for_bit() {
        // Random valence-4 stars, some tangled, one with a degenerate spoke: each lane is
        // vertex_energy's value (bit for bit) or None where a corner is degenerate.
        let mut rnd = crate::test_rng::xorshift(0x2545_f491_4f6c_dd1d);
        let mut points = Vec::new();
        for j in 0..40 {
            let centre = DVec2::new(rnd() * 4.0 - 2.0, rnd() * 4.0 - 2.0);
            points.push(centre);
            for k in 0..4 {
                let angle = std::f64::consts::FRAC_PI_2 * k as f64 + (rnd() - 0.5) * 2.5;
                let r = 0.2 + rnd() * 2.0;
                points.push(centre + r * DVec2::from_angle(angle));
            }
            if j == 7 {
                points[5 * j + 2] = centre;
            }
        }
        for batch in 0..10 {
            let vertices: [usize; BATCH] = std::array::from_fn(|j| 5 * (4 * batch + j));
            let rings: Vec<[u32; 4]> =
                vertices.iter().map(|&v| std::array::from_fn(|k| (v + 1 + k) as u32)).collect();
            let refs: [&[u32; 4]; BATCH] = std::array::from_fn(|j| &rings[j]);
            for (j, e) in energies_of_four(&points, vertices, refs).into_iter().enumerate() {
                let want = crate::smooth::energy::vertex_energy(&points, vertices[j], &rings[j]);
                match e {
                    Some(e) => assert_eq!(e.to_bits(), want.to_bits(), "vertex {}", vertices[j]),
                    None => assert_eq!(vertices[j], 35, "only the degenerate star falls back"),
                }
            }
        }
    }

    #[test]
    fn regular_star_is_a_fixed_point_with_zero_energy() {
        let mut points = vec![DVec2::ZERO];
        for k in 0..5 {
            points.push(DVec2::from_angle(k as f64 * TAU / 5.0));
        }
        let Target { point: t, energy: e } = target(&points, 0, &[1, 2, 3, 4, 5]);
        assert!(t.length() < 1e-14 && e < 1e-28);
    }

    #[test]
    fn off_centre_vertex_moves_towards_the_centre() {
        let mut points = vec![DVec2::new(0.3, 0.1)];
        for k in 0..4 {
            points.push(DVec2::from_angle(k as f64 * TAU / 4.0));
        }
        let Target { point: t, energy: e } = target(&points, 0, &[1, 2, 3, 4]);
        assert!(t.length() < points[0].length());
        assert!(e > 0.0);
    }

    #[test]
    fn weighted_update_matches_a_hand_computation_of_eqs_4_to_8() {
        // Valence-4 star with an off-centre v. Each spoke lies inside its corner's angle, so
        // Eq. 4 can be evaluated with arccosines exactly as printed: theta_i is half the
        // difference of the angles between the spoke and the two polygon edges at P_i.
        let ring_points =
            [DVec2::new(1.0, 0.0), DVec2::new(0.1, 1.2), DVec2::new(-0.9, 0.1), DVec2::new(0.0, -1.0)];
        let v = DVec2::new(0.2, 0.15);
        let mut points = vec![v];
        points.extend(ring_points);
        let angle = |a: DVec2, b: DVec2| (a.dot(b) / (a.length() * b.length())).acos();
        let n = 4;
        let (mut thetas, mut cands) = (Vec::new(), Vec::new());
        for i in 0..n {
            let p = ring_points[i];
            let prev = ring_points[(i + n - 1) % n];
            let next = ring_points[(i + 1) % n];
            // Eq. 4: rotate towards the larger of the two angles by half their difference;
            // counter-clockwise (positive) when the angle to the previous neighbour is larger.
            let theta = 0.5 * (angle(v - p, prev - p) - angle(v - p, next - p));
            thetas.push(theta);
            // Eq. 5: rotation about P_i.
            let (s, c) = theta.sin_cos();
            let a = v - p;
            cands.push(p + DVec2::new(c * a.x - s * a.y, s * a.x + c * a.y));
        }
        // Eq. 7 weights, normalized (Eq. 8 with lambda = 1).
        let total: f64 = thetas.iter().map(|t| t.abs()).sum();
        let w: Vec<f64> = thetas.iter().map(|t| 1.0 - t.abs() / total).collect();
        let expected = (0..n).map(|i| w[i] * cands[i]).sum::<DVec2>() / w.iter().sum::<f64>();
        let energy: f64 = thetas.iter().map(|t| 0.5 * t * t).sum();
        let Target { point: got, energy: e } = target(&points, 0, &[1, 2, 3, 4]);
        assert!((got - expected).length() < 1e-14, "{got} vs {expected}");
        assert!((e - energy).abs() < 1e-14, "{e} vs {energy}");
    }

    #[test]
    fn bisector_agrees_with_the_trigonometric_form_on_every_angle() {
        // The counter-clockwise sweep from c to b, halved, by atan2: what Eq. 4 describes.
        for k in 0..3600 {
            let sweep = (k as f64 + 0.5) * TAU / 3600.0;
            let c = DVec2::from_angle(0.37 * k as f64) * (1.0 + (k % 7) as f64);
            let b = DVec2::from_angle(sweep).rotate(c) * 0.5;
            let expected = DVec2::from_angle(0.5 * sweep).rotate(c).normalize();
            assert!((bisector(c, b) - expected).length() < 1e-12, "sweep {sweep}");
            let v = c.rotate(DVec2::from_angle(0.3)) + DVec2::new(0.1, -0.2);
            let (t, cand) = bisect(v, DVec2::ZERO, b, c).unwrap();
            assert!((cand - rotate_about(v, DVec2::ZERO, t)).length() < 1e-12 * v.length());
        }
        // A straight angle turns c by a quarter turn counter-clockwise.
        assert!((bisector(DVec2::X, -DVec2::X) - DVec2::Y).length() < 1e-15);
    }
}
