//! A validated 2D quad or quad-dominant mesh: flat vertex and face arrays (a triangle is a
//! face with [`crate::face::NO_VERTEX`] fourth), fixed flags, consistent orientation.
//!
//! Validation names the offending quad or vertex. A closed component (one without a boundary
//! edge, such as a periodic grid whose quads wrap around) is refused: a closed surface cannot
//! lie flat in a plane without folds, so no orientation of it makes every quad valid, and the
//! rule below would have no sign to go by. Orientation is made consistent per connected
//! component (quads disagreeing with their component's majority are reversed and listed in
//! [`Mesh::reoriented`]); a component whose total signed area is negative is clockwise,
//! which is a valid mesh seen from the other side, not a mesh of inverted quads. Internally every
//! quad is stored counter-clockwise so quality is always measured against +z.
//!
//! Everything that grows with the input is allocated fallibly ([`crate::alloc`]): a mesh too
//! large for the memory available gives [`Error::OutOfMemory`].

use crate::alloc::{try_copy, try_filled, try_push, try_with_capacity};
use crate::error::{Error, Result};
use glam::DVec2;

/// A validated planar mesh of quads, or of quads and triangles (a quad-dominant mesh, built
/// with [`Mesh::with_faces`]; faces as in [`crate::face`]). "Quad" in the names of its
/// methods means "face" where the mesh has triangles: [`Mesh::quads`] and [`Mesh::faces`] are
/// the same array.
#[derive(Clone, Debug)]
pub struct Mesh {
    points: Vec<DVec2>,
    /// Quads, consistently counter-clockwise (positive total signed area per component).
    quads: Vec<[u32; 4]>,
    fixed: Vec<bool>,
    /// Quads whose vertex order was reversed to agree with their neighbours.
    reoriented: Vec<u32>,
    /// Per quad: its component was given clockwise (empty when none was).
    clockwise: Vec<bool>,
    /// Edges used by one quad only.
    boundary_edges: usize,
}

use crate::face::{Face, corner_count, reversed};

impl Mesh {
    /// Validates and builds a mesh.
    ///
    /// `fixed`, if given, holds one flag per vertex; fixed vertices never move.
    ///
    /// ```
    /// use glam::DVec2;
    /// use quadopt::Mesh;
    /// let points = vec![DVec2::new(0., 0.), DVec2::new(1., 0.), DVec2::new(1., 1.), DVec2::new(0., 1.)];
    /// let mesh = Mesh::new(points, vec![[0, 1, 2, 3]], None).unwrap();
    /// assert_eq!(mesh.quads().len(), 1);
    /// assert!(Mesh::new(vec![DVec2::ZERO; 3], vec![[0, 1, 2, 3]], None).is_err());
    /// ```
    pub fn new(points: Vec<DVec2>, quads: Vec<[u32; 4]>, fixed: Option<Vec<bool>>) -> Result<Self> {
        Self::build(points, quads, fixed, false)
    }

    /// Validates and builds a quad-dominant mesh: faces of four vertices or, for a triangle,
    /// three and [`crate::face::NO_VERTEX`] (see [`crate::face`]). A mesh without triangles is
    /// the mesh [`Mesh::new`] builds.
    ///
    /// ```
    /// use glam::DVec2;
    /// use quadopt::{Mesh, face};
    /// let points = vec![DVec2::new(0., 0.), DVec2::new(1., 0.), DVec2::new(1., 1.), DVec2::new(0., 1.), DVec2::new(2., 0.5)];
    /// let mesh = Mesh::with_faces(points, vec![[0, 1, 2, 3], face::triangle(1, 4, 2)], None).unwrap();
    /// assert_eq!((mesh.faces().len(), mesh.triangle_count()), (2, 1));
    /// ```
    pub fn with_faces(points: Vec<DVec2>, faces: Vec<Face>, fixed: Option<Vec<bool>>) -> Result<Self> {
        Self::build(points, faces, fixed, true)
    }

