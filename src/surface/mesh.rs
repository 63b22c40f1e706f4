//! A validated mesh on a surface in 3D (issue 33): quads and triangles ([`crate::face`]),
//! fixed flags, consistent orientation, its edges and components, and area-weighted vertex
//! normals of the input.
//!
//! Validation is the planar [`crate::Mesh`]'s, shared with it (`mesh::validate_indices`,
//! `mesh::orient_components`): indices in range, no vertex repeated in a face, no edge of more
//! than two faces ([`Error::NonManifoldEdge`]), every component orientable
//! ([`Error::NonOrientable`]), finite coordinates. Unlike a planar mesh, a closed component (a
//! sphere, a torus) is accepted. Orientation is made consistent per component by reversing
//! the faces that disagree with their component's majority (listed in
//! [`SurfaceMesh::reoriented`]); a closed component is then turned outward (positive enclosed
//! volume; faces reversed that way are flagged, see [`SurfaceMesh::faces_as_given`]). An open
//! component has no inside, so its majority orientation stands.

use crate::alloc::{try_filled, try_with_capacity};
use crate::error::{Error, Result};
use crate::face::{Face, NO_VERTEX, corner_count};
use glam::DVec3;

/// "No face": the second face of a boundary edge.
pub const NO_FACE: u32 = u32::MAX;

/// An undirected edge of a [`SurfaceMesh`]: `a < b`, and the faces on its sides
/// (`faces[1] == NO_FACE` on the boundary).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SurfaceEdge {
    /// The lower vertex.
    pub a: u32,
    /// The higher vertex.
    pub b: u32,
    /// The faces on either side; the second is [`NO_FACE`] on the boundary.
    pub faces: [u32; 2],
}

impl SurfaceEdge {
    /// Whether the edge has one face only.
    pub fn is_boundary(&self) -> bool {
        self.faces[1] == NO_FACE
    }
}

/// One connected component (faces connected through shared edges).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SurfaceComponent {
    /// Number of faces.
    pub faces: usize,
    /// Number of edges.
    pub edges: usize,
    /// Number of vertices (a vertex shared with an earlier component counts there only).
    pub vertices: usize,
    /// Number of boundary edges.
    pub boundary_edges: usize,
}

impl SurfaceComponent {
    /// Whether the component has no boundary edge (a sphere, a torus).
    pub fn is_closed(&self) -> bool {
        self.boundary_edges == 0
    }

    /// `V - E + F`.
    pub fn euler_characteristic(&self) -> i64 {
        self.vertices as i64 - self.edges as i64 + self.faces as i64
    }

    /// The genus of a closed component, `(2 - chi) / 2` (0 for a sphere, 1 for a torus);
    /// `None` for an open one.
    pub fn genus(&self) -> Option<i64> {
        self.is_closed().then(|| (2 - self.euler_characteristic()) / 2)
    }
}

/// A validated quad or quad-dominant mesh in 3D.
#[derive(Clone, Debug)]
pub struct SurfaceMesh {
    points: Vec<DVec3>,
    faces: Vec<Face>,
    fixed: Vec<bool>,
    reoriented: Vec<u32>,
    /// Per face: its (closed) component was reversed to face outward (empty when none was).
    turned_outward: Vec<bool>,
    edges: Vec<SurfaceEdge>,
    face_component: Vec<u32>,
    components: Vec<SurfaceComponent>,
    normals: Vec<DVec3>,
}

/// The vector area of face `f` (half the cross product of the diagonals of a quad; of two
/// edges of a triangle): its direction is the face's normal, its length its area when planar.
pub fn face_vector_area(points: &[DVec3], f: &Face) -> DVec3 {
    let p = |i: usize| points[f[i] as usize];
    if f[3] == NO_VERTEX {
        0.5 * (p(1) - p(0)).cross(p(2) - p(0))
    } else {
        0.5 * (p(2) - p(0)).cross(p(3) - p(1))
    }
}

