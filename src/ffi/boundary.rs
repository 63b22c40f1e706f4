//! The boundary between C and Rust: the panic boundary every entry point runs in, and the
//! checks of the caller's arrays (NULL only with a zero length, alignment, byte sizes within
//! `isize::MAX`, `uint32_t` index ranges) before they are read into owned memory or written.

use crate::alloc::try_with_capacity;
use crate::io::PlanarFrame;
use crate::mesh::Mesh;
use crate::quiet_threads;
use crate::surface::SurfaceMesh;
use glam::{DVec2, DVec3};
use std::panic::{self, AssertUnwindSafe};

use super::quiet;
use super::status::{FfiError, QuadoptStatus, set_last_error};

/// The fourth index of a triangle in the face arrays ("no vertex"): every function that takes
/// `quads` reads four `uint32_t` per face, a quad as four vertex indices and a triangle as
/// three followed by `QUADOPT_NO_VERTEX`, so a quad-dominant mesh (quads and triangles) uses
/// the same arrays, the same stride and the same functions as a quad mesh. Anywhere else in a
/// face (its first three slots) it is an index out of range
/// (`QUADOPT_STATUS_INDEX_OUT_OF_RANGE`). Equal to `UINT32_MAX`, never a valid index (a mesh
/// has at most `UINT32_MAX` vertices, numbered from 0).
pub const QUADOPT_NO_VERTEX: u32 = 0xFFFF_FFFF;

const _: () = assert!(QUADOPT_NO_VERTEX == crate::face::NO_VERTEX, "the C sentinel is the face model's");

fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_owned()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "unknown panic payload".to_owned()
    }
}

/// Runs the body of entry point `name`: catches panics, records the message of a failure in
/// the thread-local last error and turns the outcome into a status.
pub(super) fn boundary(name: &str, body: impl FnOnce() -> Result<(), FfiError>) -> QuadoptStatus {
    quiet::install_hook();
    let inside = quiet_threads::enter(true);
    let outcome = panic::catch_unwind(AssertUnwindSafe(body));
    drop(inside);
    match outcome {
        Ok(Ok(())) => QuadoptStatus::Ok,
        Ok(Err(e)) => {
            set_last_error(format!("{name}: {}", e.message));
            e.status
        }
        Err(payload) => {
            set_last_error(format!(
                "{name}: internal error (panic: {}); please report this bug",
                panic_message(payload.as_ref())
            ));
            QuadoptStatus::Panic
        }
    }
}

/// Panic boundary for the functions without a status: a panic returns `fallback`.
pub(super) fn boundary_or<T>(fallback: T, body: impl FnOnce() -> T) -> T {
    quiet::install_hook();
    let _inside = quiet_threads::enter(true);
    panic::catch_unwind(AssertUnwindSafe(body)).unwrap_or(fallback)
}

/// Checks the caller's array `ptr[0..len]` without touching it: NULL is accepted only with
/// `len == 0`, the pointer must be aligned and the byte size must fit in `isize::MAX` (what
/// `std::slice::from_raw_parts` requires).
fn check_array<T>(ptr: *const T, len: usize, what: &str) -> Result<(), FfiError> {
    if len == 0 {
        return Ok(());
    }
    if ptr.is_null() {
        return Err(FfiError::new(QuadoptStatus::NullPointer, format!("{what} is NULL (length {len})")));
    }
    if !ptr.is_aligned() {
        return Err(FfiError::new(
            QuadoptStatus::InvalidArgument,
            format!("{what} is not aligned to {} bytes", align_of::<T>()),
        ));
    }
    check_bytes(len, size_of::<T>(), what)?;
    Ok(())
}

/// A read-only view of the caller's array `ptr[0..len]`, after [`check_array`].
///
/// # Safety
/// If `len > 0`, `ptr` must point to `len` initialized values of `T` that stay valid and are
/// not written by anyone for the returned lifetime.
unsafe fn checked_slice<'a, T>(ptr: *const T, len: usize, what: &str) -> Result<&'a [T], FfiError> {
    check_array(ptr, len, what)?;
    if len == 0 {
        return Ok(&[]);
    }
    // SAFETY: non-null and aligned, the byte size fits in isize (checked by check_array), and
    // the caller guarantees `len` valid values not written during the borrow.
    Ok(unsafe { std::slice::from_raw_parts(ptr, len) })
}

/// Checks that `count` elements of `size` bytes fit in `isize::MAX` bytes.
pub(super) fn check_bytes(count: usize, size: usize, what: &str) -> Result<usize, FfiError> {
    match count.checked_mul(size) {
        Some(bytes) if bytes <= isize::MAX as usize => Ok(bytes),
        _ => Err(FfiError::new(
            QuadoptStatus::InvalidArgument,
            format!("{what}: {count} elements of {size} bytes overflow the address space"),
        )),
    }
}