    fn build(
        points: Vec<DVec2>,
        quads: Vec<Face>,
        fixed: Option<Vec<bool>>,
        triangles: bool,
    ) -> Result<Self> {
        let n = points.len();
        let fixed = match fixed {
            Some(f) if f.len() != n => return Err(Error::FixedLengthMismatch { expected: n, got: f.len() }),
            Some(f) => f,
            None => try_filled(n, false, "fixed flags")?,
        };
        validate_indices(&quads, n, triangles)?;
        // Coordinates of vertices used by no quad are never read, but a NaN there is still
        // almost certainly a caller bug, so reject every non-finite coordinate.
        if let Some(v) = points.iter().position(|p| !p.is_finite()) {
            return Err(Error::NonFiniteCoordinate { vertex: v });
        }
        let Oriented { quads, reoriented, clockwise, boundary_edges } = orient(&points, quads)?;
        Ok(Mesh { points, quads, fixed, reoriented, clockwise, boundary_edges })
    }

    /// A copy of the mesh, or [`Error::OutOfMemory`] (where `clone` would abort).
    pub fn try_clone(&self) -> Result<Mesh> {
        Ok(Mesh {
            points: try_copy(&self.points, "vertex coordinates")?,
            quads: try_copy(&self.quads, "quads")?,
            fixed: try_copy(&self.fixed, "fixed flags")?,
            reoriented: try_copy(&self.reoriented, "reoriented quads")?,
            clockwise: try_copy(&self.clockwise, "quad orientations")?,
            boundary_edges: self.boundary_edges,
        })
    }

    /// Vertex positions.
    pub fn points(&self) -> &[DVec2] {
        &self.points
    }

    /// Mutable vertex positions (connectivity cannot change).
    pub fn points_mut(&mut self) -> &mut [DVec2] {
        &mut self.points
    }

    /// Mutable vertex positions together with the quads (which cannot change).
    pub(crate) fn points_mut_and_quads(&mut self) -> (&mut [DVec2], &[[u32; 4]]) {
        (&mut self.points, &self.quads)
    }

    /// Faces (quads, and triangles in a quad-dominant mesh: see [`crate::face`]),
    /// consistently oriented counter-clockwise.
    pub fn quads(&self) -> &[Face] {
        &self.quads
    }

    /// The faces: [`Mesh::quads`], named for a quad-dominant mesh.
    pub fn faces(&self) -> &[Face] {
        &self.quads
    }

    /// Number of triangles (faces with [`crate::face::NO_VERTEX`] fourth).
    pub fn triangle_count(&self) -> usize {
        self.quads.iter().filter(|f| crate::face::is_triangle(f)).count()
    }

    /// Quality statistics of the quads and of the triangles apart.
    pub fn quality_by_face_kind(&self) -> crate::quality::ByFaceKind {
        crate::quality::ByFaceKind::new(&self.quads, &self.quality_values())
    }

    /// Quads in the handedness the caller used: consistently oriented, but a component given
    /// clockwise stays clockwise. This is what file writers should emit.
    pub fn quads_as_given(&self) -> Vec<[u32; 4]> {
        faces_as_given(&self.quads, &self.clockwise)
    }

    /// Per-vertex fixed flags.
    pub fn fixed(&self) -> &[bool] {
        &self.fixed
    }

    /// Quads whose vertex order was reversed to make the orientation consistent.
    pub fn reoriented(&self) -> &[u32] {
        &self.reoriented
    }

    /// Number of boundary edges (edges of one quad only); the boundary loops have at most this
    /// many vertices.
    pub fn boundary_edge_count(&self) -> usize {
        self.boundary_edges
    }

    /// Whether any connected component was given clockwise.
    pub fn has_clockwise_component(&self) -> bool {
        self.clockwise.iter().any(|&c| c)
    }

