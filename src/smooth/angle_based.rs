//! Baseline: Xu and Newman's angle-based smoothing of quad meshes (2005).
//!
//! Every neighbour of v, edge-neighbour or quad diagonal (2n of them around a valence-n
//! vertex), proposes v rotated about itself onto the bisector of its angle between its two
//! ring neighbours; at a diagonal vertex that angle is the quad's own interior angle, so v
//! moves towards the bisector of the opposite corner. Candidates are averaged with equal
//! weights.

use super::embedded_polygon::bisect;
use glam::DVec2;

/// Angle-based target of interior vertex `v` with alternating edge/diagonal ring `full_ring`.
pub fn target(points: &[DVec2], v: usize, full_ring: &[u32]) -> DVec2 {
    let n = full_ring.len();
    let p = points[v];
    let (mut acc, mut count) = (DVec2::ZERO, 0usize);
    for i in 0..n {
        let corner = points[full_ring[i] as usize];
        let prev = points[full_ring[(i + n - 1) % n] as usize];
        let next = points[full_ring[(i + 1) % n] as usize];
        if let Some((_, candidate)) = bisect(p, corner, prev, next) {
            acc += candidate;
            count += 1;
        }
    }
    if count == 0 { p } else { acc / count as f64 }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regular_grid_star_is_a_fixed_point() {
        // Centre of a 2x2 grid: ring E, NE, N, NW, W, SW, S, SE.
        let mut points = vec![DVec2::ZERO];
        for (x, y) in [(1., 0.), (1., 1.), (0., 1.), (-1., 1.), (-1., 0.), (-1., -1.), (0., -1.), (1., -1.)] {
            points.push(DVec2::new(x, y));
        }
        let ring: Vec<u32> = (1..=8).collect();
        assert!(target(&points, 0, &ring).length() < 1e-15);
        points[0] = DVec2::new(0.3, 0.2);
        assert!(target(&points, 0, &ring).length() < points[0].length());
    }
}
