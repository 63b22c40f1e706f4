//! Feature curves of a [`SurfaceMesh`] (issue 33, item 2): the edges a vertex may only slide
//! along, and the corners that never move.
//!
//! A **feature edge** is a boundary edge, a **sharp** edge (the angle between the normals of its
//! two faces exceeds the feature angle) or an edge the user marked. Each face's normal is its
//! vector area ([`super::mesh::face_vector_area`]: the cross product of a quad's diagonals),
//! the normal of the plane that best fits a non-planar quad; a face of no area has no
//! direction and makes no edge sharp. Nor does a face folded over (a corner of it turns against
//! the input's vertex normals, [`SurfaceMesh::signed_quality_values`]): a fold is a defect the
//! optimizer repairs, and its edges' dihedral angles say nothing about the surface.
//!
//! A **feature corner** is a vertex with one feature edge (a curve's end), with three or more
//! (a junction), or with two that turn by more than the feature angle (the angle between the
//! directions of the incoming and the outgoing edge: 0 where the curve runs straight on).
//! **Feature curves** are the maximal chains of feature edges between corners; a chain that
//! meets no corner is a closed curve (a boundary loop of a cylinder, a smooth crease around a
//! body). Every other vertex is [`VertexRole::Free`].
//!
//! The default feature angle is [`DEFAULT_FEATURE_ANGLE_DEG`], 45 degrees, the planar default
//! (`feature_angle_deg` of the planar options) so that a planar mesh and the same mesh seen as a
//! surface find the same corners. It keeps the usual meshes of smooth surfaces smooth: a
//! polygonal approximation with at least 8 segments per full turn (the coarsest a quad
//! mesher produces for a sphere or a cylinder, 45 degrees per segment) has no sharp edge,
//! while a box's 90 degree edges and a 60 degree chamfer are sharp. Angles within
//! [`FEATURE_ANGLE_TOLERANCE_DEG`] of the threshold are not beyond it, so rounding cannot
//! decide the 8-segment case.

use super::mesh::{SurfaceMesh, face_vector_area};
use crate::error::{Error, Result};
use glam::DVec3;

/// The default feature angle, in degrees (see the module's documentation).
pub const DEFAULT_FEATURE_ANGLE_DEG: f64 = 45.0;

/// An angle must exceed the feature angle by more than this, in degrees, to count (the planar
/// features' tolerance, src/features.rs).
pub const FEATURE_ANGLE_TOLERANCE_DEG: f64 = 1e-3;

/// What a vertex may do.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VertexRole {
    /// On no feature edge: moves on the surface.
    Free,
    /// Inside feature curve `id` ([`SurfaceFeatures::curves`]): moves along its polyline only.
    OnCurve(u32),
    /// A feature corner: never moves.
    Corner,
}

/// A feature curve: a polyline of mesh vertices.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FeatureCurve {
    /// The vertices in order. An open curve runs from a corner to a corner (the same one for
    /// a loop through a single corner: then the first and last entries are equal); a closed
    /// curve has no corner and its last vertex joins its first, which is not repeated.
    pub vertices: Vec<u32>,
    /// Whether the curve is a loop without corner.
    pub closed: bool,
}

impl FeatureCurve {
    /// Number of edges of the polyline.
    pub fn edge_count(&self) -> usize {
        if self.closed { self.vertices.len() } else { self.vertices.len() - 1 }
    }

    /// The segments of the polyline, as vertex pairs in order.
    pub fn segments(&self) -> impl Iterator<Item = (u32, u32)> + '_ {
        let n = self.vertices.len();
        (0..self.edge_count()).map(move |i| (self.vertices[i], self.vertices[(i + 1) % n]))
    }

    /// The closest point of the polyline (at `points`, the original positions) to `p`, the
    /// segment it lies on (index into [`FeatureCurve::segments`]) and its squared distance.
    /// Ties go to the first segment.
    pub fn closest_point(&self, points: &[DVec3], p: DVec3) -> (DVec3, usize, f64) {
        let mut best = (points[self.vertices[0] as usize], 0, f64::INFINITY);
        for (i, (a, b)) in self.segments().enumerate() {
            let (q, _) = super::closest_point_on_segment(p, points[a as usize], points[b as usize]);
            let d = (q - p).length_squared();
            if d < best.2 {
                best = (q, i, d);
            }
        }
        best
    }
}