    /// The same mesh numbered differently: its vertex `i` is this mesh's `vertex_of[i]`, its
    /// quad `k` this mesh's `quad_of[k]` (both permutations), each quad with its corners in
    /// the same order.
    pub(crate) fn renumbered(&self, vertex_of: &[u32], quad_of: &[u32]) -> Result<Mesh> {
        let n = self.points.len();
        if vertex_of.len() != n {
            return Err(Error::VertexCountMismatch { expected: vertex_of.len(), got: n });
        }
        if quad_of.len() != self.quads.len() {
            return Err(Error::ConnectivityMismatch { expected: quad_of.len(), got: self.quads.len() });
        }
        let mut internal = try_filled(n, 0u32, "vertex order")?;
        for (i, &v) in vertex_of.iter().enumerate() {
            internal[v as usize] = i as u32;
        }
        let mut points = try_with_capacity(n, "vertex coordinates")?;
        points.extend(vertex_of.iter().map(|&v| self.points[v as usize]));
        let mut fixed = try_with_capacity(n, "fixed flags")?;
        fixed.extend(vertex_of.iter().map(|&v| self.fixed[v as usize]));
        let mut quads = try_with_capacity(self.quads.len(), "quads")?;
        quads.extend(
            quad_of
                .iter()
                .map(|&k| self.quads[k as usize].map(|v| internal.get(v as usize).copied().unwrap_or(v))),
        );
        let mut clockwise = try_with_capacity(self.clockwise.len(), "quad orientations")?;
        if !self.clockwise.is_empty() {
            clockwise.extend(quad_of.iter().map(|&k| self.clockwise[k as usize]));
        }
        let mut reoriented = Vec::new();
        for (k, &q) in quad_of.iter().enumerate() {
            if self.reoriented.binary_search(&q).is_ok() {
                try_push(&mut reoriented, k as u32, "reoriented quads")?;
            }
        }
        Ok(Mesh { points, quads, fixed, reoriented, clockwise, boundary_edges: self.boundary_edges })
    }

    /// Replaces the vertex positions (same count, all finite).
    pub fn set_points(&mut self, points: &[DVec2]) -> Result<()> {
        replace_points(&mut self.points, points, |p| p.is_finite())
    }

    /// Per-quad scaled Jacobians (see [`crate::quality`]).
    pub fn quality_values(&self) -> Vec<f64> {
        crate::quality::quad_values(&self.points, &self.quads)
    }

    /// [`Mesh::quality_values`], or [`Error::OutOfMemory`].
    pub fn try_quality_values(&self) -> Result<Vec<f64>> {
        let mut values = try_with_capacity(self.quads.len(), "quality values")?;
        values.resize(self.quads.len(), 0.0);
        crate::quality::values_into(&self.points, &self.quads, &mut values);
        Ok(values)
    }

    /// Quality statistics of the mesh.
    pub fn quality(&self) -> crate::quality::QualityStats {
        crate::quality::QualityStats::from_values(&self.quality_values())
    }
}

/// Copies `new` over `current`: the same count, every point finite (`is_finite`).
pub(crate) fn replace_points<P: Copy>(
    current: &mut [P],
    new: &[P],
    is_finite: impl Fn(&P) -> bool,
) -> Result<()> {
    if new.len() != current.len() {
        return Err(Error::VertexCountMismatch { expected: current.len(), got: new.len() });
    }
    if let Some(v) = new.iter().position(|p| !is_finite(p)) {
        return Err(Error::NonFiniteCoordinate { vertex: v });
    }
    current.copy_from_slice(new);
    Ok(())
}

/// Reverses every face of `component` and flags it in `turned`.
pub(crate) fn reverse_component(faces: &mut [Face], component: &[u32], turned: &mut [bool]) {
    for &f in component {
        faces[f as usize] = reversed(faces[f as usize]);
        turned[f as usize] = true;
    }
}