/// `a * b` for element counts, naming the quantities on overflow.
pub(super) fn checked_count(a: usize, b: usize, what: &str) -> Result<usize, FfiError> {
    a.checked_mul(b).ok_or_else(|| {
        FfiError::new(QuadoptStatus::InvalidArgument, format!("{what}: {a} * {b} overflows size_t"))
    })
}

pub(super) fn require_non_null<T>(ptr: *const T, what: &str) -> Result<(), FfiError> {
    if ptr.is_null() {
        return Err(FfiError::new(QuadoptStatus::NullPointer, format!("{what} is NULL")));
    }
    if !ptr.is_aligned() {
        return Err(FfiError::new(
            QuadoptStatus::InvalidArgument,
            format!("{what} is not aligned to {} bytes", align_of::<T>()),
        ));
    }
    Ok(())
}

fn check_dim(dim: u32) -> Result<usize, FfiError> {
    match dim {
        2 | 3 => Ok(dim as usize),
        _ => Err(FfiError::new(
            QuadoptStatus::InvalidArgument,
            format!("dim is {dim}; coordinates must have 2 or 3 components per vertex"),
        )),
    }
}

/// Vertex and quad indices are `uint32_t`, so larger counts cannot be meshes.
fn check_u32_count(count: usize, what: &str) -> Result<(), FfiError> {
    if count > u32::MAX as usize {
        return Err(FfiError::new(
            QuadoptStatus::InvalidArgument,
            format!("{what} is {count}; at most {} are supported (uint32_t indices)", u32::MAX),
        ));
    }
    Ok(())
}

/// Reads `vertex_count` points of `dim` doubles (x and y; z is ignored) into owned memory.
///
/// # Safety
/// `coords` must be NULL with `vertex_count == 0`, or point to `vertex_count * dim` doubles.
pub(super) unsafe fn read_points(
    coords: *const f64,
    dim: u32,
    vertex_count: usize,
) -> Result<Vec<DVec2>, FfiError> {
    let dim = check_dim(dim)?;
    check_u32_count(vertex_count, "vertex_count")?;
    let len = checked_count(vertex_count, dim, "vertex_count * dim")?;
    // SAFETY: the caller guarantees `coords` holds `vertex_count * dim` doubles.
    let flat = unsafe { checked_slice(coords, len, "coords") }?;
    let mut points = try_with_capacity(vertex_count, "vertex coordinates")?;
    points.extend(flat.chunks_exact(dim).map(|c| DVec2::new(c[0], c[1])));
    Ok(points)
}

/// Reads `quad_count` faces of four `uint32_t` indices into owned memory (a triangle's fourth
/// is [`QUADOPT_NO_VERTEX`], which [`Mesh::with_faces`] checks).
///
/// # Safety
/// `quads` must be NULL with `quad_count == 0`, or point to `4 * quad_count` indices.
unsafe fn read_quads(quads: *const u32, quad_count: usize) -> Result<Vec<[u32; 4]>, FfiError> {
    check_u32_count(quad_count, "quad_count")?;
    let len = checked_count(quad_count, 4, "quad_count * 4")?;
    // SAFETY: the caller guarantees `quads` holds `4 * quad_count` indices.
    let flat = unsafe { checked_slice(quads, len, "quads") }?;
    let mut out = try_with_capacity(quad_count, "quads")?;
    out.extend(flat.chunks_exact(4).map(|q| [q[0], q[1], q[2], q[3]]));
    Ok(out)
}

/// Reads the optional fixed mask (`vertex_count` bytes, nonzero = fixed).
///
/// # Safety
/// `fixed` must be NULL or point to `vertex_count` bytes.
unsafe fn read_fixed(fixed: *const u8, vertex_count: usize) -> Result<Option<Vec<bool>>, FfiError> {
    if fixed.is_null() {
        return Ok(None);
    }
    // SAFETY: non-null, so the caller guarantees `vertex_count` bytes.
    let flags = unsafe { checked_slice(fixed, vertex_count, "fixed") }?;
    let mut out = try_with_capacity(vertex_count, "fixed flags")?;
    out.extend(flags.iter().map(|&f| f != 0));
    Ok(Some(out))
}

