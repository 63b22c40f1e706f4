//! A run: the memory the topology and the optimizer need (checked before they start), one run
//! on the library's worker threads with the C progress callback on the calling thread, and the
//! one-shot entry points [`quadopt_optimize`] and [`quadopt_quality`].

use crate::alloc::try_with_capacity;
use crate::error::Error;
use crate::mesh::Mesh;
use crate::pool;
use crate::quality::QualityStats;
use crate::quiet_threads;
use crate::smooth::{Optimizer, Progress, Report};
use glam::DVec2;
use std::mem::size_of;

use super::boundary::{
    Plane, boundary, check_bytes, plane_of, read_mesh, read_mesh_in, require_non_null, write_points,
    write_points_in,
};
use super::options::{QuadoptOptions, QuadoptProgress, convert_options, read_options};
use super::report::{QuadoptQuality, QuadoptReport, quality_of, report_of, report_size, write_report};
use super::status::{FfiError, QuadoptStatus};
use super::surface::{optimize_surface, surface_quality_values};
use std::ptr::null;

/// Peak bytes of building the optimizer, per vertex or quad (whichever is more) and fixed:
/// measured by tests/memory.rs at up to about 56 per element, 97 for a mesh large enough
/// to be renumbered (its copy in the internal order is alive while its topology is built),
/// with room to spare.
const TOPOLOGY_BYTES_PER_ELEMENT: u128 = 120;
const TOPOLOGY_BYTES_FIXED: u128 = 64 << 10;
/// Peak bytes of a run beyond the mesh and its topology, per vertex or quad, per boundary
/// edge and fixed: measured at up to about 135 per element plus 40 per boundary edge on
/// grids and strips, and 250 per vertex on a 2000-quad fan (the max-min stage's star), with
/// any method and boundary mode.
const RUN_BYTES_PER_ELEMENT: u128 = 220;
const RUN_BYTES_PER_BOUNDARY_EDGE: u128 = 64;
const RUN_BYTES_FIXED: u128 = 64 << 10;

/// Upper estimate of the bytes `Optimizer::new(mesh)` allocates at its peak.
#[doc(hidden)]
pub fn topology_bytes(mesh: &Mesh) -> u128 {
    TOPOLOGY_BYTES_PER_ELEMENT * mesh.points().len().max(mesh.quads().len()) as u128 + TOPOLOGY_BYTES_FIXED
}

/// Upper estimate of the bytes one `Optimizer::run` on `mesh` allocates at its peak.
#[doc(hidden)]
pub fn run_bytes(mesh: &Mesh) -> u128 {
    let elements = mesh.points().len().max(mesh.quads().len()) as u128;
    RUN_BYTES_PER_ELEMENT * elements
        + RUN_BYTES_PER_BOUNDARY_EDGE * mesh.boundary_edge_count() as u128
        + RUN_BYTES_FIXED
}

/// Checks that `bytes` can be allocated now (in one piece, so also in the many pieces the
/// work will use), and frees them again: an address-space or commit limit too tight for the
/// work fails here, as an error, rather than in an allocation that aborts. The probe is
/// never written, so it costs address space for a moment, not memory.
pub(super) fn check_memory_for(bytes: u128, what: &'static str) -> Result<(), Error> {
    let fail = || Error::OutOfMemory { what, bytes };
    let probe =
        try_with_capacity::<u8>(usize::try_from(bytes).map_err(|_| fail())?, what).map_err(|_| fail())?;
    drop(probe);
    Ok(())
}

/// Runs `job` on the library's worker threads with `o`'s C progress callback called on the
/// calling thread: `job` gets the Rust callback to hand to the optimizer. Returns `job`'s
/// result and the last progress the C callback saw (for a cancellation's message).
pub(super) fn with_progress<R: Send>(
    o: &QuadoptOptions,
    job: impl FnOnce(&mut dyn FnMut(&Progress) -> bool) -> Result<R, Error> + Send,
) -> Result<(R, Option<QuadoptProgress>), FfiError> {
    let (callback, user_data) = (o.progress, o.progress_user_data);
    let mut last = None;
    let on_progress = |cp: QuadoptProgress| -> bool {
        let Some(f) = callback else { return true };
        last = Some(cp);
        // A panic of the caller's own Rust code (if any) is not ours to silence.
        let _outside = quiet_threads::enter(false);
        // SAFETY: the caller guarantees that a non-NULL `progress` is a valid function of this
        // signature; `cp` lives for the duration of the call.
        unsafe { f(&cp, user_data) }
    };
    let has_callback = callback.is_some();
    let outer = |ask: &mut dyn FnMut(QuadoptProgress) -> bool| {
        let mut forward = |p: &Progress| {
            !has_callback
                || ask(QuadoptProgress {
                    iteration: p.iteration,
                    max_iterations: p.max_iterations,
                    pass: p.pass,
                    passes: p.passes,
                    energy: p.energy,
                    energy_change: p.energy_change,
                })
        };
        // On a worker thread the run stays on it (and on its pool), calling `forward` there.
        job(&mut forward)
    };
    let result = pool::run_with_progress(outer, on_progress)
        .map_err(|pool::NoThreads(why)| FfiError::new(QuadoptStatus::OutOfMemory, why))?
        .map_err(FfiError::from)?;
    Ok((result, last))
}

