//! Planar meshes in 3D space: the one planarity rule of every interface (the CLI, the C ABI
//! and its C++ adapters), fitting the plane, and mapping between the file's 3D coordinates and
//! the 2D coordinates the optimizer works in.
//!
//! - If one coordinate is the same for every vertex used by a face (the plane z = c, the usual
//!   case, or x = c, y = c), the mesh is planar, the 2D coordinates are the other two
//!   coordinates, unchanged, and the constant one is kept: nothing is rounded.
//! - Otherwise the plane is fitted by least squares (centroid and the covariance matrix's
//!   eigenvector of the smallest eigenvalue, by Jacobi rotations). The mesh is planar when every
//!   used vertex lies on that plane to within rounding: no farther than
//!   [`PLANARITY_TOLERANCE`] (1e-12) times the bounding-box diagonal of the used vertices, plus
//!   [`ROUNDING_ULPS`] units in the last place of their largest coordinate (so a mesh far from
//!   the origin, whose coordinates carry less of its own size, is judged by what its
//!   coordinates can hold). An exactly planar mesh in a tilted plane, its coordinates rounded
//!   to doubles, is planar; its 2D coordinates are taken in an orthonormal frame of the plane.
//! - Anything farther is a mesh on a curved surface: [`Error::NotPlanar`] names the farthest
//!   vertex, and every interface optimizes such a mesh on its surface in 3D, never flattened
//!   (a sheet whose z wobbles by 1e-4 of its size is a surface; so is a tilted plane written
//!   with 6 significant digits, as `float` VTK files often are: Mesquite's `quad_2_not_xy`
//!   deviates by 1.0e-7 of its diagonal).
//!
//! [`PlanarFrame::fit`] is that rule: the CLI (through [`PlanarMesh::new`]), the C ABI's
//! `dim` 3 entry points and `quadopt_is_planar` (which the C++ adapters call) all decide with it.
//!
//! Writing back ([`PlanarMesh::write_back`]) replaces the 3D coordinates of the vertices whose
//! 2D position changed (compared bitwise) and nothing else, so vertices that did not move
//! (fixed, corners, unused) keep their original coordinates bit for bit, in any plane.

use super::{IoError, MeshData};
use crate::error::Error;
use crate::mesh::Mesh;
use crate::power_of_two::{binary_exponent, scale_by_power_of_two};
use glam::{DVec2, DVec3};

/// Largest allowed distance from the fitted plane, relative to the bounding-box diagonal of the
/// vertices used by faces: rounding only (see the module docs).
pub const PLANARITY_TOLERANCE: f64 = 1e-12;

/// Units in the last place of the largest coordinate (in magnitude) of the used vertices that
/// the distance from the fitted plane may also take: the rounding of coordinates far from the
/// origin, and of the fit there.
pub const ROUNDING_ULPS: f64 = 16.0;

/// The used flag of each of `vertex_count` vertices: whether a face has it (indices out of
/// range and `face::NO_VERTEX` are ignored: the mesh's validation reports them), or
/// [`Error::OutOfMemory`].
pub(crate) fn used_vertices(vertex_count: usize, faces: &[[u32; 4]]) -> Result<Vec<bool>, Error> {
    let mut used = crate::alloc::try_filled(vertex_count, false, "used-vertex flags")?;
    for f in faces {
        for &v in crate::face::vertices(f) {
            if let Some(u) = used.get_mut(v as usize) {
                *u = true;
            }
        }
    }
    Ok(used)
}

/// The plane of a mesh and its 2D coordinate frame.
#[derive(Clone, Debug, PartialEq)]
pub enum PlanarFrame {
    /// Coordinate `axis` (0 = x, 1 = y, 2 = z) equals `value` at every used vertex; the 2D
    /// coordinates are the two others, in right-handed order (yz, zx or xy).
    Axis {
        /// The constant coordinate.
        axis: usize,
        /// Its value.
        value: f64,
    },
    /// A general plane through `origin` spanned by the orthonormal `u` and `v`;
    /// `normal = u x v`.
    Tilted {
        /// A point of the plane (the centroid of the used vertices).
        origin: DVec3,
        /// First in-plane axis.
        u: DVec3,
        /// Second in-plane axis.
        v: DVec3,
        /// Unit normal.
        normal: DVec3,
    },
}

