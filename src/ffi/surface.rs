//! Meshes on curved surfaces in 3D (issue 33): [`quadopt_optimize_surface`], and the surface
//! run that `quadopt_optimize` also takes for a `dim` 3 mesh that is not planar (the library's
//! one planarity rule, `quadopt_is_planar`). The run is the
//! crate's [`SurfaceOptimizer`] on the library's worker threads, with the C progress callback
//! on the calling thread, as in the plane (`run.rs`).

use crate::error::Error;
use crate::pool;
use crate::surface::{DEFAULT_FEATURE_ANGLE_DEG, SurfaceMesh, SurfaceOptimizer};
use std::ptr::null;

use super::boundary::{boundary, read_surface_mesh, write_points_3d};
use super::options::{QuadoptOptions, convert_options, read_options};
use super::report::{QuadoptReport, report_size, surface_report_of, write_report};
use super::run::{check_memory_for, with_progress};
use super::status::{FfiError, QuadoptStatus};

/// Peak bytes of building a surface optimizer and running it, per vertex or face (whichever
/// is more) and fixed. Measured with a counting allocator (a scratch program, as
/// tests/memory.rs does for the planar run): about 1,470 to 1,690 bytes per element on smooth
/// surfaces (jittered and tangled cylinder grids of 16 to 90,601 vertices, a cube sphere,
/// every effort) and 850 on a strip; feature curves add to it (3,890 on a grid whose every
/// vertical line is a marked curve), so the bound covers that with a margin. A surface where
/// yet more edges are features can need more: like the planar checks, this one guards against
/// a mesh far too large for the memory, it is not exact.
const SURFACE_BYTES_PER_ELEMENT: u128 = 4096;
const SURFACE_BYTES_FIXED: u128 = 256 << 10;

/// Upper estimate of the bytes building a [`SurfaceOptimizer`] for `mesh` and one run allocate.
fn surface_bytes(mesh: &SurfaceMesh) -> u128 {
    SURFACE_BYTES_PER_ELEMENT * mesh.points().len().max(mesh.faces().len()) as u128 + SURFACE_BYTES_FIXED
}

/// Optimizes `mesh` on its surface (the optimizer built on a worker from its positions, with
/// `marked` feature edges and the options' feature angle), with the C progress callback on the
/// calling thread, and returns the report as the C struct. Cancellation is an error here, so
/// nothing is written.
pub(super) fn run_surface(
    mesh: &mut SurfaceMesh,
    marked: &[[u32; 2]],
    o: &QuadoptOptions,
) -> Result<QuadoptReport, FfiError> {
    let options = convert_options(o)?;
    let (report, last) = with_progress(o, |forward| {
        // Checked on a worker, once the pool (its stacks, its allocator arenas) exists.
        check_memory_for(surface_bytes(mesh), "the surface optimizer's working memory")?;
        let optimizer = SurfaceOptimizer::new(mesh, options.feature_angle_deg, marked)?;
        optimizer.run(mesh, &options, Some(forward))
    })?;
    if report.cancelled {
        let at = last.map_or(String::new(), |p| format!(" at iteration {}", p.iteration));
        return Err(FfiError::new(
            QuadoptStatus::Cancelled,
            format!("cancelled by the progress callback{at}; nothing was written"),
        ));
    }
    Ok(surface_report_of(&report, options.sweep_cap(), mesh.reoriented().len()))
}

/// Reads the surface mesh, runs it and writes the coordinates and the report: the body of
/// [`quadopt_optimize_surface`], and of `quadopt_optimize` for a curved `dim` 3 mesh (`names`:
/// the caller's names of the face array and its count, for the messages).
///
/// # Safety
/// As [`quadopt_optimize_surface`].
#[allow(clippy::too_many_arguments)]
pub(super) unsafe fn optimize_surface(
    coords: *mut f64,
    vertex_count: usize,
    faces: *const u32,
    face_count: usize,
    fixed: *const u8,
    feature_edges: *const u32,
    feature_edge_count: usize,
    options: *const QuadoptOptions,
    report: *mut QuadoptReport,
    names: (&str, &str),
) -> Result<(), FfiError> {
    // SAFETY: forwarded from this function's contract.
    let report_bytes = unsafe { report_size(report) }?;
    // SAFETY: forwarded from this function's contract.
    let o = unsafe { read_options(options) }?;
    convert_options(&o)?;
    // SAFETY: forwarded from this function's contract.
    let (mut mesh, marked) = unsafe {
        read_surface_mesh(
            coords,
            vertex_count,
            faces,
            face_count,
            fixed,
            feature_edges,
            feature_edge_count,
            names,
        )
    }?;
    let r = run_surface(&mut mesh, &marked, &o)?;
    // SAFETY: `coords` held `vertex_count * 3` doubles (checked by read_surface_mesh), and the
    // report size was checked against the caller's declaration.
    unsafe {
        write_points_3d(coords, mesh.points());
        if let Some(bytes) = report_bytes {
            write_report(report, r, bytes);
        }
    }
    Ok(())
}