/// Builds and validates a mesh from the caller's arrays.
///
/// # Safety
/// As [`read_points`], [`read_quads`] and [`read_fixed`].
pub(super) unsafe fn read_mesh(
    coords: *const f64,
    dim: u32,
    vertex_count: usize,
    quads: *const u32,
    quad_count: usize,
    fixed: *const u8,
) -> Result<Mesh, FfiError> {
    // Every check of every array first, so no array is read when another one is bad.
    let dim_n = check_dim(dim)?;
    check_u32_count(vertex_count, "vertex_count")?;
    check_u32_count(quad_count, "quad_count")?;
    check_array(coords, checked_count(vertex_count, dim_n, "vertex_count * dim")?, "coords")?;
    check_array(quads, checked_count(quad_count, 4, "quad_count * 4")?, "quads")?;
    if !fixed.is_null() {
        check_array(fixed, vertex_count, "fixed")?;
    }
    // SAFETY: forwarded from this function's contract.
    let points = unsafe { read_points(coords, dim, vertex_count) }?;
    // SAFETY: forwarded from this function's contract.
    let quads = unsafe { read_quads(quads, quad_count) }?;
    // SAFETY: forwarded from this function's contract.
    let fixed = unsafe { read_fixed(fixed, vertex_count) }?;
    // Faces: quads, and triangles with QUADOPT_NO_VERTEX fourth (a quad-only array builds the
    // mesh Mesh::new would).
    Ok(Mesh::with_faces(points, quads, fixed)?)
}

/// Where a mesh given to a planar-or-surface entry point lies, by the library's one
/// planarity rule ([`PlanarFrame::fit`], `src/io/planar.rs`: the vertices used by a face lie on
/// a plane to within rounding).
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Plane {
    /// x and y are the plane's coordinates: `dim` 2, or `dim` 3 with the same z at every used
    /// vertex. The planar path as ever: x and y read and written, z never read or written.
    Xy,
    /// Another plane (x or y constant, or a tilted plane): the planar path in this frame, the
    /// 3D coordinates of moved vertices written back onto the plane.
    Frame(PlanarFrame),
    /// Not planar: a mesh on a curved surface, for the surface optimizer.
    Curved,
}

/// Which [`Plane`] the caller's `dim` 3 mesh lies in. `Xy` whenever a check of `coords` fails
/// (so that the planar path, which checks them first, reports the failure exactly as before)
/// and for a z that is the same (equal, `-0.0` and `0.0` included, or bit-identical, so a z
/// left as one NaN pattern stays the planar path's, whose z is never read) at every vertex, as
/// it always was; otherwise the rule decides on the vertices used by a face. `Curved` when the
/// faces' checks fail or a coordinate is not finite: the surface path reports that as it did.
///
/// # Safety
/// As [`read_mesh`].
pub(super) unsafe fn plane_of(
    coords: *const f64,
    dim: u32,
    vertex_count: usize,
    quads: *const u32,
    quad_count: usize,
) -> Result<Plane, FfiError> {
    if dim != 3 || vertex_count < 2 || check_u32_count(vertex_count, "vertex_count").is_err() {
        return Ok(Plane::Xy);
    }
    let Ok(len) = checked_count(vertex_count, 3, "vertex_count * dim") else { return Ok(Plane::Xy) };
    // SAFETY: the caller guarantees `coords` holds `vertex_count * 3` doubles.
    let Ok(flat) = (unsafe { checked_slice(coords, len, "coords") }) else { return Ok(Plane::Xy) };
    if same_z(flat) {
        return Ok(Plane::Xy);
    }
    let faces = match check_u32_count(quad_count, "quad_count")
        .and_then(|()| checked_count(quad_count, 4, "quad_count * 4"))
    {
        // SAFETY: the caller guarantees `quads` holds `4 * quad_count` indices.
        Ok(len) => match unsafe { checked_slice(quads, len, "quads") } {
            Ok(faces) => faces,
            Err(_) => return Ok(Plane::Curved),
        },
        Err(_) => return Ok(Plane::Curved),
    };
    // SAFETY: `faces` holds `4 * quad_count` indices, and `[u32; 4]` has the size of four of
    // them and their alignment.
    let faces = unsafe { std::slice::from_raw_parts(faces.as_ptr().cast::<[u32; 4]>(), quad_count) };
    plane_by_rule(flat, faces)
}