impl PlanarFrame {
    /// Fits the plane of the points whose `used` flag is set (all points when `used` is
    /// `None`) by the planarity rule of every interface (see the module docs); fails with
    /// [`Error::NotPlanar`] naming the farthest vertex when they are not planar, and
    /// [`Error::NonFiniteCoordinate`] on NaN or infinite coordinates. Allocates nothing.
    pub fn fit(points: &[[f64; 3]], used: Option<&[bool]>) -> Result<PlanarFrame, Error> {
        if let Some(v) = points.iter().position(|p| p.iter().any(|c| !c.is_finite())) {
            return Err(Error::NonFiniteCoordinate { vertex: v });
        }
        let is_used = |i: &usize| used.is_none_or(|u| u.get(*i).copied().unwrap_or(false));
        let idx = || (0..points.len()).filter(is_used);
        let Some(first) = idx().next() else {
            return Ok(PlanarFrame::Axis { axis: 2, value: 0.0 });
        };
        for axis in [2, 0, 1] {
            let value = points[first][axis];
            if idx().all(|i| points[i][axis] == value) {
                return Ok(PlanarFrame::Axis { axis, value });
            }
        }
        let p = |i: usize| DVec3::from_array(points[i]);
        let (mut lo, mut hi) = (p(first), p(first));
        let mut count = 0usize;
        for i in idx() {
            lo = lo.min(p(i));
            hi = hi.max(p(i));
            count += 1;
        }
        // Sums and products on coordinates scaled by 2^-e (exact), so that nothing overflows
        // or underflows at any scale; every comparison is between quantities scaled alike.
        // (No axis is constant here, so the extent is positive.)
        let e = binary_exponent((hi * 0.5 - lo * 0.5).max_element()) + 1;
        let scaled = |v: DVec3, e: i32| {
            DVec3::new(
                scale_by_power_of_two(v.x, e),
                scale_by_power_of_two(v.y, e),
                scale_by_power_of_two(v.z, e),
            )
        };
        let mut sum = DVec3::ZERO;
        for i in idx() {
            sum += scaled(p(i), -e);
        }
        let origin = scaled(sum / count as f64, e);
        let mut cov = [[0.0; 3]; 3];
        for i in idx() {
            let d = scaled(p(i) - origin, -e).to_array();
            for r in 0..3 {
                for c in 0..3 {
                    cov[r][c] += d[r] * d[c];
                }
            }
        }
        let normal = smallest_eigenvector(cov);
        // Rounding: the diagonal's share, and the last places of the largest coordinate.
        let largest = scaled(lo.abs().max(hi.abs()), -e).max_element();
        let tolerance =
            PLANARITY_TOLERANCE * scaled(hi - lo, -e).length() + ROUNDING_ULPS * f64::EPSILON * largest;
        let (mut worst, mut distance) = (first, 0.0);
        for i in idx() {
            let d = scaled(p(i) - origin, -e).dot(normal).abs();
            if d > distance {
                (worst, distance) = (i, d);
            }
        }
        if distance > tolerance {
            let (distance, tolerance) =
                (scale_by_power_of_two(distance, e), scale_by_power_of_two(tolerance, e));
            return Err(Error::NotPlanar { vertex: worst, distance, tolerance });
        }
        // The normal's sign and u's axis are discrete choices: taken with a relative margin so
        // that a rescaled copy of the mesh, whose fitted normal differs in its last bits, gets
        // the same frame (else its 2D copy comes out mirrored or rotated, and the optimizer's
        // result then differs by more than rounding; the plane z = x + y ties on every axis).
        let a = normal.abs();
        let near = |c: f64, m: f64| c <= m * (1.0 + FRAME_TIE);
        // Sign: the first component within the margin of the largest one is positive.
        let big = a.max_element();
        let first_big = normal.to_array().into_iter().find(|c| near(big, c.abs())).unwrap_or(1.0);
        let normal = if first_big < 0.0 { -normal } else { normal };
        // u: the coordinate axis most parallel to the plane (the first within the margin of
        // the smallest component), projected into it.
        let small = a.min_element();
        let axis = if near(a.x, small) {
            DVec3::X
        } else if near(a.y, small) {
            DVec3::Y
        } else {
            DVec3::Z
        };
        let u = (axis - axis.dot(normal) * normal).normalize();
        let v = normal.cross(u);
        Ok(PlanarFrame::Tilted { origin, u, v, normal })
    }

    /// The in-plane coordinates of a point (its projection onto the plane).
    pub fn to_2d(&self, p: [f64; 3]) -> DVec2 {
        match *self {
            PlanarFrame::Axis { axis, .. } => {
                let (i, j) = in_plane_axes(axis);
                DVec2::new(p[i], p[j])
            }
            PlanarFrame::Tilted { origin, u, v, .. } => {
                let d = DVec3::from_array(p) - origin;
                DVec2::new(d.dot(u), d.dot(v))
            }
        }
    }