/// `faces` with each face whose `turned` flag is set reversed back (no flags: none was turned).
pub(crate) fn faces_as_given(faces: &[Face], turned: &[bool]) -> Vec<Face> {
    if turned.is_empty() {
        return faces.to_vec();
    }
    faces.iter().zip(turned).map(|(&f, &t)| if t { reversed(f) } else { f }).collect()
}

/// Checks every face's indices; `triangles` lets a face end in [`crate::face::NO_VERTEX`].
pub(crate) fn validate_indices(quads: &[Face], n: usize, triangles: bool) -> Result<()> {
    if quads.is_empty() {
        return Err(Error::NoQuads);
    }
    for (qi, q) in quads.iter().enumerate() {
        let corners = if triangles { corner_count(q) } else { 4 };
        for (c, &v) in q[..corners].iter().enumerate() {
            if v as usize >= n {
                return Err(Error::IndexOutOfRange { quad: qi, corner: c, index: v as u64, vertex_count: n });
            }
            if q[..c].contains(&v) {
                return Err(Error::RepeatedVertex { quad: qi, vertex: v });
            }
        }
    }
    Ok(())
}

/// One directed quad edge: (min vertex, max vertex, quad, whether it runs min -> max).
type EdgeRecord = (u32, u32, u32, bool);

/// The quad edges sorted by undirected key, so quads sharing an edge are adjacent, and the
/// number of boundary edges. Fails on an edge used by more than two quads.
fn sorted_edges(quads: &[Face]) -> Result<(Vec<EdgeRecord>, usize)> {
    // No overflow: `quads` holds 16 bytes per quad within isize::MAX.
    let mut edges: Vec<EdgeRecord> = try_with_capacity(quads.len() * 4, "quad edges")?;
    for (qi, q) in quads.iter().enumerate() {
        let n = corner_count(q);
        for i in 0..n {
            let (a, b) = (q[i], q[(i + 1) % n]);
            edges.push((a.min(b), a.max(b), qi as u32, a < b));
        }
    }
    edges.sort_unstable();
    let mut boundary = 0;
    let mut i = 0;
    while i < edges.len() {
        let mut j = i + 1;
        while j < edges.len() && edges[j].0 == edges[i].0 && edges[j].1 == edges[i].1 {
            j += 1;
        }
        if j - i > 2 {
            return Err(Error::NonManifoldEdge {
                a: edges[i].0,
                b: edges[i].1,
                count: j - i,
                first: edges[i].2 as usize,
                second: edges[i + 1].2 as usize,
            });
        }
        boundary += usize::from(j - i == 1);
        i = j;
    }
    Ok((edges, boundary))
}

/// Signed area of a quad whose corners are scaled by `2^scale` (exact, so the sign is that of
/// the true area; the scale keeps the products from overflowing or underflowing).
fn signed_area(points: &[DVec2], q: &[u32; 4], scale: i32) -> f64 {
    let p = crate::quality::corners(points, q).map(|p| crate::power_of_two::scale_point(p, scale));
    // Shoelace formula; a quad's doubled area is the cross product of its diagonals.
    0.5 * (p[2] - p[0]).perp_dot(p[3] - p[1])
}

/// The consistently oriented quads and what orienting them found.
struct Oriented {
    quads: Vec<[u32; 4]>,
    reoriented: Vec<u32>,
    clockwise: Vec<bool>,
    boundary_edges: usize,
}