/// [`plane_of`] for the faces of a validated mesh (a reusable optimizer's).
///
/// # Safety
/// As [`read_points`].
pub(super) unsafe fn plane_of_faces(
    coords: *const f64,
    dim: u32,
    vertex_count: usize,
    faces: &[[u32; 4]],
) -> Result<Plane, FfiError> {
    if dim != 3 || vertex_count < 2 || check_u32_count(vertex_count, "vertex_count").is_err() {
        return Ok(Plane::Xy);
    }
    let Ok(len) = checked_count(vertex_count, 3, "vertex_count * dim") else { return Ok(Plane::Xy) };
    // SAFETY: the caller guarantees `coords` holds `vertex_count * 3` doubles.
    let Ok(flat) = (unsafe { checked_slice(coords, len, "coords") }) else { return Ok(Plane::Xy) };
    if same_z(flat) {
        return Ok(Plane::Xy);
    }
    plane_by_rule(flat, faces)
}

/// A checked read-only view of the caller's `vertex_count` points of three doubles.
///
/// # Safety
/// `coords` must be NULL with `vertex_count == 0`, or point to `vertex_count * 3` doubles that
/// stay valid and unwritten for the returned lifetime.
pub(super) unsafe fn read_points_3d_flat<'a>(
    coords: *const f64,
    vertex_count: usize,
) -> Result<&'a [[f64; 3]], FfiError> {
    check_u32_count(vertex_count, "vertex_count")?;
    let len = checked_count(vertex_count, 3, "vertex_count * 3")?;
    // SAFETY: the caller guarantees `coords` holds `vertex_count * 3` doubles.
    let flat = unsafe { checked_slice(coords, len, "coords") }?;
    // SAFETY: `[f64; 3]` has the size of three doubles and their alignment.
    Ok(unsafe { std::slice::from_raw_parts(flat.as_ptr().cast::<[f64; 3]>(), vertex_count) })
}

/// A checked read-only view of the caller's `quad_count` faces of four indices.
///
/// # Safety
/// `quads` must be NULL with `quad_count == 0`, or point to `4 * quad_count` indices that stay
/// valid and unwritten for the returned lifetime.
pub(super) unsafe fn read_quads_checked<'a>(
    quads: *const u32,
    quad_count: usize,
) -> Result<&'a [[u32; 4]], FfiError> {
    check_u32_count(quad_count, "quad_count")?;
    let len = checked_count(quad_count, 4, "quad_count * 4")?;
    // SAFETY: the caller guarantees `quads` holds `4 * quad_count` indices.
    let flat = unsafe { checked_slice(quads, len, "quads") }?;
    // SAFETY: `[u32; 4]` has the size of four indices and their alignment.
    Ok(unsafe { std::slice::from_raw_parts(flat.as_ptr().cast::<[u32; 4]>(), quad_count) })
}

/// Whether z (every third double) is the same at every vertex: equal or bit-identical.
fn same_z(flat: &[f64]) -> bool {
    let z0 = flat[2];
    flat.chunks_exact(3).all(|c| c[2] == z0 || c[2].to_bits() == z0.to_bits())
}

/// The library's planarity rule on the points `flat` (three doubles each) used by `faces`.
fn plane_by_rule(flat: &[f64], faces: &[[u32; 4]]) -> Result<Plane, FfiError> {
    let vertex_count = flat.len() / 3;
    // SAFETY: `flat` holds `3 * vertex_count` doubles, and `[f64; 3]` has the size of three
    // doubles and their alignment.
    let points = unsafe { std::slice::from_raw_parts(flat.as_ptr().cast::<[f64; 3]>(), vertex_count) };
    let used = crate::io::planar::used_vertices(vertex_count, faces)?;
    Ok(match PlanarFrame::fit(points, Some(&used)) {
        Ok(PlanarFrame::Axis { axis: 2, .. }) => Plane::Xy,
        Ok(frame) => Plane::Frame(frame),
        Err(_) => Plane::Curved,
    })
}

/// Reads `vertex_count` points of three doubles into owned memory as their 2D coordinates in
/// `frame`.
///
/// # Safety
/// `coords` must be NULL with `vertex_count == 0`, or point to `vertex_count * 3` doubles.
pub(super) unsafe fn read_points_in(
    coords: *const f64,
    vertex_count: usize,
    frame: &PlanarFrame,
) -> Result<Vec<DVec2>, FfiError> {
    check_u32_count(vertex_count, "vertex_count")?;
    let len = checked_count(vertex_count, 3, "vertex_count * dim")?;
    // SAFETY: the caller guarantees `coords` holds `vertex_count * 3` doubles.
    let flat = unsafe { checked_slice(coords, len, "coords") }?;
    let mut points = try_with_capacity(vertex_count, "vertex coordinates")?;
    points.extend(flat.chunks_exact(3).map(|c| frame.to_2d([c[0], c[1], c[2]])));
    Ok(points)
}