/// Why an edge is a feature edge (several may hold).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FeatureEdgeKind {
    /// The edge has one face only.
    pub boundary: bool,
    /// The normals of its two faces differ by more than the feature angle.
    pub sharp: bool,
    /// The user marked it.
    pub marked: bool,
}

impl FeatureEdgeKind {
    /// Whether the edge is a feature edge at all.
    pub fn any(&self) -> bool {
        self.boundary || self.sharp || self.marked
    }
}

/// The feature curves and vertex roles of a [`SurfaceMesh`] at its input positions.
#[derive(Clone, Debug)]
pub struct SurfaceFeatures {
    feature_angle_deg: f64,
    edge_kind: Vec<FeatureEdgeKind>,
    roles: Vec<VertexRole>,
    curves: Vec<FeatureCurve>,
}

/// The angle between two vectors, in degrees in [0, 180]; 0 when either is zero.
pub fn angle_between_deg(u: DVec3, v: DVec3) -> f64 {
    u.cross(v).length().atan2(u.dot(v)).to_degrees()
}

impl SurfaceFeatures {
    /// Features with the default angle and no marked edge.
    pub fn detect_default(mesh: &SurfaceMesh) -> SurfaceFeatures {
        Self::detect(mesh, DEFAULT_FEATURE_ANGLE_DEG, &[]).expect("the default options are valid")
    }