impl SurfaceMesh {
    /// Validates and builds a surface mesh of quads and triangles (a triangle has
    /// [`NO_VERTEX`] fourth). `fixed`, if given, holds one flag per vertex.
    ///
    /// ```
    /// use glam::DVec3;
    /// use quadopt::surface::SurfaceMesh;
    /// let p = vec![DVec3::ZERO, DVec3::X, DVec3::new(1., 1., 1.), DVec3::Y];
    /// let mesh = SurfaceMesh::new(p, vec![[0, 1, 2, 3]], None).unwrap();
    /// assert_eq!(mesh.edges().len(), 4);
    /// ```
    pub fn new(points: Vec<DVec3>, faces: Vec<Face>, fixed: Option<Vec<bool>>) -> Result<Self> {
        let n = points.len();
        let fixed = match fixed {
            Some(f) if f.len() != n => return Err(Error::FixedLengthMismatch { expected: n, got: f.len() }),
            Some(f) => f,
            None => try_filled(n, false, "fixed flags")?,
        };
        crate::mesh::validate_indices(&faces, n, true)?;
        if let Some(v) = points.iter().position(|p| !p.is_finite()) {
            return Err(Error::NonFiniteCoordinate { vertex: v });
        }
        // The orientation's volume (a cube of lengths) and the normals (squares) computed on
        // coordinates scaled by a power of two into the unit box: nothing over- or underflows at
        // any scale, and a mesh scaled by a power of two gets the same bits.
        let exponent = crate::power_of_two::extent_exponent3(
            faces.iter().flat_map(|f| crate::face::vertices(f).iter().map(|&v| points[v as usize])),
        );
        let unit: std::borrow::Cow<[DVec3]> = if exponent == 0 {
            std::borrow::Cow::Borrowed(&points)
        } else {
            let mut unit = try_with_capacity(n, "scaled points")?;
            unit.extend(points.iter().map(|&p| crate::power_of_two::scale_point3(p, -exponent)));
            std::borrow::Cow::Owned(unit)
        };
        let mut faces = faces;
        let nf = faces.len();
        let mut turned_outward = try_filled(nf, false, "face orientations")?;
        let mut any_turned = false;
        let mut face_component = try_filled(nf, 0u32, "face components")?;
        let mut component_count = 0u32;
        let (reoriented, _) = crate::mesh::orient_components(&mut faces, |faces, component, closed| {
            for &f in component {
                face_component[f as usize] = component_count;
            }
            component_count += 1;
            if closed && enclosed_volume(&unit, faces, component) < 0.0 {
                any_turned = true;
                crate::mesh::reverse_component(faces, component, &mut turned_outward);
            }
            Ok(())
        })?;
        if !any_turned {
            turned_outward = Vec::new();
        }
        let edges = build_edges(&faces)?;
        let components = count_components(n, &faces, &edges, &face_component, component_count as usize);
        let normals = vertex_normals(&unit, &faces);
        drop(unit);
        Ok(SurfaceMesh {
            points,
            faces,
            fixed,
            reoriented,
            turned_outward,
            edges,
            face_component,
            components,
            normals,
        })
    }

    /// This mesh with every position scaled by `2^exponent` (exact, see
    /// [`crate::power_of_two::scale_by_power_of_two`]); everything else, the vertex normals
    /// included, is the same.
    pub(crate) fn scaled(&self, exponent: i32) -> Result<SurfaceMesh> {
        let mut points = try_with_capacity(self.points.len(), "scaled points")?;
        points.extend(self.points.iter().map(|&p| crate::power_of_two::scale_point3(p, exponent)));
        Ok(SurfaceMesh {
            points,
            faces: self.faces.clone(),
            fixed: self.fixed.clone(),
            reoriented: self.reoriented.clone(),
            turned_outward: self.turned_outward.clone(),
            edges: self.edges.clone(),
            face_component: self.face_component.clone(),
            components: self.components.clone(),
            normals: self.normals.clone(),
        })
    }

    /// Vertex positions.
    pub fn points(&self) -> &[DVec3] {
        &self.points
    }

    /// Replaces the vertex positions (same count, all finite). Edges, components and the
    /// input's vertex normals ([`SurfaceMesh::vertex_normals`]) stay those of the input.
    pub fn set_points(&mut self, points: &[DVec3]) -> Result<()> {
        crate::mesh::replace_points(&mut self.points, points, |p| p.is_finite())
    }

    /// Faces, consistently oriented (closed components outward).
    pub fn faces(&self) -> &[Face] {
        &self.faces
    }

    /// Faces in the orientation the caller used for each closed component (consistent, but a
    /// closed component given inward stays inward). What file writers should emit.
    pub fn faces_as_given(&self) -> Vec<Face> {
        crate::mesh::faces_as_given(&self.faces, &self.turned_outward)
    }

    /// Per-vertex fixed flags.
    pub fn fixed(&self) -> &[bool] {
        &self.fixed
    }

    /// Faces reversed to agree with their component's majority (sorted).
    pub fn reoriented(&self) -> &[u32] {
        &self.reoriented
    }

    /// Whether a closed component was given inward (and is stored outward).
    pub fn has_inward_component(&self) -> bool {
        self.turned_outward.iter().any(|&t| t)
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.faces.iter().filter(|f| crate::face::is_triangle(f)).count()
    }

    /// The undirected edges, sorted by `(a, b)`.
    pub fn edges(&self) -> &[SurfaceEdge] {
        &self.edges
    }