/// Builds and validates a mesh from the caller's arrays (`dim` 3) in the 2D coordinates of
/// `frame`.
///
/// # Safety
/// As [`read_mesh`] with `dim` 3.
pub(super) unsafe fn read_mesh_in(
    coords: *const f64,
    vertex_count: usize,
    quads: *const u32,
    quad_count: usize,
    fixed: *const u8,
    frame: &PlanarFrame,
) -> Result<Mesh, FfiError> {
    // The checks of every array first, as read_mesh makes them.
    check_u32_count(vertex_count, "vertex_count")?;
    check_u32_count(quad_count, "quad_count")?;
    check_array(coords, checked_count(vertex_count, 3, "vertex_count * dim")?, "coords")?;
    check_array(quads, checked_count(quad_count, 4, "quad_count * 4")?, "quads")?;
    if !fixed.is_null() {
        check_array(fixed, vertex_count, "fixed")?;
    }
    // SAFETY: forwarded from this function's contract.
    let points = unsafe { read_points_in(coords, vertex_count, frame) }?;
    // SAFETY: forwarded from this function's contract.
    let quads = unsafe { read_quads(quads, quad_count) }?;
    // SAFETY: forwarded from this function's contract.
    let fixed = unsafe { read_fixed(fixed, vertex_count) }?;
    Ok(Mesh::with_faces(points, quads, fixed)?)
}

/// Reads the optional marked feature edges (`2 * count` vertex indices, two per edge) into
/// owned memory.
///
/// # Safety
/// `edges` must be NULL with `count == 0`, or point to `2 * count` indices.
unsafe fn read_feature_edges(edges: *const u32, count: usize) -> Result<Vec<[u32; 2]>, FfiError> {
    let len = checked_count(count, 2, "feature_edge_count * 2")?;
    // SAFETY: the caller guarantees `edges` holds `2 * count` indices.
    let flat = unsafe { checked_slice(edges, len, "feature_edges") }?;
    let mut out = try_with_capacity(count, "feature edges")?;
    out.extend(flat.chunks_exact(2).map(|e| [e[0], e[1]]));
    Ok(out)
}

/// Checks every marked feature edge against `mesh`: a vertex out of range is
/// `QUADOPT_STATUS_INDEX_OUT_OF_RANGE`, a pair that is not an edge of the mesh
/// `QUADOPT_STATUS_INVALID_ARGUMENT`, each naming the pair.
pub(super) fn check_feature_edges(mesh: &SurfaceMesh, edges: &[[u32; 2]]) -> Result<(), FfiError> {
    let n = mesh.points().len();
    for (k, &[a, b]) in edges.iter().enumerate() {
        if let Some(v) = [a, b].into_iter().find(|&v| v as usize >= n) {
            return Err(FfiError::new(
                QuadoptStatus::IndexOutOfRange,
                format!(
                    "feature edge {k}, vertices ({a}, {b}), refers to vertex {v}, but vertex_count is {n}"
                ),
            ));
        }
        if a == b || mesh.find_edge(a, b).is_none() {
            return Err(FfiError::new(
                QuadoptStatus::InvalidArgument,
                format!(
                    "feature edge {k}, vertices ({a}, {b}), is not an edge of the mesh (no face has \
                     these two vertices as neighbours; vertex numbers are 0-based)"
                ),
            ));
        }
    }
    Ok(())
}

/// A mesh on a surface in 3D read from the caller's arrays (three doubles per vertex), with
/// its marked feature edges (checked against the mesh). `names` are the caller's names of the
/// face array and its count, for the messages (`quadopt_optimize()` calls them `quads` and
/// `quad_count`).
///
/// # Safety
/// As [`read_mesh`] with `dim` 3; `feature_edges` NULL with `feature_edge_count == 0`, or
/// `2 * feature_edge_count` indices.
#[allow(clippy::too_many_arguments)]
pub(super) unsafe fn read_surface_mesh(
    coords: *const f64,
    vertex_count: usize,
    faces: *const u32,
    face_count: usize,
    fixed: *const u8,
    feature_edges: *const u32,
    feature_edge_count: usize,
    names: (&str, &str),
) -> Result<(SurfaceMesh, Vec<[u32; 2]>), FfiError> {
    let (faces_name, count_name) = names;
    // Every check of every array first, so no array is read when another one is bad.
    check_u32_count(vertex_count, "vertex_count")?;
    check_u32_count(face_count, count_name)?;
    let len = checked_count(vertex_count, 3, "vertex_count * 3")?;
    check_array(coords, len, "coords")?;
    check_array(faces, checked_count(face_count, 4, &format!("{count_name} * 4"))?, faces_name)?;
    if !fixed.is_null() {
        check_array(fixed, vertex_count, "fixed")?;
    }
    check_array(
        feature_edges,
        checked_count(feature_edge_count, 2, "feature_edge_count * 2")?,
        "feature_edges",
    )?;
    // SAFETY: forwarded from this function's contract (checked above).
    let flat = unsafe { checked_slice(coords, len, "coords") }?;
    let mut points = try_with_capacity(vertex_count, "vertex coordinates")?;
    points.extend(flat.chunks_exact(3).map(|c| DVec3::new(c[0], c[1], c[2])));
    // SAFETY: forwarded from this function's contract.
    let faces = unsafe { read_quads(faces, face_count) }?;
    // SAFETY: forwarded from this function's contract.
    let fixed = unsafe { read_fixed(fixed, vertex_count) }?;
    // SAFETY: forwarded from this function's contract.
    let edges = unsafe { read_feature_edges(feature_edges, feature_edge_count) }?;
    let mesh = SurfaceMesh::new(points, faces, fixed)?;
    check_feature_edges(&mesh, &edges)?;
    Ok((mesh, edges))
}