/// Makes orientation consistent per component and counter-clockwise internally.
fn orient(points: &[DVec2], mut quads: Vec<[u32; 4]>) -> Result<Oriented> {
    let nq = quads.len();
    let mut clockwise = try_filled(nq, false, "quad orientations")?;
    let mut any_clockwise = false;
    let (reoriented, boundary_edges) = orient_components(&mut quads, |quads, component, closed| {
        // A closed surface cannot lie flat in a plane without folds.
        if closed {
            return Err(Error::ClosedMesh { quad: component[0] as usize, whole_mesh: component.len() == nq });
        }
        // Areas on coordinates scaled so the component's largest is in [1, 2): the sum's sign
        // is right at any scale.
        let largest = component
            .iter()
            .flat_map(|&q| quads[q as usize])
            .filter(|&v| v != crate::face::NO_VERTEX)
            .fold(0.0f64, |m, v| m.max(points[v as usize].abs().max_element()));
        let scale = if largest > 0.0 { -crate::power_of_two::binary_exponent(largest) } else { 0 };
        let mut area = 0.0;
        for &q in component {
            area += signed_area(points, &quads[q as usize], scale);
        }
        if area < 0.0 {
            any_clockwise = true;
            reverse_component(quads, component, &mut clockwise);
        }
        Ok(())
    })?;
    if !any_clockwise {
        clockwise = Vec::new();
    }
    Ok(Oriented { quads, reoriented, clockwise, boundary_edges })
}

