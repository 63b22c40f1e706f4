//! Feature curves of a [`SurfaceMesh`] (issue 33, item 2): the edges a vertex may only slide
//! along, and the corners that never move.
//!
//! A **feature edge** is a boundary edge, a **sharp** edge or an edge the user marked. An edge
//! is sharp when the angle between the normals of its two faces (its dihedral angle) exceeds
//! the feature angle, and it is a crease rather than the bending of a coarse surface:
//!
//! - it bends by more than the feature angle beyond the flattest edge at its two ends (a
//!   crease stands out from the surface it cuts: a box's 90 degree edge meets the flat edges
//!   across its faces, while on a low-poly model, where every edge bends by 30 to 60 degrees,
//!   a 60 degree edge is the surface's curvature), or it bends by more than
//!   [`CREASE_FACTOR`] (1.5) times the feature angle, 67.5 degrees by default, whatever bends
//!   around it (a pyramid's sides, a box made of six faces);
//! - and it is not on a chain of at most [`SHORT_SPUR_EDGES`] (2) sharp edges that dies out on
//!   the surface (starts at a vertex with no other feature edge): a crease a user would call a
//!   feature runs on or meets another feature, while one or two bent edges ending in the
//!   middle of a surface are its faceting. Their vertices would be corners that never move.
//!
//! On the fine CAD bracket this finds the dihedral rule's sharp edges, on the impeller all but
//! its short spurs (203 curves instead of 258); on a 500-face low-poly head (Blender's Suzanne, quads and
//! triangles) 76 feature curves and 88 corners instead of 176 and 191, so most of it can move.
//! Each face's normal is its
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

use super::mesh::{SurfaceEdge, SurfaceMesh, face_vector_area};
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

/// An edge bending by more than this times the feature angle (67.5 degrees by default) is
/// sharp whatever bends around it (see the module docs).
pub const CREASE_FACTOR: f64 = 1.5;

/// Sharp chains of at most this many edges that die out on the surface are not features (see
/// the module docs).
pub const SHORT_SPUR_EDGES: usize = 2;

/// Per vertex, the two smallest dihedral angles of the edges at it (NaN ones left out) and
/// the edge of the smallest: the flattest edge around an edge, itself excluded.
struct Flattest {
    smallest: Vec<(f64, usize, f64)>,
}

fn flattest_around(n: usize, edges: &[SurfaceEdge], dihedral: &[f64]) -> Flattest {
    let mut smallest = vec![(f64::INFINITY, usize::MAX, f64::INFINITY); n];
    for (i, (e, &angle)) in edges.iter().zip(dihedral).enumerate() {
        if angle.is_nan() {
            continue;
        }
        for v in [e.a, e.b] {
            let s = &mut smallest[v as usize];
            if angle < s.0 {
                *s = (angle, i, s.0);
            } else if angle < s.2 {
                s.2 = angle;
            }
        }
    }
    Flattest { smallest }
}

impl Flattest {
    /// The smallest dihedral angle of the edges at `e`'s ends other than `e` (edge `i`); 0 when
    /// there is none (nothing bends around it).
    fn excluding(&self, e: &SurfaceEdge, i: usize) -> f64 {
        let at = |v: u32| {
            let (a, edge, b) = self.smallest[v as usize];
            if edge == i { b } else { a }
        };
        let m = at(e.a).min(at(e.b));
        if m.is_finite() { m } else { 0.0 }
    }
}

/// Unmarks the sharp edges (neither boundary nor marked) of every chain of at most
/// [`SHORT_SPUR_EDGES`] that starts at a vertex with no other feature edge and runs through
/// vertices with two to where it ends (another curve, a junction, its other end).
fn drop_short_spurs(n: usize, edges: &[SurfaceEdge], kinds: &mut [FeatureEdgeKind]) {
    let sharp_only = |k: &FeatureEdgeKind| k.sharp && !k.boundary && !k.marked;
    // The feature edges at each vertex, at most the first three (more is a junction all the same).
    let mut at: Vec<(u8, [usize; 3])> = vec![(0, [0; 3]); n];
    for (i, (e, k)) in edges.iter().zip(kinds.iter()).enumerate() {
        if k.any() {
            for v in [e.a, e.b] {
                let (count, list) = &mut at[v as usize];
                if (*count as usize) < 3 {
                    list[*count as usize] = i;
                }
                *count = count.saturating_add(1);
            }
        }
    }
    let mut drop = Vec::new();
    for v in 0..n {
        let (count, list) = at[v];
        if count != 1 || !sharp_only(&kinds[list[0]]) {
            continue;
        }
        let (mut here, mut edge) = (v as u32, list[0]);
        let mut chain = vec![edge];
        loop {
            let e = &edges[edge];
            let next = if e.a == here { e.b } else { e.a };
            let (count, list) = at[next as usize];
            if count != 2 {
                break;
            }
            let other = if list[0] == edge { list[1] } else { list[0] };
            if !sharp_only(&kinds[other]) || chain.len() > SHORT_SPUR_EDGES {
                break;
            }
            chain.push(other);
            (here, edge) = (next, other);
        }
        if chain.len() <= SHORT_SPUR_EDGES {
            drop.extend(chain);
        }
    }
    for i in drop {
        kinds[i].sharp = false;
    }
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
        // Each edge's dihedral angle: NaN on the boundary and where a face is folded.
        let dihedral: Vec<f64> = mesh
            .edges()
            .iter()
            .map(|e| {
                let [f, g] = e.faces.map(|f| f as usize);
                if e.is_boundary() || folded[f] || folded[g] {
                    f64::NAN
                } else {
                    angle_between_deg(normals[f], normals[g])
                }
            })
            .collect();
        let flattest = flattest_around(points.len(), mesh.edges(), &dihedral);
        let mut edge_kind: Vec<FeatureEdgeKind> = mesh
            .edges()
            .iter()
            .enumerate()
            .map(|(i, e)| {
                let boundary = e.is_boundary();
                let angle = dihedral[i];
                // A crease stands out from the surface it cuts (see the module docs).
                let around = flattest.excluding(e, i);
                let sharp = angle > threshold
                    && (angle > CREASE_FACTOR * feature_angle_deg + FEATURE_ANGLE_TOLERANCE_DEG
                        || angle - around > threshold);
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

        drop_short_spurs(points.len(), mesh.edges(), &mut edge_kind);

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