    /// The index in [`SurfaceMesh::edges`] of the edge between `a` and `b`, if there is one.
    pub fn find_edge(&self, a: u32, b: u32) -> Option<usize> {
        let key = (a.min(b), a.max(b));
        self.edges.binary_search_by(|e| (e.a, e.b).cmp(&key)).ok()
    }

    /// Number of boundary edges.
    pub fn boundary_edge_count(&self) -> usize {
        self.edges.iter().filter(|e| e.is_boundary()).count()
    }

    /// The connected components, numbered by their lowest face.
    pub fn components(&self) -> &[SurfaceComponent] {
        &self.components
    }

    /// The component of each face.
    pub fn face_components(&self) -> &[u32] {
        &self.face_component
    }

    /// Whether every component is closed.
    pub fn is_closed(&self) -> bool {
        self.components.iter().all(SurfaceComponent::is_closed)
    }

    /// Area-weighted vertex normals of the input: the normalized sum of the vector areas
    /// ([`face_vector_area`]) of the faces around each vertex, in the stored (outward for a
    /// closed component) orientation. Zero for a vertex of no face, or where the sum vanishes.
    pub fn vertex_normals(&self) -> &[DVec3] {
        &self.normals
    }

    /// Per-face Verdict 3D scaled Jacobians ([`crate::quality3d::verdict_scaled_jacobian`]).
    pub fn verdict_quality_values(&self) -> Vec<f64> {
        crate::quality3d::verdict_values(&self.points, &self.faces)
    }

    /// Per-face signed scaled Jacobians against the input's vertex normals
    /// ([`crate::quality3d::signed_scaled_jacobian`]).
    pub fn signed_quality_values(&self) -> Vec<f64> {
        crate::quality3d::signed_values(&self.points, &self.faces, &self.normals)
    }
}

/// Six times the signed volume enclosed by a closed component, each face fanned into
/// triangles from its first corner, relative to the component's first vertex (which cuts the
/// cancellation of far-off coordinates).
fn enclosed_volume(points: &[DVec3], faces: &[Face], component: &[u32]) -> f64 {
    let o = points[faces[component[0] as usize][0] as usize];
    let mut volume = 0.0;
    for &f in component {
        let f = &faces[f as usize];
        let p = |i: usize| points[f[i] as usize] - o;
        for k in 1..corner_count(f) - 1 {
            volume += p(0).dot(p(k).cross(p(k + 1)));
        }
    }
    volume
}

fn build_edges(faces: &[Face]) -> Result<Vec<SurfaceEdge>> {
    let mut half: Vec<(u32, u32, u32)> = try_with_capacity(faces.len() * 4, "surface edges")?;
    for (fi, f) in faces.iter().enumerate() {
        let n = corner_count(f);
        for i in 0..n {
            let (a, b) = (f[i], f[(i + 1) % n]);
            half.push((a.min(b), a.max(b), fi as u32));
        }
    }
    half.sort_unstable();
    let mut edges = try_with_capacity(half.len() / 2 + 1, "surface edges")?;
    let mut i = 0;
    while i < half.len() {
        // Validation has refused edges of three or more faces.
        let shared = i + 1 < half.len() && (half[i + 1].0, half[i + 1].1) == (half[i].0, half[i].1);
        let second = if shared { half[i + 1].2 } else { NO_FACE };
        edges.push(SurfaceEdge { a: half[i].0, b: half[i].1, faces: [half[i].2, second] });
        i += if shared { 2 } else { 1 };
    }
    Ok(edges)
}

fn count_components(
    n: usize,
    faces: &[Face],
    edges: &[SurfaceEdge],
    face_component: &[u32],
    count: usize,
) -> Vec<SurfaceComponent> {
    let mut out = vec![SurfaceComponent { faces: 0, edges: 0, vertices: 0, boundary_edges: 0 }; count];
    let mut vertex_component = vec![u32::MAX; n];
    for (f, &c) in faces.iter().zip(face_component) {
        out[c as usize].faces += 1;
        for &v in crate::face::vertices(f) {
            if vertex_component[v as usize] == u32::MAX {
                vertex_component[v as usize] = c;
                out[c as usize].vertices += 1;
            }
        }
    }
    for e in edges {
        let c = &mut out[face_component[e.faces[0] as usize] as usize];
        c.edges += 1;
        c.boundary_edges += usize::from(e.is_boundary());
    }
    out
}

fn vertex_normals(points: &[DVec3], faces: &[Face]) -> Vec<DVec3> {
    let mut normals = vec![DVec3::ZERO; points.len()];
    for f in faces {
        let a = face_vector_area(points, f);
        for &v in crate::face::vertices(f) {
            normals[v as usize] += a;
        }
    }
    for n in &mut normals {
        *n = n.normalize_or_zero();
    }
    normals
}