/// Runs the optimizer (`built`, else one built here for `mesh`) on an owned mesh on the
/// library's worker threads, calling the C progress callback on the calling thread, and
/// returns the new positions and the report. Cancellation is an error here, so nothing is
/// written.
pub(super) fn run(
    built: Option<&Optimizer>,
    mut mesh: Mesh,
    o: &QuadoptOptions,
) -> Result<(Mesh, Report), FfiError> {
    let options = convert_options(o)?;
    let ((mesh, report), last) = with_progress(o, |forward| {
        // Checked on a worker, once the pool (its stacks, its allocator arenas) exists.
        let needed = run_bytes(&mesh) + built.map_or_else(|| topology_bytes(&mesh), |_| 0);
        check_memory_for(needed, "the optimizer's working memory")?;
        let owned;
        let optimizer = match built {
            Some(optimizer) => optimizer,
            None => {
                owned = Optimizer::new(&mesh);
                &owned
            }
        };
        optimizer.run(&mut mesh, &options, Some(forward)).map(|report| (mesh, report))
    })?;
    if report.cancelled {
        let at = last.map_or(String::new(), |p| {
            format!(" at pass {} of {}, iteration {}", p.pass, p.passes, p.iteration)
        });
        return Err(FfiError::new(
            QuadoptStatus::Cancelled,
            format!("cancelled by the progress callback{at}; nothing was written"),
        ));
    }
    Ok((mesh, report))
}

/// Builds and validates the 2D mesh of a planar input: x and y (`Plane::Xy`), or the 2D
/// coordinates in the input's plane (`Plane::Frame`, `dim` 3).
///
/// # Safety
/// As [`read_mesh`]; `plane` is the input's, from [`plane_of`], and not `Curved`.
pub(super) unsafe fn read_planar_mesh(
    coords: *const f64,
    dim: u32,
    vertex_count: usize,
    quads: *const u32,
    quad_count: usize,
    fixed: *const u8,
    plane: &Plane,
) -> Result<Mesh, FfiError> {
    match plane {
        // SAFETY: forwarded from this function's contract (a frame comes from dim 3 only).
        Plane::Frame(frame) => unsafe { read_mesh_in(coords, vertex_count, quads, quad_count, fixed, frame) },
        // SAFETY: forwarded from this function's contract.
        _ => unsafe { read_mesh(coords, dim, vertex_count, quads, quad_count, fixed) },
    }
}

/// Writes the optimized 2D `points` of a planar input back into the caller's coordinates: x and
/// y (`Plane::Xy`, z never written), or the moved vertices' points of the input's plane.
///
/// # Safety
/// `coords` must be aligned and hold `points.len() * dim` doubles, the input still (for a
/// frame, which compares against it); `plane` as in [`read_planar_mesh`].
pub(super) unsafe fn write_planar_points(coords: *mut f64, dim: u32, points: &[DVec2], plane: &Plane) {
    match plane {
        // SAFETY: forwarded from this function's contract (a frame comes from dim 3 only).
        Plane::Frame(frame) => unsafe { write_points_in(coords, points, frame) },
        // SAFETY: forwarded from this function's contract.
        _ => unsafe { write_points(coords, dim as usize, points) },
    }
}

/// Optimizes a mesh in place: moves the vertices to raise the faces' scaled Jacobians, keeping
/// connectivity, corners, fixed vertices and the boundary. On any error, cancellation
/// included, neither `coords` nor `report` is written.
///
/// A planar mesh is optimized in its plane: `dim` 2, or `dim` 3 with the same z at every vertex
/// used by a face (x and y of each vertex move and z is never written). A `dim` 3 mesh is
/// planar when the vertices used by its faces lie on one plane to within rounding (the
/// library's one planarity rule, the command-line tool's and the C++ adapters' too: see
/// `quadopt_is_planar()`); in a plane x or y = const, or a tilted plane, it is optimized in
/// an orthonormal frame of that plane and each moved vertex is written back as its point of
/// the plane (vertices that do not move are not written). Any other `dim` 3 mesh lies on a
/// curved surface, however slightly curved: it is optimized on that surface in 3D as
/// `quadopt_optimize_surface()` does with no marked feature edge (x, y and z written; a closed
/// surface accepted; the report's `surface` is 1), never flattened.
///
/// - `coords`: `vertex_count * dim` doubles, read and written; NULL only if `vertex_count` is 0.
/// - `dim`: 2 or 3 doubles per vertex.
/// - `quads`: `4 * quad_count` vertex indices, four per face in boundary order; NULL only if
///   `quad_count` is 0 (`quad_count` counts faces). A quad is four indices; a triangle is three
///   followed by `QUADOPT_NO_VERTEX` (a quad-dominant mesh: quads and triangles; triangles are
///   kept as triangles and their quality counts too). Faces may be given clockwise or
///   counter-clockwise. Each connected part
///   of a planar mesh needs a boundary edge: a closed mesh (every vertex interior, such as a grid
///   whose quads wrap around) cannot lie flat in a plane without folds and is
///   `QUADOPT_STATUS_CLOSED_MESH`.
/// - `fixed`: NULL (no fixed vertices) or `vertex_count` bytes, nonzero = the vertex never moves.
/// - `options`: NULL for the defaults.
/// - `report`: NULL, or a report whose `struct_size` is set (see `quadopt_report_init()`).
///
/// # Safety
/// Every non-NULL pointer must point to (aligned) memory of the size described above, valid
/// for the duration of the call; the buffers must not overlap.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn quadopt_optimize(
    coords: *mut f64,
    dim: u32,
    vertex_count: usize,
    quads: *const u32,
    quad_count: usize,
    fixed: *const u8,
    options: *const QuadoptOptions,
    report: *mut QuadoptReport,
) -> QuadoptStatus {
    boundary("quadopt_optimize", || {
        // SAFETY: forwarded from this function's contract (plane_of reads nothing when the
        // arguments' checks fail).
        let plane = unsafe { plane_of(coords, dim, vertex_count, quads, quad_count) }?;
        if plane == Plane::Curved {
            // SAFETY: `dim` is 3: the contract of quadopt_optimize_surface with no marked edge.
            return unsafe {
                optimize_surface(
                    coords,
                    vertex_count,
                    quads,
                    quad_count,
                    fixed,
                    null(),
                    0,
                    options,
                    report,
                    ("quads", "quad_count"),
                )
            };
        }
        // SAFETY: forwarded from this function's contract.
        let report_bytes = unsafe { report_size(report) }?;
        // SAFETY: forwarded from this function's contract.
        let o = unsafe { read_options(options) }?;
        convert_options(&o)?;
        // SAFETY: forwarded from this function's contract.
        let mesh = unsafe { read_planar_mesh(coords, dim, vertex_count, quads, quad_count, fixed, &plane) }?;
        let (mesh, r) = run(None, mesh, &o)?;
        // SAFETY: `coords` held `vertex_count * dim` doubles (checked by read_planar_mesh), and
        // the report size was checked against the caller's declaration.
        unsafe {
            write_planar_points(coords, dim, mesh.points(), &plane);
            if let Some(bytes) = report_bytes {
                write_report(report, report_of(&r), bytes);
            }
        }
        Ok(())
    })
}