/// Optimizes a mesh on a curved surface in 3D in place: moves the vertices on the input
/// surface to raise the faces' scaled Jacobians, keeping connectivity, fixed vertices and the
/// feature curves. On any error, cancellation included, neither `coords` nor `report` is
/// written.
///
/// The surface is the input mesh itself (its faces, frozen for the run). Feature curves are the
/// boundary, the edges whose two faces' normals differ by more than
/// `options->feature_angle_deg`, and the edges marked in `feature_edges`; they cut the surface
/// into smooth patches. A vertex on no feature curve moves within its patch, a vertex on a
/// curve along the curve's original polyline (unless `options->boundary` is
/// `QUADOPT_BOUNDARY_FIXED`, which keeps every curve's vertices in place), and feature corners
/// (where curves meet or turn by more than the feature angle) and fixed vertices never move:
/// they keep their coordinates bit for bit. The result is never worse than the input by the
/// signed measure. A closed surface (a sphere, a torus) is accepted. Options as in
/// `quadopt_optimize()` (the effort preset, the method, `max_iterations`, `max_min`, the
/// progress callback); the report's surface fields say how far the output is from the input
/// surface. A flat mesh is a surface too: it is optimized by the same surface method (use
/// `quadopt_optimize()` for the planar optimizer).
///
/// - `coords`: `3 * vertex_count` doubles (x, y, z per vertex), read and written; NULL only if
///   `vertex_count` is 0.
/// - `faces`: `4 * face_count` vertex indices, a quad's four or a triangle's three followed by
///   `QUADOPT_NO_VERTEX`; faces may be given in either orientation (made consistent per
///   connected part). Errors as in `quadopt_optimize()`, except that a closed mesh is accepted.
/// - `fixed`: NULL (no fixed vertices) or `vertex_count` bytes, nonzero = the vertex never moves.
/// - `feature_edges`: `2 * feature_edge_count` vertex indices, two per marked edge (in either
///   order); NULL only if `feature_edge_count` is 0. A vertex index out of range is
///   `QUADOPT_STATUS_INDEX_OUT_OF_RANGE`, a pair that is not an edge of the mesh
///   `QUADOPT_STATUS_INVALID_ARGUMENT`; the message names the pair.
/// - `options`: NULL for the defaults.
/// - `report`: NULL, or a report whose `struct_size` is set (see `quadopt_report_init()`); its
///   `surface` is 1.
///
/// # Safety
/// Every non-NULL pointer must point to (aligned) memory of the size described above, valid
/// for the duration of the call; the buffers must not overlap.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn quadopt_optimize_surface(
    coords: *mut f64,
    vertex_count: usize,
    faces: *const u32,
    face_count: usize,
    fixed: *const u8,
    feature_edges: *const u32,
    feature_edge_count: usize,
    options: *const QuadoptOptions,
    report: *mut QuadoptReport,
) -> QuadoptStatus {
    boundary("quadopt_optimize_surface", || {
        // SAFETY: forwarded from this function's contract.
        unsafe {
            optimize_surface(
                coords,
                vertex_count,
                faces,
                face_count,
                fixed,
                feature_edges,
                feature_edge_count,
                options,
                report,
                ("faces", "face_count"),
            )
        }
    })
}

