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
/// embedded polygon: edge (v, n_i) gets w_i = (cot of the angle at n_i-1 in triangle
/// (v, n_i-1, n_i) + cot of the angle at n_i+1 in triangle (v, n_i, n_i+1)) / 2.
///
/// Note (measured, and the reason this baseline moves little): in the plane the cotangent
/// Laplacian of a valid triangulation vanishes identically (it is the gradient of the
/// one-ring's area, which is constant), so v is already the weighted mean and only vertices
/// whose weights are clamped move: negative weights (obtuse opposite angles, folded
/// triangles) make the update unstable and are clamped to a small positive floor. This
/// matches the small changes the paper reports for its cotangent Laplacian. Splitting the
/// quads along the diagonal through v and dropping the diagonal term instead was tried and
/// diverges (the weights pull v further towards the side it moved to).
pub fn cotangent_target(points: &[DVec2], v: usize, ring: &[u32]) -> DVec2 {
    let n = ring.len();
    let p = points[v];
    let (mut acc, mut wsum) = (DVec2::ZERO, 0.0);
    for i in 0..n {
        let ni = points[ring[i] as usize];
        let prev = points[ring[(i + n - 1) % n] as usize];
        let next = points[ring[(i + 1) % n] as usize];
        let w = 0.5 * (cot(prev, p, ni).unwrap_or(0.0) + cot(next, p, ni).unwrap_or(0.0));
        let w = w.max(COTAN_WEIGHT_FLOOR);
        acc += w * ni;
        wsum += w;
    }
    if wsum > 0.0 && acc.is_finite() { acc / wsum } else { uniform_target(points, ring) }
}

/// Smallest cotangent weight used (negative weights make the update unstable).
const COTAN_WEIGHT_FLOOR: f64 = 1e-3;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_is_the_mean_of_the_edge_neighbours() {
        let points = vec![DVec2::new(0.3, -0.2), DVec2::X, DVec2::Y, -DVec2::X, -DVec2::Y];
        assert_eq!(uniform_target(&points, &[1, 2, 3, 4]), DVec2::ZERO);
    }

    #[test]
    fn cotangent_update_is_stationary_in_a_valid_planar_star() {
        // In the plane the cotangent Laplacian vanishes: an off-centre vertex stays put.
        let points = vec![DVec2::new(0.3, -0.2), DVec2::X, DVec2::Y, -DVec2::X, -DVec2::Y];
        let t = cotangent_target(&points, 0, &[1, 2, 3, 4]);
        assert!((t - points[0]).length() < 1e-14, "{t}");
        // A vertex outside its star (folded triangles) has clamped weights and moves inside.
        let points = vec![DVec2::new(1.5, 0.2), DVec2::X, DVec2::Y, -DVec2::X, -DVec2::Y];
        let t = cotangent_target(&points, 0, &[1, 2, 3, 4]);
        assert!(t.x < 1.0, "{t}");
    }
}