    /// Finds the feature edges, corners and curves of `mesh`.
    ///
    /// `feature_angle_deg` must be finite and in [0, 180]; `marked` lists the edges the user
    /// marks as features, as vertex pairs in either order. A pair that is not an edge of the
    /// mesh gives [`Error::InvalidOption`] naming it.
    pub fn detect(
        mesh: &SurfaceMesh,
        feature_angle_deg: f64,
        marked: &[[u32; 2]],
    ) -> Result<SurfaceFeatures> {
        if !(feature_angle_deg.is_finite() && (0.0..=180.0).contains(&feature_angle_deg)) {
            return Err(Error::InvalidOption {
                name: "feature_angle",
                reason: format!("{feature_angle_deg} is not an angle in [0, 180] degrees"),
            });
        }
        let threshold = feature_angle_deg + FEATURE_ANGLE_TOLERANCE_DEG;
        let points = mesh.points();
        let faces = mesh.faces();
        let normals: Vec<DVec3> = faces.iter().map(|f| face_vector_area(points, f)).collect();
        // A face folded over (a corner turning against the vertex normals) is a defect to
        // repair, not a feature: its edges are never sharp.
        let folded: Vec<bool> = mesh.signed_quality_values().iter().map(|&q| q <= 0.0).collect();
        let mut edge_kind: Vec<FeatureEdgeKind> = mesh
            .edges()
            .iter()
            .map(|e| {
                let boundary = e.is_boundary();
                let sharp = !boundary
                    && !folded[e.faces[0] as usize]
                    && !folded[e.faces[1] as usize]
                    && angle_between_deg(normals[e.faces[0] as usize], normals[e.faces[1] as usize])
                        > threshold;
                FeatureEdgeKind { boundary, sharp, marked: false }
            })
            .collect();
        for (k, &[a, b]) in marked.iter().enumerate() {
            match mesh.find_edge(a, b).filter(|_| a != b) {
                Some(e) => edge_kind[e].marked = true,
                None => {
                    return Err(Error::InvalidOption {
                        name: "feature_edges",
                        reason: format!(
                            "marked edge {k}, vertices ({a}, {b}), is not an edge of the mesh (vertex numbers \
                             are 0-based)"
                        ),
                    });
                }
            }
        }

        // Feature edges around each vertex (CSR): neighbour vertex and edge index.
        let n = points.len();
        let mut degree = vec![0usize; n + 1];
        for (e, k) in mesh.edges().iter().zip(&edge_kind) {
            if k.any() {
                degree[e.a as usize] += 1;
                degree[e.b as usize] += 1;
            }
        }
        let mut offsets = vec![0usize; n + 1];
        for v in 0..n {
            offsets[v + 1] = offsets[v] + degree[v];
        }
        let mut fill = offsets.clone();
        let mut adj = vec![(0u32, 0usize); offsets[n]];
        for (i, (e, k)) in mesh.edges().iter().zip(&edge_kind).enumerate() {
            if k.any() {
                adj[fill[e.a as usize]] = (e.b, i);
                fill[e.a as usize] += 1;
                adj[fill[e.b as usize]] = (e.a, i);
                fill[e.b as usize] += 1;
            }
        }
        let star = |v: usize| &adj[offsets[v]..offsets[v + 1]];

        let mut roles = vec![VertexRole::Free; n];
        for (v, role) in roles.iter_mut().enumerate() {
            let s = star(v);
            *role = match s.len() {
                0 => VertexRole::Free,
                2 => {
                    let p = points[v];
                    let turn = angle_between_deg(p - points[s[0].0 as usize], points[s[1].0 as usize] - p);
                    if turn > threshold { VertexRole::Corner } else { VertexRole::OnCurve(u32::MAX) }
                }
                _ => VertexRole::Corner,
            };
        }

        // Walk the chains: first from every corner, then the loops without corner.
        let mut used = vec![false; mesh.edges().len()];
        let mut curves: Vec<FeatureCurve> = Vec::new();
        let walk = |start: u32, first: (u32, usize), used: &mut [bool], roles: &mut [VertexRole], id: u32| {
            let mut vertices = vec![start];
            let (mut v, mut e) = first;
            used[e] = true;
            loop {
                if roles[v as usize] == VertexRole::Corner || v == start {
                    vertices.push(v);
                    break;
                }
                roles[v as usize] = VertexRole::OnCurve(id);
                vertices.push(v);
                // An on-curve vertex has exactly two feature edges: take the other one.
                let s = star(v as usize);
                let next = if s[0].1 == e { s[1] } else { s[0] };
                (v, e) = next;
                used[e] = true;
            }
            vertices
        };
        for c in 0..n {
            if roles[c] != VertexRole::Corner {
                continue;
            }
            for &(w, e) in star(c) {
                if !used[e] {
                    let id = curves.len() as u32;
                    let vertices = walk(c as u32, (w, e), &mut used, &mut roles, id);
                    curves.push(FeatureCurve { vertices, closed: false });
                }
            }
        }
        for v in 0..n {
            if let Some(&(w, e)) = star(v).iter().find(|&&(_, e)| !used[e]) {
                // No corner on this loop: every vertex has two feature edges and turns gently.
                let id = curves.len() as u32;
                roles[v] = VertexRole::OnCurve(id);
                let mut vertices = walk(v as u32, (w, e), &mut used, &mut roles, id);
                vertices.pop();
                curves.push(FeatureCurve { vertices, closed: true });
            }
        }
        Ok(SurfaceFeatures { feature_angle_deg, edge_kind, roles, curves })
    }

    /// The feature angle used, in degrees.
    pub fn feature_angle_deg(&self) -> f64 {
        self.feature_angle_deg
    }

    /// Per edge of [`SurfaceMesh::edges`]: why it is a feature edge.
    pub fn edge_kinds(&self) -> &[FeatureEdgeKind] {
        &self.edge_kind
    }

    /// Number of sharp edges (not counting boundary edges).
    pub fn sharp_edge_count(&self) -> usize {
        self.edge_kind.iter().filter(|k| k.sharp).count()
    }

    /// Number of feature edges of any kind.
    pub fn feature_edge_count(&self) -> usize {
        self.edge_kind.iter().filter(|k| k.any()).count()
    }

    /// The role of each vertex.
    pub fn roles(&self) -> &[VertexRole] {
        &self.roles
    }

    /// The feature corners, in increasing order.
    pub fn corners(&self) -> Vec<u32> {
        (0..self.roles.len() as u32).filter(|&v| self.roles[v as usize] == VertexRole::Corner).collect()
    }

    /// The feature curves.
    pub fn curves(&self) -> &[FeatureCurve] {
        &self.curves
    }
}