/// Writes x, y and z of every point into the caller's array of three doubles per vertex.
///
/// # Safety
/// `coords` must be aligned and point to `points.len() * 3` writable doubles.
pub(super) unsafe fn write_points_3d(coords: *mut f64, points: &[DVec3]) {
    for (i, p) in points.iter().enumerate() {
        // SAFETY: 3 * i + 2 < points.len() * 3, inside the caller's buffer; raw writes create
        // no reference.
        unsafe {
            coords.add(3 * i).write(p.x);
            coords.add(3 * i + 1).write(p.y);
            coords.add(3 * i + 2).write(p.z);
        }
    }
}

/// Writes the 2D `points` of a mesh in `frame` back into the caller's array of three doubles
/// per vertex (which still holds the input): a vertex whose 2D position differs (bitwise) from
/// its input's gets its point of the plane, every other vertex is not written. In a plane x or
/// y = const only the two in-plane coordinates are written.
///
/// # Safety
/// `coords` must be aligned and point to `points.len() * 3` readable and writable doubles.
pub(super) unsafe fn write_points_in(coords: *mut f64, points: &[DVec2], frame: &PlanarFrame) {
    for (i, p) in points.iter().enumerate() {
        // SAFETY: 3 * i + 2 < points.len() * 3, inside the caller's buffer; raw reads and
        // writes create no reference.
        unsafe {
            let at = coords.add(3 * i);
            let was = frame.to_2d([at.read(), at.add(1).read(), at.add(2).read()]);
            if was.x.to_bits() == p.x.to_bits() && was.y.to_bits() == p.y.to_bits() {
                continue;
            }
            let q = frame.to_3d(*p);
            for (c, value) in q.into_iter().enumerate() {
                if !matches!(*frame, PlanarFrame::Axis { axis, .. } if axis == c) {
                    at.add(c).write(value);
                }
            }
        }
    }
}