    /// The point of the plane with in-plane coordinates `q`.
    pub fn to_3d(&self, q: DVec2) -> [f64; 3] {
        match *self {
            PlanarFrame::Axis { axis, value } => {
                let (i, j) = in_plane_axes(axis);
                let mut p = [0.0; 3];
                p[axis] = value;
                p[i] = q.x;
                p[j] = q.y;
                p
            }
            PlanarFrame::Tilted { origin, u, v, .. } => (origin + q.x * u + q.y * v).to_array(),
        }
    }
}

/// The two in-plane coordinates for a plane perpendicular to `axis`, right-handed.
fn in_plane_axes(axis: usize) -> (usize, usize) {
    match axis {
        0 => (1, 2),
        1 => (2, 0),
        _ => (0, 1),
    }
}

/// The unit eigenvector of the smallest eigenvalue of a symmetric 3x3 matrix (cyclic Jacobi).
#[allow(clippy::needless_range_loop)] // rows p and q are updated together
/// Relative margin within which the frame's discrete choices (the normal's sign, u's axis)
/// count components as equal: far above the fit's rounding, far below any real difference.
const FRAME_TIE: f64 = 1e-9;

fn smallest_eigenvector(mut a: [[f64; 3]; 3]) -> DVec3 {
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _ in 0..64 {
        let off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
        let diag = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
        if off <= 1e-32 * diag || off == 0.0 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            for row in a.iter_mut() {
                let (kp, kq) = (row[p], row[q]);
                row[p] = c * kp - s * kq;
                row[q] = s * kp + c * kq;
            }
            #[allow(clippy::needless_range_loop)] // rows p and q of the same matrix
            for k in 0..3 {
                let (pk, qk) = (a[p][k], a[q][k]);
                a[p][k] = c * pk - s * qk;
                a[q][k] = s * pk + c * qk;
            }
            for row in v.iter_mut() {
                let (kp, kq) = (row[p], row[q]);
                row[p] = c * kp - s * kq;
                row[q] = s * kp + c * kq;
            }
        }
    }
    let k = (0..3).min_by(|&i, &j| a[i][i].total_cmp(&a[j][j])).unwrap_or(2);
    DVec3::new(v[0][k], v[1][k], v[2][k]).normalize_or(DVec3::Z)
}

/// A file's mesh as the 2D [`Mesh`] the optimizer works on, with the frame to map it back.
#[derive(Clone, Debug)]
pub struct PlanarMesh {
    /// The 2D mesh (fixed flags from the file; vertices used by no face included, they never
    /// move).
    pub mesh: Mesh,
    /// The plane and its 2D frame.
    pub frame: PlanarFrame,
}

impl PlanarMesh {
    /// Fits the plane of `data` (see the module docs) and builds the validated 2D mesh, its
    /// triangles included ([`Mesh::with_faces`]).
    pub fn new(data: &MeshData) -> Result<PlanarMesh, IoError> {
        data.check()?;
        let used = used_vertices(data.points.len(), &data.quads)?;
        let frame = PlanarFrame::fit(&data.points, Some(&used))?;
        let points: Vec<DVec2> = data.points.iter().map(|&p| frame.to_2d(p)).collect();
        // Triangles are kept (a mesh without any is the one `Mesh::new` builds).
        let mesh = Mesh::with_faces(points, data.quads.clone(), data.fixed.clone())?;
        Ok(PlanarMesh { mesh, frame })
    }

    /// Indices of the vertices whose 2D position differs (bitwise) from their position in
    /// `data`, the mesh this was built from (before [`PlanarMesh::write_back`]). The initial
    /// positions are not kept (16 bytes a vertex): they are the plane image of `data`'s.
    pub fn moved(&self, data: &MeshData) -> Vec<usize> {
        (0..self.mesh.points().len()).filter(|&i| self.has_moved(data, i)).collect()
    }

    /// Whether vertex `i` is no longer where `data` puts it.
    fn has_moved(&self, data: &MeshData, i: usize) -> bool {
        let (now, was) = (self.mesh.points()[i], data.points.get(i).map(|&p| self.frame.to_2d(p)));
        was.is_none_or(|was| now.x.to_bits() != was.x.to_bits() || now.y.to_bits() != was.y.to_bits())
    }

    /// Writes the optimized positions back into `data` (the mesh this was built from) and
    /// returns how many vertices moved: moved vertices get their point of the plane, every
    /// other vertex keeps its original coordinates bit for bit; the faces become
    /// [`Mesh::quads_as_given`] (consistently oriented, in the handedness of the input),
    /// so `data.quads` need not be kept meanwhile.
    pub fn write_back(&self, data: &mut MeshData) -> usize {
        let mut moved = 0;
        for i in 0..self.mesh.points().len().min(data.points.len()) {
            if self.has_moved(data, i) {
                data.points[i] = self.frame.to_3d(self.mesh.points()[i]);
                moved += 1;
            }
        }
        data.quads = self.mesh.quads_as_given();
        moved
    }
}
