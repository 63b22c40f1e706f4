//! Which vertices may move in a run: corners and features (Section 3.3), fixed vertices and
//! whether the boundary may move at all. Recomputed per run from the current positions, so one [`Topology`]
//! serves many runs.

use crate::mesh::Mesh;
use crate::topology::{Topology, VertexKind};
use glam::DVec2;

/// Tolerance on the feature angle, in degrees: angles within it of the threshold are not
/// corners, so rounding cannot decide (a regular octagon's 135 degree angles sit exactly on
/// the default 45 degree threshold). It must exceed what the normalization's grid can do to an
/// angle: vertices move by at most 2^-21 of the shortest edge, which turns an edge by at most
/// 2^-21 rad and an angle by 2^-20 rad = 5.5e-5 degrees (src/normalization.rs).
const FEATURE_ANGLE_TOLERANCE_DEG: f64 = 1e-3;

/// The role of each vertex in one run.
#[derive(Clone, Debug)]
pub struct Features {
    corner: Vec<bool>,
    boundary: Vec<bool>,
    movable: Vec<bool>,
}

/// Interior angle (through the mesh) at boundary vertex `v` between its boundary neighbours,
/// in degrees in [0, 360).
pub fn boundary_angle_deg(points: &[DVec2], topo: &Topology, v: usize) -> f64 {
    let ring = topo.ring(v);
    let p = points[v];
    let next = points[ring[0] as usize] - p;
    let prev = points[ring[ring.len() - 1] as usize] - p;
    // Counter-clockwise sweep from the outgoing boundary edge to the incoming one.
    let a = next.perp_dot(prev).atan2(next.dot(prev)).to_degrees();
    if a < 0.0 { a + 360.0 } else { a }
}

impl Features {
    /// Classifies the vertices of `mesh`.
    ///
    /// A boundary vertex is a corner when its number of incident quads is not 2 or its
    /// boundary angle differs from 180 degrees by more than `feature_angle_deg`; at a boundary
    /// vertex with a triangle among its faces, the angle alone decides. Boundary
    /// vertices are movable only when `boundary_moves` (a boundary mode other than fixed).
    pub fn new(mesh: &Mesh, topo: &Topology, feature_angle_deg: f64, boundary_moves: bool) -> Features {
        let n = topo.vertex_count();
        let points = mesh.points();
        let mut corner = vec![false; n];
        let mut boundary = vec![false; n];
        let mut movable = vec![false; n];
        for v in 0..n {
            match topo.kind(v) {
                VertexKind::Interior => movable[v] = !mesh.fixed()[v],
                VertexKind::Boundary => {
                    boundary[v] = true;
                    let turn = (boundary_angle_deg(points, topo, v) - 180.0).abs();
                    // The paper's valence rule (two quads at a regular boundary vertex) says
                    // nothing where triangles meet the boundary: there the angle alone decides.
                    let with_triangle = topo
                        .vertex_quads(v)
                        .iter()
                        .any(|&f| crate::face::is_triangle(&mesh.quads()[f as usize]));
                    let irregular = !with_triangle && topo.quad_count(v) != 2;
                    corner[v] = irregular || turn > feature_angle_deg + FEATURE_ANGLE_TOLERANCE_DEG;
                    movable[v] = !corner[v] && !mesh.fixed()[v] && boundary_moves;
                }
                VertexKind::NonManifold => {
                    boundary[v] = true;
                    corner[v] = true;
                }
                VertexKind::Unused => {}
            }
        }
        Features { corner, boundary, movable }
    }

    /// Whether `v` is a corner (never moves).
    pub fn is_corner(&self, v: usize) -> bool {
        self.corner[v]
    }

    /// Whether `v` is on the boundary.
    pub fn is_boundary(&self, v: usize) -> bool {
        self.boundary[v]
    }

    /// Whether `v` may move in this run.
    pub fn is_movable(&self, v: usize) -> bool {
        self.movable[v]
    }

    /// Number of corners.
    pub fn corner_count(&self) -> usize {
        self.corner.iter().filter(|&&c| c).count()
    }

    /// The movable vertices, ascending.
    pub fn movable_vertices(&self) -> Vec<u32> {
        (0..self.movable.len() as u32).filter(|&v| self.movable[v as usize]).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn polygon_patch(angle_deg: f64) -> (Mesh, Topology) {
        // Two quads meeting at boundary vertex 1 with a bend of `angle_deg` at it.
        let t = angle_deg.to_radians();
        let p = vec![
            DVec2::new(-1.0, 0.0),
            DVec2::new(0.0, 0.0),
            DVec2::new(t.cos(), t.sin()),
            DVec2::new(-1.0, 1.0),
            DVec2::new(0.0, 1.0),
            DVec2::new(t.cos() + 0.0, t.sin() + 1.0),
        ];
        // Interior above the bottom polyline 0-1-2.
        let m = Mesh::new(p, vec![[0, 1, 4, 3], [1, 2, 5, 4]], None).unwrap();
        let topo = Topology::new(&m);
        (m, topo)
    }

    #[test]
    fn corner_rule_uses_turning_angle_and_quad_count() {
        let (m, t) = polygon_patch(10.0);
        assert!((boundary_angle_deg(m.points(), &t, 1) - 170.0).abs() < 1e-9);
        let f = Features::new(&m, &t, 45.0, true);
        assert!(!f.is_corner(1) && f.is_movable(1));
        // Vertices with one quad are corners.
        assert!(f.is_corner(0) && !f.is_movable(0));
        let (m, t) = polygon_patch(50.0);
        let f = Features::new(&m, &t, 45.0, true);
        assert!(f.is_corner(1));
        let f = Features::new(&m, &t, 60.0, false);
        assert!(!f.is_corner(1) && !f.is_movable(1));
    }

    #[test]
    fn threshold_angle_is_stable() {
        // Exactly 45 degrees of turn (an octagon's angle) is not a corner.
        let (m, t) = polygon_patch(45.0);
        let f = Features::new(&m, &t, 45.0, true);
        assert!(!f.is_corner(1));
    }
}
