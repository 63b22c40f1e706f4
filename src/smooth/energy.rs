//! The torsion-spring energy of Eq. 1 (Zhou and Shimada), used for termination (Section 3.2).
//!
//! Reading: for a vertex, theta_i are the bisecting rotations of its embedded polygon (Eq. 4),
//! so E_v = sum_i 1/2 K theta_i^2 with K = 1 is zero exactly when every spoke bisects its
//! interior angle. The collective energy is the sum over the vertices being optimized.

use super::embedded_polygon::bisecting_rotation_magnitude;
use glam::DVec2;

/// Torsion energy of interior vertex `v` with counter-clockwise edge-neighbours `ring`.
#[inline(always)]
pub fn vertex_energy(points: &[DVec2], v: usize, ring: &[u32]) -> f64 {
    let n = ring.len();
    let p = points[v];
    (0..n)
        .filter_map(|i| {
            bisecting_rotation_magnitude(
                p,
                points[ring[i] as usize],
                points[ring[(i + n - 1) % n] as usize],
                points[ring[(i + 1) % n] as usize],
            )
        })
        .map(|t| 0.5 * t * t)
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn energy_of_a_skewed_star_is_half_the_squared_rotations() {
        // Square star with the centre moved right by 0.2: at the east corner the spoke is
        // already on the bisector; at north and south it must turn by atan(0.2) each way; at
        // west the spoke is on the bisector again.
        let points = vec![DVec2::new(0.2, 0.0), DVec2::X, DVec2::Y, -DVec2::X, -DVec2::Y];
        let e = vertex_energy(&points, 0, &[1, 2, 3, 4]);
        let t = (0.2f64).atan2(1.0);
        assert!((e - t * t).abs() < 1e-14, "{e} vs {}", t * t);
    }
}