/// Writes x and y of every point into the caller's strided array; z is never written.
///
/// # Safety
/// `coords` must be aligned and point to `points.len() * dim` writable doubles.
pub(super) unsafe fn write_points(coords: *mut f64, dim: usize, points: &[DVec2]) {
    for (i, p) in points.iter().enumerate() {
        // SAFETY: i * dim + 1 < points.len() * dim (dim >= 2), inside the caller's buffer;
        // raw writes create no reference, so no aliasing rule is broken.
        unsafe {
            coords.add(i * dim).write(p.x);
            coords.add(i * dim + 1).write(p.y);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ffi::options::default_options;
    use crate::ffi::test_support::*;
    use crate::ffi::*;
    use crate::pool;
    use std::ptr::{null, null_mut};

    #[test]
    fn argument_errors_are_caught_before_any_access() {
        use QuadoptStatus as S;
        let (coords, quads) = patch(2);
        for dim in [0, 1, 4, u32::MAX] {
            assert_eq!(optimize_status(&coords[..18], dim, &quads, None, None), S::InvalidArgument);
            assert!(last_error().contains(&format!("dim is {dim}")), "{}", last_error());
        }
        let mut report = sentinel_report();
        let mut c = coords.clone();
        // SAFETY: the calls fail before touching the (deliberately wrong) lengths' memory.
        unsafe {
            // Counts beyond the uint32_t index range (with 64-bit size_t, the only way
            // vertex_count * dim or 4 * quad_count could overflow), checked for every array
            // before any is read.
            let s = quadopt_optimize(
                c.as_mut_ptr(),
                3,
                usize::MAX / 2,
                quads.as_ptr(),
                4,
                null(),
                null(),
                null_mut(),
            );
            assert_eq!(s, S::InvalidArgument);
            assert!(last_error().contains("vertex_count is"), "{}", last_error());
            let s = quadopt_optimize(
                c.as_mut_ptr(),
                2,
                u32::MAX as usize,
                quads.as_ptr(),
                usize::MAX / 2,
                null(),
                null(),
                null_mut(),
            );
            assert_eq!(s, S::InvalidArgument);
            assert!(last_error().contains("quad_count is"), "{}", last_error());
            assert_eq!(checked_count(usize::MAX / 2, 3, "n").unwrap_err().status, S::InvalidArgument);
            assert_eq!(check_bytes(usize::MAX / 8, 8, "n").unwrap_err().status, S::InvalidArgument);
            assert!(check_bytes(isize::MAX as usize / 8, 8, "n").is_ok());
            // An unreadable fixed mask is not read when the coordinates are bad.
            let s = quadopt_optimize(
                c.as_mut_ptr(),
                5,
                9,
                quads.as_ptr(),
                4,
                std::ptr::dangling::<u8>(),
                null(),
                null_mut(),
            );
            assert_eq!(s, S::InvalidArgument);
            // NULL arrays with nonzero counts.
            let s = quadopt_optimize(null_mut(), 2, 9, quads.as_ptr(), 4, null(), null(), &mut report);
            assert_eq!(s, S::NullPointer);
            assert!(last_error().contains("coords is NULL"), "{}", last_error());
            let s = quadopt_optimize(c.as_mut_ptr(), 2, 9, null(), 4, null(), null(), &mut report);
            assert_eq!(s, S::NullPointer);
            assert!(last_error().contains("quads is NULL"), "{}", last_error());
            // NULL arrays with zero counts are empty arrays.
            let s = quadopt_optimize(null_mut(), 2, 0, null(), 0, null(), null(), &mut report);
            assert_eq!(s, S::NoQuads);
            // A misaligned coordinate pointer.
            let s = quadopt_optimize(
                c.as_mut_ptr().cast::<u8>().add(1).cast(),
                2,
                8,
                quads.as_ptr(),
                4,
                null(),
                null(),
                &mut report,
            );
            assert_eq!(s, S::InvalidArgument);
            assert!(last_error().contains("aligned"), "{}", last_error());
            // A report that declares less than this version's struct.
            let mut small = sentinel_report();
            small.struct_size = 8;
            let s = quadopt_optimize(c.as_mut_ptr(), 2, 9, quads.as_ptr(), 4, null(), null(), &mut small);
            assert_eq!(s, S::InvalidArgument);
            assert!(last_error().contains("report->struct_size is 8"), "{}", last_error());
            let mut expected_small = sentinel_report();
            expected_small.struct_size = 8;
            assert_eq!(bytes_of(&small), bytes_of(&expected_small));
        }
        assert_eq!(bits(&c), bits(&coords));
        assert_eq!(bytes_of(&report), bytes_of(&sentinel_report()));
        let short = QuadoptOptions { struct_size: 16, ..default_options() };
        assert_eq!(optimize_status(&coords, 2, &quads, None, Some(&short)), S::InvalidArgument);
        assert!(last_error().contains("options->struct_size is 16"), "{}", last_error());
    }

    #[test]
    fn every_mesh_error_has_its_status_and_writes_nothing() {
        use QuadoptStatus as S;
        let (coords, quads) = patch(2);
        let mut q = quads.clone();
        q[6] = 9;
        assert_eq!(optimize_status(&coords, 2, &q, None, None), S::IndexOutOfRange);
        assert!(last_error().contains("quad 1 corner 2 refers to vertex 9"), "{}", last_error());
        let mut q = quads.clone();
        q[2] = 0;
        assert_eq!(optimize_status(&coords, 2, &q, None, None), S::RepeatedVertex);
        assert!(last_error().contains("quad 0 uses vertex 0"), "{}", last_error());
        assert_eq!(optimize_status(&coords, 2, &[], None, None), S::NoQuads);
        let mut c = coords.clone();
        c[2 * 5 + 1] = f64::INFINITY;
        assert_eq!(optimize_status(&c, 2, &quads, None, None), S::NonFiniteCoordinate);
        assert!(last_error().contains("vertex 5"), "{}", last_error());
        // Three quads on edge (1, 4): add two vertices and a quad [1, 4, 9, 10].
        let mut c = coords.clone();
        c.extend([1.5, 2.5, 0.5, 2.5]);
        let mut q = quads.clone();
        q.extend([1, 4, 9, 10]);
        assert_eq!(optimize_status(&c, 2, &q, None, None), S::NonManifold);
        assert!(last_error().contains("edge (1, 4)"), "{}", last_error());
        // A ring of four quads glued with a half twist.
        let mut c = Vec::new();
        for i in 0..4 {
            c.extend([i as f64, 0.0, i as f64, 1.0]);
        }
        let moebius = [0, 2, 3, 1, 2, 4, 5, 3, 4, 6, 7, 5, 6, 1, 0, 7];
        assert_eq!(optimize_status(&c, 2, &moebius, None, None), S::NonOrientable);
        assert!(last_error().contains("quad"), "{}", last_error());
    }

    /// A periodic 6 x 6 grid (every quad wraps around, every vertex is interior) has no
    /// orientation that makes its quads valid: every entry point refuses it, with one message.
    #[test]
    fn a_closed_mesh_is_refused_by_every_entry_point() {
        use QuadoptStatus as S;
        let n = 6u32;
        let id = |i: u32, j: u32| (j % n) * n + i % n;
        let coords: Vec<f64> = (0..n * n).flat_map(|v| [f64::from(v % n), f64::from(v / n)]).collect();
        let quads: Vec<u32> = (0..n * n)
            .flat_map(|c| {
                [id(c % n, c / n), id(c % n + 1, c / n), id(c % n + 1, c / n + 1), id(c % n, c / n + 1)]
            })
            .collect();
        let message = "the mesh is closed (it has no boundary edge): a closed surface cannot lie flat in a plane without folds";
        assert_eq!(optimize_status(&coords, 2, &quads, None, None), S::ClosedMesh);
        assert_eq!(last_error(), format!("quadopt_optimize: {message}"));
        let mut stats = QuadoptQuality { min: 0.0, avg: 0.0, max: 0.0, inverted: 0 };
        // SAFETY: every pointer refers to a live buffer of the stated length.
        let s =
            unsafe { quadopt_quality(coords.as_ptr(), 2, 36, quads.as_ptr(), 36, &mut stats, null_mut(), 0) };
        assert_eq!((s, last_error()), (S::ClosedMesh, format!("quadopt_quality: {message}")));
        let mut handle = null_mut();
        // SAFETY: as above.
        let s = unsafe {
            quadopt_optimizer_create(coords.as_ptr(), 2, 36, quads.as_ptr(), 36, null(), &mut handle)
        };
        let created = (s, last_error(), handle.is_null());
        assert_eq!(created, (S::ClosedMesh, format!("quadopt_optimizer_create: {message}"), true));
        // One quad less leaves a hole, a boundary: then it is an ordinary mesh.
        assert_eq!(optimize_status(&coords, 2, &quads[..quads.len() - 4], None, None), S::Ok);
    }

    #[test]
    fn panics_are_caught_at_the_boundary() {
        let status = boundary("quadopt_test", || panic!("boom {}", 42));
        assert_eq!(status, QuadoptStatus::Panic);
        assert_eq!(last_error(), "quadopt_test: internal error (panic: boom 42); please report this bug");
        assert_eq!(boundary_or(5, || panic!("static")), 5);
    }

    #[test]
    fn a_caught_panic_prints_nothing_and_others_still_reach_the_previous_hook() {
        const NAME: &str =
            "ffi::boundary::tests::a_caught_panic_prints_nothing_and_others_still_reach_the_previous_hook";
        if !is_child(NAME) {
            for backtrace in ["0", "1", "full"] {
                let stderr = run_in_child(NAME, &[("RUST_BACKTRACE", backtrace)]);
                // Only the panic outside the library reached the default hook.
                assert!(stderr.contains("panicked") && stderr.contains("outside the library"), "{stderr}");
                assert!(!stderr.contains("boom"), "RUST_BACKTRACE={backtrace}:\n{stderr}");
            }
            return;
        }
        // On the calling thread, in both kinds of boundary.
        assert_eq!(boundary("quadopt_test", || panic!("boom 1")), QuadoptStatus::Panic);
        assert_eq!(boundary_or(7, || panic!("boom 2")), 7);
        // On a worker thread, resumed on the calling thread.
        let status = boundary("quadopt_test", || {
            let _ = pool::run_with_progress(|_| -> () { panic!("boom 3") }, |_: ()| true);
            Ok(())
        });
        assert_eq!(status, QuadoptStatus::Panic);
        assert!(last_error().contains("boom 3"), "{}", last_error());
        // The pool survives a panicking job.
        assert_eq!(optimize_patch(&fixed_boundary_options()).0, QuadoptStatus::Ok);
        assert!(panic::catch_unwind(|| panic!("outside the library")).is_err());
    }
}