/// The signed scaled Jacobian of every face of a mesh on a curved surface, as the optimizer
/// measures its input (each corner against the normal of the mesh's own surface there, with
/// the default feature angle and no marked edge): `quadopt_quality()` for a `dim` 3 mesh that
/// is not planar. Computed on the library's worker threads.
///
/// # Safety
/// As `read_mesh` with `dim` 3.
pub(super) unsafe fn surface_quality_values(
    coords: *const f64,
    vertex_count: usize,
    quads: *const u32,
    quad_count: usize,
) -> Result<Vec<f64>, FfiError> {
    // SAFETY: forwarded from this function's contract.
    let (mesh, _) = unsafe {
        read_surface_mesh(coords, vertex_count, quads, quad_count, null(), null(), 0, ("quads", "quad_count"))
    }?;
    let job = |_: &mut dyn FnMut(()) -> bool| {
        check_memory_for(surface_bytes(&mesh), "the surface measure's working memory")?;
        let optimizer = SurfaceOptimizer::new(&mesh, DEFAULT_FEATURE_ANGLE_DEG, &[])?;
        Ok::<_, Error>(optimizer.input_values())
    };
    let values = pool::run_with_progress(job, |()| true)
        .map_err(|pool::NoThreads(why)| FfiError::new(QuadoptStatus::OutOfMemory, why))??;
    Ok(values)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ffi::options::default_options;
    use crate::ffi::report::{REPORT_V1_SIZE, REPORT_V2_SIZE, REPORT_V3_SIZE};
    use crate::ffi::test_support::*;
    use crate::ffi::*;
    use std::f64::consts::FRAC_PI_8;
    use std::ffi::c_void;
    use std::ptr::{null, null_mut};

    /// A 4 x 4 grid of quads on a quarter of the cylinder of radius 1 around the z axis
    /// (vertex `5 j + i` at angle `i pi / 8`, height `0.4 j`), whose centre vertex 12 has been
    /// pushed along the cylinder (to angle `2.6 pi / 8`, height 0.8): 25 vertices, 16 quads.
    fn quarter_cylinder() -> (Vec<f64>, Vec<u32>) {
        let mut coords = Vec::new();
        for j in 0..5 {
            for i in 0..5 {
                let a = f64::from(i) * FRAC_PI_8;
                coords.extend([a.cos(), a.sin(), 0.4 * f64::from(j)]);
            }
        }
        let a = 2.6 * FRAC_PI_8;
        coords[36..39].copy_from_slice(&[a.cos(), a.sin(), 0.8]);
        let faces = (0..16u32)
            .flat_map(|k| {
                let v = (k / 4) * 5 + k % 4;
                [v, v + 1, v + 6, v + 5]
            })
            .collect();
        (coords, faces)
    }

    /// The distance of (x, y, z) from the cylinder's axis, minus the radius.
    fn off_cylinder(c: &[f64]) -> f64 {
        c[0].hypot(c[1]) - 1.0
    }

    /// How far the faceted input surface is from the analytic cylinder at most: the sagitta
    /// of the widest face's angular span (the faces around the pushed vertex are wider than
    /// the grid's pi / 8).
    fn chordal_tolerance(coords: &[f64], faces: &[u32]) -> f64 {
        let angle = |v: u32| coords[3 * v as usize + 1].atan2(coords[3 * v as usize]);
        let span = |f: &[u32]| {
            let a = f.iter().map(|&v| angle(v));
            a.clone().fold(f64::MIN, f64::max) - a.fold(f64::MAX, f64::min)
        };
        faces.chunks(4).map(|f| 1.0 - (span(f) / 2.0).cos()).fold(0.0, f64::max)
    }

    unsafe fn surface_call(
        coords: &mut [f64],
        faces: &[u32],
        fixed: Option<&[u8]>,
        edges: &[u32],
        options: Option<&QuadoptOptions>,
        report: &mut QuadoptReport,
    ) -> QuadoptStatus {
        // SAFETY: the slices are live buffers of the stated lengths.
        unsafe {
            quadopt_optimize_surface(
                coords.as_mut_ptr(),
                coords.len() / 3,
                faces.as_ptr(),
                faces.len() / 4,
                fixed.map_or(null(), <[u8]>::as_ptr),
                if edges.is_empty() { null() } else { edges.as_ptr() },
                edges.len() / 2,
                options.map_or(null(), |o| o as *const _),
                report,
            )
        }
    }

    #[test]
    fn a_curved_mesh_improves_and_stays_on_its_surface() {
        let (before, faces) = quarter_cylinder();
        let mut coords = before.clone();
        // The bottom row is fixed.
        let fixed: Vec<u8> = (0..25).map(|v| u8::from(v < 5)).collect();
        let mut r = quadopt_report_init();
        // SAFETY: live buffers.
        let s = unsafe { surface_call(&mut coords, &faces, Some(&fixed), &[], None, &mut r) };
        assert_eq!(s, QuadoptStatus::Ok, "{}", last_error());
        assert_eq!(r.struct_size as usize, size_of::<QuadoptReport>());
        assert_eq!(r.surface, 1);
        assert!(r.output.min > r.input.min + 0.05, "{:?} -> {:?}", r.input, r.output);
        assert!(
            r.output_verdict.min > r.input_verdict.min,
            "{:?} -> {:?}",
            r.input_verdict,
            r.output_verdict
        );
        assert_eq!((r.output.inverted, r.tangled_quads), (0, 0));
        assert!(r.max_distance < 1e-9 && r.max_feature_distance < 1e-9, "{r:?}");
        assert!(r.max_distance_relative < 1e-8);
        assert!(r.patches >= 1 && r.feature_curves >= 1 && r.corners >= 4, "{r:?}");
        assert!(r.movable >= 9 && r.iterations >= 1);
        assert!(r.hausdorff.is_nan() && r.initial_energy.is_nan());
        assert_eq!((r.input_quads.count, r.output_quads.count, r.output_triangles.count), (16, 16, 0));
        let tolerance = chordal_tolerance(&before, &faces);
        assert!(tolerance > 0.04 && tolerance < 0.05, "{tolerance}");
        for v in 0..25 {
            let c = &coords[3 * v..3 * v + 3];
            assert!(
                off_cylinder(c) <= 1e-12 && -off_cylinder(c) <= tolerance + 1e-12,
                "vertex {v} left the cylinder: {c:?}"
            );
            if v < 5 {
                assert_eq!(bits(c), bits(&before[3 * v..3 * v + 3]), "fixed vertex {v} moved");
            }
        }
        // The pushed vertex went back most of the way towards angle 2 pi / 8.
        let angle = coords[37].atan2(coords[36]);
        assert!((angle - 2.0 * FRAC_PI_8).abs() < 0.3 * FRAC_PI_8, "{angle}");
        // quadopt_optimize with dim 3 takes the same path, with the same result.
        let mut again = before.clone();
        let mut r2 = quadopt_report_init();
        // SAFETY: live buffers.
        let s = unsafe {
            quadopt_optimize(again.as_mut_ptr(), 3, 25, faces.as_ptr(), 16, fixed.as_ptr(), null(), &mut r2)
        };
        assert_eq!(s, QuadoptStatus::Ok, "{}", last_error());
        assert_eq!(bits(&again), bits(&coords));
        assert_eq!((r2.surface, r2.output, r2.max_distance), (1, r.output, r.max_distance));
    }

    #[test]
    fn a_marked_feature_edge_keeps_its_vertices_on_its_line() {
        let (before, faces) = quarter_cylinder();
        // The vertical line i = 1 (vertices 1, 6, 11, 16, 21), marked as a feature curve.
        let edges = [1, 6, 6, 11, 16, 11, 16, 21];
        let mut coords = before.clone();
        let mut r = quadopt_report_init();
        // SAFETY: live buffers.
        let s = unsafe { surface_call(&mut coords, &faces, None, &edges, None, &mut r) };
        assert_eq!(s, QuadoptStatus::Ok, "{}", last_error());
        let mut plain = before.clone();
        let mut r0 = quadopt_report_init();
        // SAFETY: live buffers.
        let s = unsafe { surface_call(&mut plain, &faces, None, &[], None, &mut r0) };
        assert_eq!(s, QuadoptStatus::Ok, "{}", last_error());
        assert!(r.feature_curves > r0.feature_curves || r.patches > r0.patches, "{r:?}\n{r0:?}");
        assert_eq!(r.patches, 2, "the marked line cuts the quarter cylinder in two");
        for v in [6, 11, 16] {
            // Along the line: x and y stay those of angle pi / 8.
            let (x, y) = (coords[3 * v], coords[3 * v + 1]);
            assert!(
                (x - FRAC_PI_8.cos()).abs() < 1e-12 && (y - FRAC_PI_8.sin()).abs() < 1e-12,
                "{v}: {x} {y}"
            );
        }
        assert!(r.output.min > r.input.min);
    }

    #[test]
    fn constant_z_keeps_the_planar_path_bit_for_bit() {
        // The patch of the planar tests with z = 2.5 (and with z = 0.0 / -0.0 mixed, which are
        // equal): the result is dim 2's, bit for bit, and z is not written.
        let (xy, quads) = patch(2);
        let o = fixed_boundary_options();
        let mut planar = xy.clone();
        let mut r2 = quadopt_report_init();
        // SAFETY: live buffers.
        let s =
            unsafe { quadopt_optimize(planar.as_mut_ptr(), 2, 9, quads.as_ptr(), 4, null(), &o, &mut r2) };
        assert_eq!(s, QuadoptStatus::Ok);
        assert_eq!(r2.surface, 0);
        for zs in [[2.5, 2.5], [0.0, -0.0]] {
            let mut xyz: Vec<f64> = (0..9).flat_map(|v| [xy[2 * v], xy[2 * v + 1], zs[v % 2]]).collect();
            let z_before: Vec<u64> = (0..9).map(|v| xyz[3 * v + 2].to_bits()).collect();
            let mut r3 = quadopt_report_init();
            // SAFETY: live buffers.
            let s =
                unsafe { quadopt_optimize(xyz.as_mut_ptr(), 3, 9, quads.as_ptr(), 4, null(), &o, &mut r3) };
            assert_eq!(s, QuadoptStatus::Ok, "{}", last_error());
            for v in 0..9 {
                assert_eq!(bits(&xyz[3 * v..3 * v + 2]), bits(&planar[2 * v..2 * v + 2]), "vertex {v}");
                assert_eq!(xyz[3 * v + 2].to_bits(), z_before[v], "z of vertex {v} written");
            }
            r3.seconds = r2.seconds;
            assert_eq!(bytes_of(&r3), bytes_of(&r2), "the report differs from dim 2's");
        }
        // In a planar report the verdict fields repeat input and output.
        assert_eq!((r2.input_verdict, r2.output_verdict), (r2.input, r2.output));
        assert_eq!((r2.max_distance, r2.feature_curves, r2.patches), (0.0, 0, 0));
        assert_eq!(r2.max_feature_distance, r2.max_boundary_deviation);
    }

    #[test]
    fn bad_feature_edges_are_named_and_write_nothing() {
        use QuadoptStatus as S;
        let (before, faces) = quarter_cylinder();
        let cases: [(&[u32], S, &str); 4] = [
            (
                &[1, 6, 0, 6],
                S::InvalidArgument,
                "feature edge 1, vertices (0, 6), is not an edge of the mesh",
            ),
            (&[3, 3], S::InvalidArgument, "feature edge 0, vertices (3, 3), is not an edge"),
            (&[0, 25], S::IndexOutOfRange, "feature edge 0, vertices (0, 25), refers to vertex 25"),
            (&[u32::MAX, 1], S::IndexOutOfRange, "refers to vertex 4294967295"),
        ];
        for (edges, status, message) in cases {
            let mut c = before.clone();
            let mut report = sentinel_report();
            // SAFETY: live buffers.
            let s = unsafe { surface_call(&mut c, &faces, None, edges, None, &mut report) };
            assert_eq!(s, status, "{edges:?}: {}", last_error());
            assert!(last_error().starts_with("quadopt_optimize_surface: "), "{}", last_error());
            assert!(last_error().contains(message), "{}", last_error());
            assert_eq!(bits(&c), bits(&before));
            assert_eq!(bytes_of(&report), bytes_of(&sentinel_report()));
        }
    }

    #[test]
    fn null_arrays_with_counts_are_refused_before_any_access() {
        use QuadoptStatus as S;
        let (mut c, faces) = quarter_cylinder();
        let edges = [1u32, 6];
        let mut report = sentinel_report();
        // SAFETY: the calls fail on the checks, before reading any array.
        unsafe {
            let s = quadopt_optimize_surface(
                null_mut(),
                25,
                faces.as_ptr(),
                16,
                null(),
                null(),
                0,
                null(),
                &mut report,
            );
            assert_eq!(s, S::NullPointer);
            assert!(last_error().contains("coords is NULL"), "{}", last_error());
            let s = quadopt_optimize_surface(
                c.as_mut_ptr(),
                25,
                null(),
                16,
                null(),
                null(),
                0,
                null(),
                &mut report,
            );
            assert_eq!(s, S::NullPointer);
            assert!(last_error().contains("faces is NULL"), "{}", last_error());
            let s = quadopt_optimize_surface(
                c.as_mut_ptr(),
                25,
                faces.as_ptr(),
                16,
                null(),
                null(),
                3,
                null(),
                &mut report,
            );
            assert_eq!(s, S::NullPointer);
            assert!(last_error().contains("feature_edges is NULL (length 6)"), "{}", last_error());
            // Counts whose arrays overflow: refused before any array is read (the fixed mask
            // and the edges are dangling).
            let s = quadopt_optimize_surface(
                c.as_mut_ptr(),
                25,
                faces.as_ptr(),
                16,
                std::ptr::dangling(),
                edges.as_ptr(),
                usize::MAX / 2 + 1,
                null(),
                &mut report,
            );
            assert_eq!(s, S::InvalidArgument);
            assert!(last_error().contains("feature_edge_count * 2"), "{}", last_error());
            let s = quadopt_optimize_surface(
                c.as_mut_ptr(),
                usize::MAX / 2,
                faces.as_ptr(),
                16,
                std::ptr::dangling(),
                null(),
                0,
                null(),
                &mut report,
            );
            assert_eq!(s, S::InvalidArgument);
            assert!(last_error().contains("vertex_count is"), "{}", last_error());
            // No faces at all.
            let s = quadopt_optimize_surface(
                c.as_mut_ptr(),
                25,
                null(),
                0,
                null(),
                null(),
                0,
                null(),
                &mut report,
            );
            assert_eq!(s, S::NoQuads);
            // A misaligned edge array.
            let s = quadopt_optimize_surface(
                c.as_mut_ptr(),
                25,
                faces.as_ptr(),
                16,
                null(),
                edges.as_ptr().cast::<u8>().add(1).cast(),
                1,
                null(),
                &mut report,
            );
            assert_eq!(s, S::InvalidArgument);
            assert!(last_error().contains("feature_edges is not aligned"), "{}", last_error());
        }
        assert_eq!(bits(&c), bits(&quarter_cylinder().0));
        assert_eq!(bytes_of(&report), bytes_of(&sentinel_report()));
    }

    #[test]
    fn older_report_sizes_are_not_written_past_by_a_surface_run() {
        let (before, faces) = quarter_cylinder();
        for size in [REPORT_V1_SIZE, REPORT_V2_SIZE, REPORT_V3_SIZE] {
            let mut report = QuadoptReport { struct_size: size as u32, ..sentinel_report() };
            report.surface = 0xA5A5;
            report.input_quads.count = 0xDEAD;
            report.max_distance = -3.0;
            let untouched = bytes_of(&report)[size..].to_vec();
            let mut c = before.clone();
            // SAFETY: live buffers; the report holds more than its declared bytes.
            let s = unsafe { surface_call(&mut c, &faces, None, &[], None, &mut report) };
            assert_eq!(s, QuadoptStatus::Ok, "{}", last_error());
            assert_eq!(report.struct_size as usize, size, "bytes filled");
            assert!(report.output.min > report.input.min);
            assert_eq!(
                bytes_of(&report)[size..],
                untouched[..],
                "bytes beyond struct_size {size} were written"
            );
        }
    }

    #[test]
    fn cancel_writes_nothing_and_a_closed_surface_is_accepted() {
        unsafe extern "C" fn stop(_: *const QuadoptProgress, calls: *mut c_void) -> bool {
            // SAFETY: calls is the counter below.
            unsafe { *calls.cast::<usize>() += 1 };
            false
        }
        let (before, faces) = quarter_cylinder();
        let mut calls = 0usize;
        let o = QuadoptOptions {
            progress: Some(stop),
            progress_user_data: (&raw mut calls).cast(),
            ..default_options()
        };
        let mut c = before.clone();
        let mut report = sentinel_report();
        // SAFETY: live buffers.
        let s = unsafe { surface_call(&mut c, &faces, None, &[], Some(&o), &mut report) };
        assert_eq!(s, QuadoptStatus::Cancelled, "{}", last_error());
        assert!(calls >= 1 && last_error().contains("nothing was written"), "{}", last_error());
        assert_eq!(bits(&c), bits(&before));
        assert_eq!(bytes_of(&report), bytes_of(&sentinel_report()));
        // A cube of six quads, one corner pushed outward: closed, accepted on a surface.
        let mut cube: Vec<f64> =
            (0..8).flat_map(|v| [f64::from(v & 1), f64::from((v >> 1) & 1), f64::from(v >> 2)]).collect();
        cube[21..24].copy_from_slice(&[1.2, 1.2, 1.2]);
        let sides = [0, 2, 3, 1, 4, 5, 7, 6, 0, 1, 5, 4, 2, 6, 7, 3, 0, 4, 6, 2, 1, 3, 7, 5];
        let mut r = quadopt_report_init();
        // SAFETY: live buffers.
        let s = unsafe { surface_call(&mut cube, &sides, None, &[], None, &mut r) };
        assert_eq!(s, QuadoptStatus::Ok, "{}", last_error());
        assert_eq!(r.surface, 1);
    }

    #[test]
    fn quality_of_a_curved_mesh_is_the_surface_runs_input_measure() {
        let (coords, faces) = quarter_cylinder();
        let mut q = QuadoptQuality::default();
        let mut per = [f64::NAN; 17];
        // SAFETY: live buffers; per has room for 17 >= 16 values.
        let s = unsafe {
            quadopt_quality(coords.as_ptr(), 3, 25, faces.as_ptr(), 16, &mut q, per.as_mut_ptr(), 17)
        };
        assert_eq!(s, QuadoptStatus::Ok, "{}", last_error());
        assert!(per[16].is_nan(), "beyond quad_count was written");
        let mut c = coords.clone();
        let mut r = quadopt_report_init();
        // SAFETY: live buffers.
        let s = unsafe { surface_call(&mut c, &faces, None, &[], None, &mut r) };
        assert_eq!(s, QuadoptStatus::Ok, "{}", last_error());
        assert_eq!(q, r.input);
        assert_eq!(q.min, per[..16].iter().copied().fold(f64::INFINITY, f64::min));
        // The planar measure of the same x and y (z dropped) is another thing.
        let flat: Vec<f64> = coords.chunks(3).flat_map(|p| [p[0], p[1], 7.0]).collect();
        let mut qf = QuadoptQuality::default();
        // SAFETY: live buffers.
        let s = unsafe { quadopt_quality(flat.as_ptr(), 3, 25, faces.as_ptr(), 16, &mut qf, null_mut(), 0) };
        assert_eq!(s, QuadoptStatus::Ok, "{}", last_error());
        assert_ne!(qf, q);
        // Errors name the caller's arrays as quadopt_quality calls them.
        // SAFETY: fails on the checks.
        let s = unsafe { quadopt_quality(coords.as_ptr(), 3, 25, null(), 16, &mut q, null_mut(), 0) };
        assert_eq!(s, QuadoptStatus::NullPointer);
        assert!(last_error().contains("quads is NULL"), "{}", last_error());
    }

    #[test]
    fn a_handle_refuses_a_curved_mesh() {
        let (coords, faces) = quarter_cylinder();
        let mut handle = 0x10 as *mut QuadoptOptimizer;
        // SAFETY: live buffers; the call fails and leaves `handle` alone.
        let s = unsafe {
            quadopt_optimizer_create(coords.as_ptr(), 3, 25, faces.as_ptr(), 16, null(), &mut handle)
        };
        assert_eq!((s, handle as usize), (QuadoptStatus::NotPlanar, 0x10));
        assert!(last_error().contains("quadopt_optimize_surface()"), "{}", last_error());
        // A handle made from planar coordinates refuses curved ones too, writing nothing.
        let flat: Vec<f64> = (0..25).flat_map(|v| [f64::from(v % 5), f64::from(v / 5), 0.0]).collect();
        let mut handle = null_mut();
        // SAFETY: live buffers; the handle is freed once.
        unsafe {
            let s = quadopt_optimizer_create(flat.as_ptr(), 3, 25, faces.as_ptr(), 16, null(), &mut handle);
            assert_eq!(s, QuadoptStatus::Ok, "{}", last_error());
            let mut c = coords.clone();
            let s = quadopt_optimizer_optimize(handle, c.as_mut_ptr(), 3, 25, null(), null_mut());
            assert_eq!(s, QuadoptStatus::NotPlanar);
            assert_eq!(bits(&c), bits(&coords));
            quadopt_optimizer_free(handle);
        }
    }
}