/// The checks of a quality function's outputs: `out` required, `per_quad` (if not NULL)
/// aligned with room for `quad_count` values.
fn check_quality_outputs(
    out: *mut QuadoptQuality,
    per_quad: *mut f64,
    per_quad_len: usize,
    quad_count: usize,
) -> Result<(), FfiError> {
    require_non_null(out.cast_const(), "out")?;
    if !per_quad.is_null() {
        if per_quad_len < quad_count {
            return Err(FfiError::new(
                QuadoptStatus::InvalidArgument,
                format!("per_quad_len is {per_quad_len}, smaller than quad_count = {quad_count}"),
            ));
        }
        require_non_null(per_quad.cast_const(), "per_quad")?;
        check_bytes(per_quad_len, size_of::<f64>(), "per_quad")?;
    }
    Ok(())
}

/// Writes the statistics of `values` to `out` and, if `per_quad` is not NULL, the values.
///
/// # Safety
/// `out` and `per_quad` passed [`check_quality_outputs`] with `values.len()` faces.
unsafe fn write_quality_outputs(values: &[f64], out: *mut QuadoptQuality, per_quad: *mut f64) {
    let stats = quality_of(&QualityStats::from_values(values));
    // SAFETY: `out` is non-null and aligned; `per_quad`, if non-null, is aligned and holds at
    // least values.len() doubles (the caller's contract).
    unsafe {
        if !per_quad.is_null() {
            std::ptr::copy_nonoverlapping(values.as_ptr(), per_quad, values.len());
        }
        out.write(stats);
    }
}

/// Measures the quality of a mesh without changing it: statistics over every face into `*out`
/// (required) and, if `per_quad` is not NULL, each face's scaled Jacobian (a triangle's is
/// Verdict's triangle scaled Jacobian: 1 for an equilateral one) into
/// `per_quad[0..quad_count]` (`per_quad_len` must be >= `quad_count`). Quality is measured
/// against the mesh's consistent orientation, so a mesh given clockwise scores like its mirror
/// image. Arrays (triangles included) as in `quadopt_optimize()`. Nothing is written on error.
/// A `dim` 3 mesh is measured where `quadopt_optimize()` would optimize it: a planar one in its
/// plane, and one on a curved surface (not planar by `quadopt_is_planar()`'s rule) on that
/// surface: each face's value is then the signed measure a surface run reports as its `input`
/// (each corner against the normal of the mesh's surface there, so a face folded over is
/// negative; with the default feature angle and no marked edge), and a closed mesh is accepted.
///
/// # Safety
/// Every non-NULL pointer must point to (aligned) memory of the size described, valid for the
/// duration of the call; `per_quad` and `out` must not overlap the inputs.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn quadopt_quality(
    coords: *const f64,
    dim: u32,
    vertex_count: usize,
    quads: *const u32,
    quad_count: usize,
    out: *mut QuadoptQuality,
    per_quad: *mut f64,
    per_quad_len: usize,
) -> QuadoptStatus {
    boundary("quadopt_quality", || {
        check_quality_outputs(out, per_quad, per_quad_len, quad_count)?;
        // SAFETY: forwarded from this function's contract (plane_of reads nothing when the
        // arguments' checks fail).
        let plane = unsafe { plane_of(coords, dim, vertex_count, quads, quad_count) }?;
        let values = if plane == Plane::Curved {
            // SAFETY: `dim` is 3, as surface_quality_values reads.
            unsafe { surface_quality_values(coords, vertex_count, quads, quad_count) }?
        } else {
            // SAFETY: forwarded from this function's contract.
            let mesh =
                unsafe { read_planar_mesh(coords, dim, vertex_count, quads, quad_count, null(), &plane) }?;
            mesh.try_quality_values()?
        };
        // SAFETY: checked by check_quality_outputs, `values` has quad_count entries.
        unsafe { write_quality_outputs(&values, out, per_quad) };
        Ok(())
    })
}

