//! Baselines: uniform and cotangent-weighted Laplacian smoothing of interior vertices.

use glam::DVec2;

/// Average of the edge-neighbours (uniform Laplacian).
pub fn uniform_target(points: &[DVec2], ring: &[u32]) -> DVec2 {
    ring.iter().map(|&u| points[u as usize]).sum::<DVec2>() / ring.len() as f64
}

/// Cotangent of the angle at `x` between `u - x` and `w - x`; `None` when degenerate.
#[inline]
fn cot(x: DVec2, u: DVec2, w: DVec2) -> Option<f64> {
    let (a, b) = (u - x, w - x);
    let cross = a.perp_dot(b).abs();
    (cross > 1e-300).then(|| a.dot(b) / cross)
}

/// Cotangent-weighted average of the edge-neighbours.
///
/// Quads have no canonical cotangent weights; this uses the fan triangulation of the
/// embedded polygon: edge (v, n_i) gets w_i = (cot at n_{i-1} in triangle (v, n_{i-1}, n_i)
/// + cot at n_{i+1} in triangle (v, n_i, n_{i+1})) / 2. Negative weights (obtuse opposite
/// angles) make the update unstable, so weights are clamped to a small positive floor; if
/// every weight degenerates the uniform average is used.
pub fn cotangent_target(points: &[DVec2], v: usize, ring: &[u32]) -> DVec2 {
    let n = ring.len();
    let p = points[v];
    let (mut acc, mut wsum) = (DVec2::ZERO, 0.0);
    for i in 0..n {
        let ni = points[ring[i] as usize];
        let prev = points[ring[(i + n - 1) % n] as usize];
        let next = points[ring[(i + 1) % n] as usize];
        let w = 0.5 * (cot(prev, p, ni).unwrap_or(0.0) + cot(next, p, ni).unwrap_or(0.0));
        let w = w.max(1e-3);
        acc += w * ni;
        wsum += w;
    }
    if wsum > 0.0 && acc.is_finite() { acc / wsum } else { uniform_target(points, ring) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_is_the_mean_and_cotangent_of_a_square_star_is_its_centre() {
        let points = vec![DVec2::new(0.3, -0.2), DVec2::X, DVec2::Y, -DVec2::X, -DVec2::Y];
        assert_eq!(uniform_target(&points, &[1, 2, 3, 4]), DVec2::ZERO);
        // Symmetric neighbours get equal weights whatever the centre.
        let t = cotangent_target(&[DVec2::ZERO, DVec2::X, DVec2::Y, -DVec2::X, -DVec2::Y], 0, &[1, 2, 3, 4]);
        assert!(t.length() < 1e-15);
    }

    #[test]
    fn cotangent_weights_follow_the_opposite_angles() {
        // Centre at origin, ring of a rhombus stretched along x: the opposite angles at the
        // y-neighbours are smaller, so the x-neighbours' cotangents (at the y-vertices) grow.
        let points =
            vec![DVec2::new(0.1, 0.0), DVec2::new(2.0, 0.0), DVec2::Y, DVec2::new(-2.0, 0.0), -DVec2::Y];
        let t = cotangent_target(&points, 0, &[1, 2, 3, 4]);
        // Symmetric ring: the cotangent average is the ring centre up to weights on x, which
        // pull towards the nearer side symmetrically, so the target stays on the x-axis.
        assert!(t.y.abs() < 1e-15);
        assert!(t.x.abs() < 0.1);
    }
}