/// The coordinate-free part of orienting a mesh, shared by the planar [`Mesh`] and
/// [`crate::surface::SurfaceMesh`]: finds the connected components of `faces` (through shared
/// edges), refuses an edge of more than two faces ([`Error::NonManifoldEdge`]) and a
/// non-orientable component ([`Error::NonOrientable`]), and reverses the faces that disagree
/// with their component's majority. After each component is made consistent, `component` is
/// called with the faces, the component's face indices (breadth-first order from its seed,
/// the lowest index) and whether it is closed (no boundary edge); it may reverse the whole
/// component or refuse it. Returns the reversed faces (sorted) and the number of boundary
/// edges.
pub(crate) fn orient_components(
    quads: &mut [Face],
    mut component_done: impl FnMut(&mut [Face], &[u32], bool) -> Result<()>,
) -> Result<(Vec<u32>, usize)> {
    let (edges, boundary_edges) = sorted_edges(quads)?;
    // Dual graph in CSR form: neighbour quad and whether the shared edge runs the same way in
    // both (which means one of them must be reversed). Each quad has at most four neighbours,
    // so degrees fit in u8 and the offsets (up to 4 * quads) in usize.
    let nq = quads.len();
    let mut degree = try_filled(nq, 0u8, "quad degrees")?;
    let mut pairs = try_with_capacity(edges.len() / 2, "quad adjacency")?;
    for w in edges.windows(2) {
        if w[0].0 == w[1].0 && w[0].1 == w[1].1 {
            pairs.push((w[0].2, w[1].2, w[0].3 == w[1].3));
            degree[w[0].2 as usize] += 1;
            degree[w[1].2 as usize] += 1;
        }
    }
    drop(edges);
    let mut offsets = try_filled(nq + 1, 0usize, "quad adjacency offsets")?;
    for q in 0..nq {
        offsets[q + 1] = offsets[q] + usize::from(degree[q]);
    }
    drop(degree);
    let mut fill = try_copy(&offsets, "quad adjacency offsets")?;
    let mut adj = try_filled(offsets[nq], (0u32, false), "quad adjacency")?;
    for &(a, b, same) in &pairs {
        adj[fill[a as usize]] = (b, same);
        fill[a as usize] += 1;
        adj[fill[b as usize]] = (a, same);
        fill[b as usize] += 1;
    }
    drop((pairs, fill));

    // flip[q]: reverse q relative to its component's seed. Breadth-first over the dual graph.
    const UNSEEN: u8 = 2;
    let mut flip = try_filled(nq, UNSEEN, "quad orientations")?;
    let mut reoriented = Vec::new();
    // No component has more than nq quads, so pushing never reallocates.
    let mut component = try_with_capacity(nq, "mesh components")?;
    for seed in 0..nq {
        if flip[seed] != UNSEEN {
            continue;
        }
        component.clear();
        flip[seed] = 0;
        component.push(seed as u32);
        let mut head = 0;
        while head < component.len() {
            let q = component[head] as usize;
            head += 1;
            for &(nb, same) in &adj[offsets[q]..offsets[q + 1]] {
                let want = flip[q] ^ u8::from(same);
                match flip[nb as usize] {
                    UNSEEN => {
                        flip[nb as usize] = want;
                        component.push(nb);
                    }
                    f if f != want => return Err(Error::NonOrientable { quad: nb as usize }),
                    _ => {}
                }
            }
        }
        // A component with no boundary edge (every face has a neighbour per edge) is closed.
        let closed = component
            .iter()
            .all(|&q| offsets[q as usize + 1] - offsets[q as usize] == corner_count(&quads[q as usize]));
        // Reverse the minority, so "reoriented" lists as few quads as possible.
        let flipped = component.iter().filter(|&&q| flip[q as usize] == 1).count();
        let minority = u8::from(flipped * 2 <= component.len());
        for &q in &component {
            let q = q as usize;
            if flip[q] == minority {
                quads[q] = reversed(quads[q]);
                try_push(&mut reoriented, q as u32, "reoriented quads")?;
            }
        }
        component_done(quads, &component, closed)?;
    }
    reoriented.sort_unstable();
    Ok((reoriented, boundary_edges))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 2x1 strip of unit squares: vertices 0..6, quads counter-clockwise.
    fn strip() -> (Vec<DVec2>, Vec<[u32; 4]>) {
        let p = [(0., 0.), (1., 0.), (2., 0.), (0., 1.), (1., 1.), (2., 1.)];
        (p.iter().map(|&(x, y)| DVec2::new(x, y)).collect(), vec![[0, 1, 4, 3], [1, 2, 5, 4]])
    }

    #[test]
    fn errors_name_the_offending_item() {
        let (p, _) = strip();
        assert_eq!(Mesh::new(p.clone(), vec![], None).unwrap_err(), Error::NoQuads);
        assert_eq!(
            Mesh::new(p.clone(), vec![[0, 1, 4, 3], [1, 2, 9, 4]], None).unwrap_err(),
            Error::IndexOutOfRange { quad: 1, corner: 2, index: 9, vertex_count: 6 }
        );
        assert_eq!(
            Mesh::new(p.clone(), vec![[0, 1, 1, 3]], None).unwrap_err(),
            Error::RepeatedVertex { quad: 0, vertex: 1 }
        );
        let mut bad = p.clone();
        bad[4].y = f64::NAN;
        assert_eq!(
            Mesh::new(bad, vec![[0, 1, 4, 3]], None).unwrap_err(),
            Error::NonFiniteCoordinate { vertex: 4 }
        );
        assert_eq!(
            Mesh::new(p.clone(), vec![[0, 1, 4, 3]], Some(vec![false; 2])).unwrap_err(),
            Error::FixedLengthMismatch { expected: 6, got: 2 }
        );
        // Three quads on edge (1, 4).
        let mut p3 = p.clone();
        p3.push(DVec2::new(1.5, 2.0));
        p3.push(DVec2::new(0.5, 2.0));
        let err = Mesh::new(p3, vec![[0, 1, 4, 3], [1, 2, 5, 4], [1, 4, 6, 7]], None).unwrap_err();
        assert!(matches!(err, Error::NonManifoldEdge { a: 1, b: 4, count: 3, .. }), "{err:?}");
    }

    #[test]
    fn fallible_copies_match_and_boundary_edges_are_counted() {
        let (p, q) = strip();
        let mesh = Mesh::new(p, vec![q[0], reversed(q[1])], None).unwrap();
        // The 2x1 strip: 7 edges, the middle one shared.
        assert_eq!(mesh.boundary_edge_count(), 6);
        let copy = mesh.try_clone().unwrap();
        assert_eq!((copy.points(), copy.quads(), copy.fixed()), (mesh.points(), mesh.quads(), mesh.fixed()));
        assert_eq!((copy.reoriented(), copy.boundary_edge_count()), (&[1][..], 6));
        assert_eq!(mesh.try_quality_values().unwrap(), mesh.quality_values());
    }

    /// An n x n grid whose quads wrap around in both directions (a torus): every vertex is
    /// interior, no edge is on the boundary.
    fn periodic_grid(n: u32) -> (Vec<DVec2>, Vec<[u32; 4]>) {
        let id = |i: u32, j: u32| (j % n) * n + i % n;
        let points = (0..n * n).map(|v| DVec2::new(f64::from(v % n), f64::from(v / n))).collect();
        let quads = (0..n * n)
            .map(|c| (c % n, c / n))
            .map(|(i, j)| [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        (points, quads.collect())
    }

    #[test]
    fn closed_meshes_and_closed_parts_are_refused() {
        // A closed surface (a cube's six faces) has no boundary; neither has a periodic grid.
        let cube = vec![[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]];
        let corners: Vec<DVec2> = (0..8).map(|i| DVec2::new(f64::from(i % 4), f64::from(i / 4))).collect();
        let closed = Error::ClosedMesh { quad: 0, whole_mesh: true };
        assert_eq!(Mesh::new(corners, cube, None).unwrap_err(), closed);
        let (p, q) = periodic_grid(6);
        assert_eq!(Mesh::new(p.clone(), q.clone(), None).unwrap_err(), closed);
        assert_eq!(
            closed.to_string(),
            "the mesh is closed (it has no boundary edge): a closed surface cannot lie flat in a plane \
             without folds"
        );
        // A plate first, then the torus: the torus is a closed part, named by its first quad.
        let (mut points, mut quads) = strip();
        let offset = points.len() as u32;
        points.extend(p);
        quads.extend(q.iter().map(|q| q.map(|v| v + offset)));
        let err = Mesh::new(points, quads, None).unwrap_err();
        assert_eq!(err, Error::ClosedMesh { quad: 2, whole_mesh: false });
        assert_eq!(
            err.to_string(),
            "the mesh has a closed part (quad 2 and the quads connected to it have no boundary edge; quad \
             numbers are 0-based): a closed surface cannot lie flat in a plane without folds"
        );
        // One quad less, and the grid has a boundary (the hole it leaves).
        let (p, mut q) = periodic_grid(6);
        q.pop();
        let mesh = Mesh::new(p, q, None).unwrap();
        assert_eq!(mesh.boundary_edge_count(), 4);
    }

    #[test]
    fn mixed_orientation_is_made_consistent_and_reported() {
        let (p, _) = strip();
        let mesh = Mesh::new(p, vec![[0, 1, 4, 3], [1, 4, 5, 2]], None).unwrap();
        assert_eq!(mesh.reoriented(), &[1]);
        assert!(mesh.quality().min > 0.99);
        assert!(!mesh.has_clockwise_component());
    }

    #[test]
    fn clockwise_mesh_is_valid_and_kept_clockwise_for_output() {
        let (p, q) = strip();
        let cw: Vec<[u32; 4]> = q.iter().map(|&q| reversed(q)).collect();
        let mesh = Mesh::new(p, cw.clone(), None).unwrap();
        assert!(mesh.reoriented().is_empty());
        assert!(mesh.has_clockwise_component());
        assert_eq!(mesh.quality().inverted, 0);
        assert_eq!(mesh.quads_as_given(), cw);
    }

    #[test]
    fn moebius_strip_is_not_orientable() {
        // A ring of 4 quads whose last quad is glued with a half twist.
        let mut p = Vec::new();
        for i in 0..4 {
            let a = i as f64;
            p.push(DVec2::new(a, 0.0));
            p.push(DVec2::new(a, 1.0));
        }
        // Vertices 2i (bottom), 2i+1 (top). Quads i: (2i, 2i+2, 2i+3, 2i+1); last quad twisted.
        let quads = vec![[0, 2, 3, 1], [2, 4, 5, 3], [4, 6, 7, 5], [6, 1, 0, 7]];
        assert!(matches!(Mesh::new(p, quads, None), Err(Error::NonOrientable { .. })));
    }
}