/// Verdict's 3D scaled Jacobian of every face of a mesh in 3D, as VTK's vtkMeshQuality,
/// ParaView and MeshLab compute it (each corner against the face's own centre normal, so it
/// does not depend on the face's orientation, and a face folded over its neighbours can score
/// well): statistics into `*out` (required) and, if `per_quad` is not NULL, each face's value
/// into `per_quad[0..quad_count]` (`per_quad_len` must be >= `quad_count`). The measure a run
/// reports as `input_verdict` and `output_verdict`. `coords` holds `3 * vertex_count` doubles
/// (planar or not), `quads` as in `quadopt_optimize()` (triangles included). Nothing is written
/// on error.
///
/// # Safety
/// Every non-NULL pointer must point to (aligned) memory of the size described, valid for the
/// duration of the call; `per_quad` and `out` must not overlap the inputs.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn quadopt_verdict_quality(
    coords: *const f64,
    vertex_count: usize,
    quads: *const u32,
    quad_count: usize,
    out: *mut QuadoptQuality,
    per_quad: *mut f64,
    per_quad_len: usize,
) -> QuadoptStatus {
    boundary("quadopt_verdict_quality", || {
        check_quality_outputs(out, per_quad, per_quad_len, quad_count)?;
        // SAFETY: forwarded from this function's contract.
        let points = unsafe { super::boundary::read_points_3d_flat(coords, vertex_count) }?;
        // SAFETY: forwarded from this function's contract.
        let faces = unsafe { super::boundary::read_quads_checked(quads, quad_count) }?;
        if faces.is_empty() {
            return Err(Error::NoQuads.into());
        }
        crate::mesh::validate_indices(faces, vertex_count, true)?;
        if let Some(v) = points.iter().position(|p| p.iter().any(|c| !c.is_finite())) {
            return Err(Error::NonFiniteCoordinate { vertex: v }.into());
        }
        let mut values = crate::alloc::try_with_capacity(faces.len(), "per-face values")?;
        let at = |v: u32| glam::DVec3::from_array(points[v as usize]);
        // A triangle's fourth corner repeats its third, as `quality3d::corners` gives it.
        values.extend(faces.iter().map(|f| {
            let d = crate::face::fourth_corner(f);
            crate::quality3d::verdict_scaled_jacobian(&[at(f[0]), at(f[1]), at(f[2]), at(d)])
        }));
        // SAFETY: checked by check_quality_outputs, `values` has quad_count entries.
        unsafe { write_quality_outputs(&values, out, per_quad) };
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ffi::options::default_options;
    use crate::ffi::test_support::*;
    use crate::ffi::*;
    use std::ffi::c_void;
    use std::ptr::{null, null_mut};
    use std::sync::atomic::Ordering;

    #[test]
    fn optimize_puts_the_dragged_centre_back_and_fills_the_report() {
        for dim in [2u32, 3] {
            let (mut coords, quads) = patch(dim as usize);
            let before = coords.clone();
            let mut report = quadopt_report_init();
            let o = fixed_boundary_options();
            // SAFETY: live buffers of the stated lengths.
            let status = unsafe {
                quadopt_optimize(coords.as_mut_ptr(), dim, 9, quads.as_ptr(), 4, null(), &o, &mut report)
            };
            assert_eq!(status, QuadoptStatus::Ok, "{}", last_error());
            let d = dim as usize;
            assert!((coords[4 * d] - 1.0).abs() < 1e-3 && (coords[4 * d + 1] - 1.0).abs() < 1e-3);
            for v in 0..9 {
                if v != 4 {
                    // Boundary vertices are fixed: bit-identical.
                    assert_eq!(bits(&coords[v * d..v * d + 2]), bits(&before[v * d..v * d + 2]));
                }
                if dim == 3 {
                    assert_eq!(coords[v * d + 2].to_bits(), before[v * d + 2].to_bits(), "z written");
                }
            }
            assert_eq!(report.struct_size as usize, size_of::<QuadoptReport>());
            // Hand computation: in quad [4, 5, 8, 7] the corner at (1.6, 1.5) is reflex, with
            // edges (0.4, -0.5) and (-0.6, 0.5): cross -0.1 / (sqrt(0.41) sqrt(0.61)).
            let reflex = -0.1 / (0.41f64.sqrt() * 0.61f64.sqrt());
            assert!((report.input.min - reflex).abs() < 1e-12, "{}", report.input.min);
            assert_eq!(report.input.inverted, 1);
            assert!(report.untangle_sweeps >= 1);
            assert!(report.output.min > 0.999);
            assert_eq!((report.output.inverted, report.tangled_quads), (0, 0));
            assert_eq!(report.movable, 1, "only the centre may move");
            assert_eq!((report.loops_fixed, report.loops_slide, report.loops_snap), (1, 0, 0));
            assert_eq!(report.converged, 1);
            assert!(report.iterations >= 1 && report.final_energy <= report.initial_energy);
            assert_eq!((report.max_boundary_deviation, report.hausdorff), (0.0, 0.0));
        }
    }

    #[test]
    fn null_options_and_report_use_defaults() {
        let (mut coords, quads) = patch(2);
        // SAFETY: live buffers of the stated lengths.
        let status = unsafe {
            quadopt_optimize(coords.as_mut_ptr(), 2, 9, quads.as_ptr(), 4, null(), null(), null_mut())
        };
        assert_eq!(status, QuadoptStatus::Ok);
        // The default (automatic) boundary mode may move boundary vertices, but the centre
        // still ends up much closer to (1, 1) than it started.
        assert!((coords[8] - 1.0).hypot(coords[9] - 1.0) < 0.1);
    }

    #[test]
    fn fixed_mask_keeps_vertices_bit_identical() {
        let (coords, quads) = patch(2);
        let mut fixed = [0u8; 9];
        fixed[4] = 7; // any nonzero byte means fixed
        let mut c = coords.clone();
        let o = QuadoptOptions { boundary: QuadoptBoundary::Slide as u32, ..default_options() };
        let mut report = quadopt_report_init();
        // SAFETY: live buffers of the stated lengths.
        let status = unsafe {
            quadopt_optimize(c.as_mut_ptr(), 2, 9, quads.as_ptr(), 4, fixed.as_ptr(), &o, &mut report)
        };
        assert_eq!(status, QuadoptStatus::Ok);
        assert_eq!(bits(&c[8..10]), bits(&coords[8..10]));
        assert_eq!(report.loops_slide, 1);
    }

    #[test]
    fn the_max_min_stage_is_an_option_and_its_gain_is_reported() {
        let on = default_options();
        assert_eq!(on.max_min, 1, "on by default");
        let (with, r) = run_plate(&on, size_of::<QuadoptReport>());
        assert_eq!(r.max_min, 1);
        assert!(r.output.min > r.sweeps.min + 0.05, "{:?} -> {:?}", r.sweeps, r.output);
        assert!(r.output.avg >= r.sweeps.avg - 1e-3);
        let off = QuadoptOptions { max_min: 0, ..on };
        let (without, r0) = run_plate(&off, size_of::<QuadoptReport>());
        assert_eq!(r0.max_min, 0);
        assert_eq!(bytes_of(&r0.sweeps), bytes_of(&r0.output), "no stage: sweeps == output");
        // (The sweeps themselves differ: before the stage they are kept for their average.)
        assert_ne!(bits(&with), bits(&without));
    }

    #[test]
    fn cancel_writes_nothing_and_reports_where() {
        unsafe extern "C" fn cancel_at_third(p: *const QuadoptProgress, user: *mut c_void) -> bool {
            // SAFETY: the library passes a valid progress; user is the counter below.
            let (p, calls) = unsafe { (&*p, &mut *user.cast::<Vec<QuadoptProgress>>()) };
            calls.push(*p);
            calls.len() < 3
        }
        let (coords, quads) = patch(2);
        let mut calls: Vec<QuadoptProgress> = Vec::new();
        let o = QuadoptOptions {
            stop_rule: QuadoptStopRule::Energy as u32,
            tau: 0.0, // never converges: the callback decides
            progress: Some(cancel_at_third),
            progress_user_data: (&raw mut calls).cast(),
            ..fixed_boundary_options()
        };
        assert_eq!(optimize_status(&coords, 2, &quads, None, Some(&o)), QuadoptStatus::Cancelled);
        assert_eq!(calls.len(), 3);
        // The patch has an inverted quad: the first call comes from untangling (iteration 0).
        assert_eq!(calls.iter().map(|p| p.iteration).collect::<Vec<_>>(), [0, 1, 2]);
        assert!(calls.iter().all(|p| p.pass == 1 && p.passes == 1 && p.max_iterations == 1000));
        assert!(last_error().contains("cancelled by the progress callback at pass 1 of 1, iteration 2"));
        // The same callback under the automatic mode, also one pass.
        calls.clear();
        let o = QuadoptOptions { boundary: QuadoptBoundary::Auto as u32, ..o };
        assert_eq!(optimize_status(&coords, 2, &quads, None, Some(&o)), QuadoptStatus::Cancelled);
        assert!(calls.iter().all(|p| p.passes == 1 && p.pass == 1));
    }

    #[test]
    fn quality_matches_hand_computed_values() {
        // Two quads: a unit square and a 60 degree rhombus sharing its edge (1,0)-(1,1)...
        // simpler: a unit square [0,1,4,3] and the parallelogram [1,2,5,4] sheared by 1.
        let s = 2f64.sqrt() / 2.0; // sin 45 degrees
        let coords = [0.0, 0.0, 1.0, 0.0, 2.0, 0.0, 0.0, 1.0, 1.0, 1.0, 3.0, 1.0];
        let quads = [0, 1, 4, 3, 1, 2, 5, 4];
        let mut q = QuadoptQuality::default();
        let mut per = [f64::NAN; 3];
        // SAFETY: live buffers; per has room for 3 >= 2 values.
        let status =
            unsafe { quadopt_quality(coords.as_ptr(), 2, 6, quads.as_ptr(), 2, &mut q, per.as_mut_ptr(), 3) };
        assert_eq!(status, QuadoptStatus::Ok);
        assert_eq!(per[0], 1.0);
        assert!((per[1] - s).abs() < 1e-15, "{}", per[1]);
        assert!(per[2].is_nan(), "beyond quad_count was written");
        assert_eq!((q.min, q.max, q.inverted), (per[1], 1.0, 0));
        assert!((q.avg - (1.0 + s) / 2.0).abs() < 1e-15);
        // Given clockwise, the mesh scores the same (orientation is made consistent).
        let cw = [0, 3, 4, 1, 1, 4, 5, 2];
        let mut q2 = QuadoptQuality::default();
        // SAFETY: live buffers; no per-quad output.
        let status =
            unsafe { quadopt_quality(coords.as_ptr(), 2, 6, cw.as_ptr(), 2, &mut q2, null_mut(), 0) };
        assert_eq!((status, q2), (QuadoptStatus::Ok, q));
        // Errors write nothing.
        let mut q3 = QuadoptQuality { min: 9.0, ..Default::default() };
        let mut per = [7.0; 2];
        // SAFETY: live buffers; the calls fail on the checks.
        unsafe {
            let s = quadopt_quality(coords.as_ptr(), 2, 6, quads.as_ptr(), 2, &mut q3, per.as_mut_ptr(), 1);
            assert_eq!(s, QuadoptStatus::InvalidArgument);
            assert!(last_error().contains("per_quad_len is 1"));
            let s = quadopt_quality(coords.as_ptr(), 2, 6, quads.as_ptr(), 2, null_mut(), null_mut(), 0);
            assert_eq!(s, QuadoptStatus::NullPointer);
            assert!(last_error().contains("out is NULL"));
            let s = quadopt_quality(coords.as_ptr(), 2, 5, quads.as_ptr(), 2, &mut q3, per.as_mut_ptr(), 2);
            assert_eq!(s, QuadoptStatus::IndexOutOfRange);
        }
        assert_eq!((q3.min, per), (9.0, [7.0; 2]));
    }

    #[test]
    fn verdict_quality_matches_hand_computed_values() {
        // In 3D: a unit square in z = 0 (1), the same square with corner 3 lifted to z = 1
        // (its value by Verdict's definition, computed below) and an equilateral triangle (1).
        let h = 3f64.sqrt() / 2.0;
        let coords = [
            0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0, 0.0, // the flat square
            0.0, 1.0, 1.0, // corner 3 lifted: vertex 4
            0.0, 0.0, 5.0, 1.0, 0.0, 5.0, 0.5, h, 5.0, // the triangle
        ];
        let faces = [0, 1, 2, 3, 0, 1, 2, 4, 5, 6, 7, crate::face::NO_VERTEX];
        let mut q = QuadoptQuality::default();
        let mut per = [f64::NAN; 4];
        // SAFETY: live buffers; per has room for 4 >= 3 values.
        let status = unsafe {
            quadopt_verdict_quality(coords.as_ptr(), 8, faces.as_ptr(), 3, &mut q, per.as_mut_ptr(), 4)
        };
        assert_eq!(status, QuadoptStatus::Ok, "{}", last_error());
        assert_eq!(per[0], 1.0);
        // The bent square by Verdict's definition: the centre normal is the cross product of
        // the diagonals, each corner the triple product of its edges and that normal over
        // their lengths; the smallest of the four.
        let p =
            [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 1.0]].map(glam::DVec3::from_array);
        let n = (p[2] - p[0]).cross(p[3] - p[1]).normalize();
        let corner = |k: usize| {
            let (a, b) = (p[(k + 1) % 4] - p[k], p[(k + 3) % 4] - p[k]);
            a.cross(b).dot(n) / (a.length() * b.length())
        };
        let bent = (0..4).map(corner).fold(f64::INFINITY, f64::min);
        assert!(bent > 0.5 && bent < 0.9 && (per[1] - bent).abs() < 1e-12, "{} against {bent}", per[1]);
        assert!((per[2] - 1.0).abs() < 1e-12, "{}", per[2]);
        assert!(per[3].is_nan(), "beyond quad_count was written");
        assert_eq!((q.min, q.inverted), (per[1], 0));
        // Reversed, every face scores the same.
        let reversed = [0, 3, 2, 1, 0, 4, 2, 1, 5, 7, 6, crate::face::NO_VERTEX];
        let mut again = [f64::NAN; 3];
        let mut q2 = QuadoptQuality::default();
        // SAFETY: live buffers.
        let status = unsafe {
            quadopt_verdict_quality(coords.as_ptr(), 8, reversed.as_ptr(), 3, &mut q2, again.as_mut_ptr(), 3)
        };
        assert_eq!(status, QuadoptStatus::Ok);
        assert_eq!(again, per[..3]);
        // Errors write nothing.
        let mut q3 = QuadoptQuality { min: 9.0, ..Default::default() };
        let mut out = [7.0; 3];
        let mut nan = coords;
        nan[4] = f64::NAN;
        // SAFETY: live buffers; the calls fail on the checks.
        unsafe {
            let s =
                quadopt_verdict_quality(coords.as_ptr(), 8, faces.as_ptr(), 3, &mut q3, out.as_mut_ptr(), 2);
            assert_eq!(s, QuadoptStatus::InvalidArgument);
            let s = quadopt_verdict_quality(coords.as_ptr(), 8, faces.as_ptr(), 3, null_mut(), null_mut(), 0);
            assert_eq!(s, QuadoptStatus::NullPointer);
            let s =
                quadopt_verdict_quality(coords.as_ptr(), 7, faces.as_ptr(), 3, &mut q3, out.as_mut_ptr(), 3);
            assert_eq!(s, QuadoptStatus::IndexOutOfRange);
            let s = quadopt_verdict_quality(nan.as_ptr(), 8, faces.as_ptr(), 3, &mut q3, out.as_mut_ptr(), 3);
            assert_eq!(s, QuadoptStatus::NonFiniteCoordinate);
            let s =
                quadopt_verdict_quality(coords.as_ptr(), 8, faces.as_ptr(), 0, &mut q3, out.as_mut_ptr(), 3);
            assert_eq!(s, QuadoptStatus::NoQuads);
        }
        assert_eq!((q3.min, out), (9.0, [7.0; 3]));
    }

    /// Threads of this process.
    fn threads_now() -> usize {
        std::fs::read_dir("/proc/self/task").unwrap().count()
    }

    /// Threads of this process, once the count is `expected` or after a second. A joined
    /// thread can stay listed for a moment: `join` returns when the thread has cleared its id,
    /// which the kernel does before it removes the thread from /proc.
    fn thread_count(expected: usize) -> usize {
        let until = std::time::Instant::now() + std::time::Duration::from_secs(1);
        loop {
            let n = threads_now();
            if n == expected || std::time::Instant::now() > until {
                return n;
            }
            std::thread::sleep(std::time::Duration::from_millis(1));
        }
    }

    #[test]
    #[cfg(target_os = "linux")]
    fn a_pool_that_cannot_start_leaves_no_thread_and_later_calls_work() {
        const NAME: &str = "ffi::run::tests::a_pool_that_cannot_start_leaves_no_thread_and_later_calls_work";
        if !is_child(NAME) {
            run_in_child(NAME, &[("RAYON_NUM_THREADS", "3")]);
            return;
        }
        let o = fixed_boundary_options();
        let (untouched, _) = patch(2);
        let baseline = threads_now();
        // No thread at all can start: a status, nothing written, nothing left running.
        pool::THREAD_LIMIT.store(0, Ordering::SeqCst);
        let (s, c) = optimize_patch(&o);
        assert_eq!(s, QuadoptStatus::OutOfMemory);
        assert!(last_error().contains("cannot start a worker thread"), "{}", last_error());
        assert_eq!((c, thread_count(baseline)), (bits(&untouched), baseline));
        // One thread can start, the pool of three cannot: the started one is joined and the
        // call runs on a single worker, joined too.
        pool::THREAD_LIMIT.store(1, Ordering::SeqCst);
        let (s, single) = optimize_patch(&o);
        assert_eq!((s, thread_count(baseline)), (QuadoptStatus::Ok, baseline), "{}", last_error());
        // Threads available again: the next call builds the pool, with the same result.
        pool::THREAD_LIMIT.store(usize::MAX, Ordering::SeqCst);
        let (s, pooled) = optimize_patch(&o);
        assert_eq!((s, thread_count(baseline + 3)), (QuadoptStatus::Ok, baseline + 3));
        assert_eq!(single, pooled, "the thread count changed the result");
        assert!((f64::from_bits(pooled[8]) - 1.0).abs() < 1e-3);
    }

    /// A unit square [0, 1, 2, 3] and the equilateral triangle on its right edge, given with
    /// the sentinel: 5 vertices, 2 faces.
    fn square_and_triangle() -> (Vec<f64>, Vec<u32>) {
        let h = 3f64.sqrt() / 2.0;
        let coords = vec![0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0, 1.0 + h, 0.5];
        (coords, vec![0, 1, 2, 3, 1, 4, 2, QUADOPT_NO_VERTEX])
    }

    #[test]
    fn the_sentinel_makes_a_triangle_and_is_out_of_range_elsewhere() {
        assert_eq!(QUADOPT_NO_VERTEX, crate::face::NO_VERTEX);
        let (coords, faces) = square_and_triangle();
        let mut q = QuadoptQuality::default();
        let mut per = [f64::NAN; 2];
        // SAFETY: live buffers of the stated lengths.
        let s =
            unsafe { quadopt_quality(coords.as_ptr(), 2, 5, faces.as_ptr(), 2, &mut q, per.as_mut_ptr(), 2) };
        assert_eq!(s, QuadoptStatus::Ok, "{}", last_error());
        assert_eq!(per[0], 1.0);
        assert!((per[1] - 1.0).abs() < 1e-12, "the equilateral triangle scores {}", per[1]);
        assert_eq!((q.min, q.max, q.inverted), (per[0].min(per[1]), per[0].max(per[1]), 0));
        // A handle takes the same arrays.
        let mut handle = null_mut();
        // SAFETY: live buffers; `handle` receives a pointer.
        let s = unsafe {
            quadopt_optimizer_create(coords.as_ptr(), 2, 5, faces.as_ptr(), 2, null(), &mut handle)
        };
        assert_eq!(s, QuadoptStatus::Ok, "{}", last_error());
        // SAFETY: the live handle, freed once.
        unsafe { quadopt_optimizer_free(handle) };
        // The sentinel in any of a face's first three slots is an index out of range, naming
        // the face and the corner; nothing is written.
        for corner in 0..3 {
            let mut bad = faces.clone();
            bad[4 + corner] = QUADOPT_NO_VERTEX;
            let o = fixed_boundary_options();
            assert_eq!(optimize_status(&coords, 2, &bad, None, Some(&o)), QuadoptStatus::IndexOutOfRange);
            let want = format!("quad 1 corner {corner} refers to vertex {}", u32::MAX);
            assert!(last_error().contains(&want), "{}", last_error());
            let mut q2 = QuadoptQuality { min: 9.0, ..Default::default() };
            // SAFETY: live buffers; the call fails on validation.
            let s =
                unsafe { quadopt_quality(coords.as_ptr(), 2, 5, bad.as_ptr(), 2, &mut q2, null_mut(), 0) };
            assert_eq!((s, q2.min), (QuadoptStatus::IndexOutOfRange, 9.0));
            let mut other = 0x10 as *mut QuadoptOptimizer;
            // SAFETY: live buffers; the call fails on validation and leaves `other` alone.
            let s = unsafe {
                quadopt_optimizer_create(coords.as_ptr(), 2, 5, bad.as_ptr(), 2, null(), &mut other)
            };
            assert_eq!((s, other as usize), (QuadoptStatus::IndexOutOfRange, 0x10));
        }
        // A triangle repeating a vertex is still a repeated vertex.
        let repeated = [0, 1, 2, 3, 1, 4, 1, QUADOPT_NO_VERTEX];
        assert_eq!(optimize_status(&coords, 2, &repeated, None, None), QuadoptStatus::RepeatedVertex);
    }

    /// The 3x3-vertex patch with its top-right quad [4, 5, 8, 7] split into two triangles.
    fn mixed_patch() -> (Vec<f64>, Vec<u32>) {
        let (coords, mut faces) = patch(2);
        faces.truncate(12);
        faces.extend([4, 5, 8, QUADOPT_NO_VERTEX, 4, 8, 7, QUADOPT_NO_VERTEX]);
        (coords, faces)
    }

    /// Needs the optimizer's triangle support (until it lands a mixed mesh may panic, which
    /// the boundary turns into QUADOPT_STATUS_PANIC).
    #[test]
    fn a_mixed_mesh_is_optimized_through_the_c_abi_with_per_kind_statistics() {
        let (mut coords, faces) = mixed_patch();
        let before = coords.clone();
        let mut r = quadopt_report_init();
        let o = fixed_boundary_options();
        // SAFETY: live buffers of the stated lengths.
        let s = unsafe { quadopt_optimize(coords.as_mut_ptr(), 2, 9, faces.as_ptr(), 5, null(), &o, &mut r) };
        assert_eq!(s, QuadoptStatus::Ok, "{}", last_error());
        for v in (0..9).filter(|&v| v != 4) {
            assert_eq!(
                bits(&coords[2 * v..2 * v + 2]),
                bits(&before[2 * v..2 * v + 2]),
                "boundary vertex {v}"
            );
        }
        assert_eq!((r.input_quads.count, r.input_triangles.count), (3, 2));
        assert_eq!((r.output_quads.count, r.output_triangles.count), (3, 2));
        assert_eq!(r.output.inverted, 0);
        assert!(r.output.min > r.input.min, "{:?} -> {:?}", r.input, r.output);
        assert_eq!(r.input.min, r.input_quads.min.min(r.input_triangles.min));
        assert_eq!(r.output.min, r.output_quads.min.min(r.output_triangles.min));
        // The per-kind statistics are those of the faces quadopt_quality measures.
        let mut per = [0.0; 5];
        let mut q = QuadoptQuality::default();
        // SAFETY: live buffers of the stated lengths.
        let s =
            unsafe { quadopt_quality(coords.as_ptr(), 2, 9, faces.as_ptr(), 5, &mut q, per.as_mut_ptr(), 5) };
        assert_eq!((s, q), (QuadoptStatus::Ok, r.output));
        assert_eq!(r.output_quads.min, per[..3].iter().copied().fold(f64::INFINITY, f64::min));
        assert_eq!(r.output_triangles.min, per[3..].iter().copied().fold(f64::INFINITY, f64::min));
        // A handle gives the same result.
        let mut handle = null_mut();
        let mut again = before.clone();
        // SAFETY: live buffers; the handle is freed once.
        unsafe {
            let s = quadopt_optimizer_create(before.as_ptr(), 2, 9, faces.as_ptr(), 5, null(), &mut handle);
            assert_eq!(s, QuadoptStatus::Ok, "{}", last_error());
            let s = quadopt_optimizer_optimize(handle, again.as_mut_ptr(), 2, 9, &o, null_mut());
            assert_eq!(s, QuadoptStatus::Ok, "{}", last_error());
            quadopt_optimizer_free(handle);
        }
        assert_eq!(bits(&again), bits(&coords));
    }

    #[test]
    fn the_progress_callback_runs_on_the_calling_thread() {
        unsafe extern "C" fn record(_: *const QuadoptProgress, user: *mut c_void) -> bool {
            // SAFETY: user is the vector below, used by this thread only.
            unsafe { &mut *user.cast::<Vec<std::thread::ThreadId>>() }.push(std::thread::current().id());
            true
        }
        let mut seen: Vec<std::thread::ThreadId> = Vec::new();
        let o = QuadoptOptions {
            progress: Some(record),
            progress_user_data: (&raw mut seen).cast(),
            ..fixed_boundary_options()
        };
        assert_eq!(optimize_patch(&o).0, QuadoptStatus::Ok);
        assert!(!seen.is_empty());
        assert!(seen.iter().all(|&t| t == std::thread::current().id()));
    }

    #[test]
    fn nested_calls_from_the_callback_finish_on_a_single_worker() {
        const NAME: &str = "ffi::run::tests::nested_calls_from_the_callback_finish_on_a_single_worker";
        if !is_child(NAME) {
            run_in_child(NAME, &[("RAYON_NUM_THREADS", "1")]);
            return;
        }
        /// Each callback of the outer three levels optimizes the patch again, one level deeper.
        unsafe extern "C" fn recurse(_: *const QuadoptProgress, user: *mut c_void) -> bool {
            // SAFETY: user is the depth counter below, used by this thread only.
            let depth = unsafe { &mut *user.cast::<usize>() };
            if *depth < 3 {
                *depth += 1;
                let o = QuadoptOptions { max_iterations: 2, ..nested_options(user) };
                assert_eq!(optimize_patch(&o).0, QuadoptStatus::Ok);
                *depth -= 1;
            }
            true
        }
        fn nested_options(user: *mut c_void) -> QuadoptOptions {
            QuadoptOptions { progress: Some(recurse), progress_user_data: user, ..fixed_boundary_options() }
        }
        let mut depth = 0usize;
        let o = QuadoptOptions { max_iterations: 3, ..nested_options((&raw mut depth).cast()) };
        let (s, c) = optimize_patch(&o);
        assert_eq!((s, depth), (QuadoptStatus::Ok, 0), "{}", last_error());
        let (_, plain) = optimize_patch(&QuadoptOptions { max_iterations: 3, ..fixed_boundary_options() });
        assert_eq!(c, plain);
    }
}
