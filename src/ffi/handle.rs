//! The reusable optimizer handle: [`QuadoptOptimizer`] (one connectivity, its topology built
//! once, immutable afterwards) and its create, optimize and free functions.

use crate::error::Error;
use crate::mesh::Mesh;
use crate::smooth::Optimizer;

use super::boundary::{
    Plane, boundary, boundary_or, plane_of, plane_of_faces, read_points, read_points_in, require_non_null,
};
use super::options::{QuadoptOptions, convert_options, read_options};
use super::report::{QuadoptReport, report_of, report_size, write_report};
use super::run::{check_memory_for, read_planar_mesh, run, topology_bytes, write_planar_points};
use super::status::{FfiError, QuadoptStatus};

/// A handle optimizes planar meshes only: a `dim` 3 mesh that is not planar (by the library's
/// one rule, `quadopt_is_planar()`) is `QUADOPT_STATUS_NOT_PLANAR`, whatever else is wrong with
/// it (a closed mesh on a sphere is not planar first).
fn refuse_curved(plane: &Plane) -> Result<(), FfiError> {
    if *plane == Plane::Curved {
        return Err(FfiError::new(
            QuadoptStatus::NotPlanar,
            "the mesh is not planar (dim is 3 and its vertices do not lie on one plane to within \
             rounding); a reusable optimizer optimizes planar meshes only: optimize a mesh on a \
             curved surface with quadopt_optimize_surface() (or quadopt_optimize(), which takes \
             it there)",
        ));
    }
    Ok(())
}

/// A reusable optimizer for one connectivity (quads, fixed flags, vertex count), built once
/// by `quadopt_optimizer_create()` and immutable afterwards: several threads may call
/// `quadopt_optimizer_optimize()` with one handle at the same time. Opaque to C.
#[derive(Debug)]
pub struct QuadoptOptimizer {
    /// The validated mesh at creation (connectivity, fixed flags, orientation).
    mesh: Mesh,
    /// The topology built from it.
    optimizer: Optimizer,
}

/// Creates a reusable optimizer for one connectivity: validates the mesh (arrays as in
/// `quadopt_optimize()`) and builds its topology once. A handle optimizes planar meshes only
/// (`dim` 2, or `dim` 3 in a plane by `quadopt_is_planar()`'s rule, as `quadopt_optimize()`
/// decides): a `dim` 3 mesh that is not planar is `QUADOPT_STATUS_NOT_PLANAR`, here (before
/// any other check of the mesh, so a closed surface is not planar rather than closed) and in
/// `quadopt_optimizer_optimize()`; use `quadopt_optimize_surface()` (or `quadopt_optimize()`)
/// for a mesh on a curved surface. The orientation and the fixed flags are taken from this
/// call. On success `*out` receives the handle (free it with
/// `quadopt_optimizer_free()`); on error `*out` is not written.
///
/// # Safety
/// Pointers as in `quadopt_optimize()`; `out` must point to a writable pointer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn quadopt_optimizer_create(
    coords: *const f64,
    dim: u32,
    vertex_count: usize,
    quads: *const u32,
    quad_count: usize,
    fixed: *const u8,
    out: *mut *mut QuadoptOptimizer,
) -> QuadoptStatus {
    boundary("quadopt_optimizer_create", || {
        require_non_null(out.cast_const(), "out")?;
        // SAFETY: forwarded from this function's contract (plane_of reads nothing when the
        // arguments' checks fail).
        let plane = unsafe { plane_of(coords, dim, vertex_count, quads, quad_count) }?;
        refuse_curved(&plane)?;
        // SAFETY: forwarded from this function's contract.
        let mesh = unsafe { read_planar_mesh(coords, dim, vertex_count, quads, quad_count, fixed, &plane) }?;
        check_memory_for(topology_bytes(&mesh), "the mesh's topology")?;
        let optimizer = Optimizer::new(&mesh);
        let handle = Box::into_raw(Box::new(QuadoptOptimizer { mesh, optimizer }));
        // SAFETY: `out` is non-null and aligned (checked) and writable by the contract.
        unsafe { out.write(handle) };
        Ok(())
    })
}

/// Optimizes `coords` (`vertex_count * dim` doubles, `vertex_count` equal to the handle's,
/// else `QUADOPT_STATUS_MISMATCH`) with the connectivity and fixed flags of `opt`. Options,
/// report and the nothing-written-on-error rule as in `quadopt_optimize()`. The handle is not
/// modified: several threads may use one handle at the same time with different `coords`.
///
/// # Safety
/// `opt` must be NULL or a live handle from `quadopt_optimizer_create()`; other pointers as in
/// `quadopt_optimize()`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn quadopt_optimizer_optimize(
    opt: *const QuadoptOptimizer,
    coords: *mut f64,
    dim: u32,
    vertex_count: usize,
    options: *const QuadoptOptions,
    report: *mut QuadoptReport,
) -> QuadoptStatus {
    boundary("quadopt_optimizer_optimize", || {
        require_non_null(opt, "opt")?;
        // SAFETY: a non-null `opt` is a live handle by the contract; it is only read.
        let handle = unsafe { &*opt };
        // SAFETY: forwarded from this function's contract.
        let report_bytes = unsafe { report_size(report) }?;
        // SAFETY: forwarded from this function's contract.
        let o = unsafe { read_options(options) }?;
        convert_options(&o)?;
        let expected = handle.mesh.points().len();
        if vertex_count != expected {
            return Err(Error::VertexCountMismatch { expected, got: vertex_count }.into());
        }
        // SAFETY: forwarded from this function's contract (plane_of_faces reads nothing when
        // the arguments' checks fail).
        let plane = unsafe { plane_of_faces(coords, dim, vertex_count, handle.mesh.quads()) }?;
        refuse_curved(&plane)?;
        let points = match &plane {
            // SAFETY: forwarded from this function's contract (a frame comes from dim 3 only).
            Plane::Frame(frame) => unsafe { read_points_in(coords, vertex_count, frame) }?,
            // SAFETY: forwarded from this function's contract.
            _ => unsafe { read_points(coords, dim, vertex_count) }?,
        };
        let mut mesh = handle.mesh.try_clone()?;
        mesh.set_points(&points)?;
        let (mesh, r) = run(Some(&handle.optimizer), mesh, &o)?;
        // SAFETY: as in quadopt_optimize.
        unsafe {
            write_planar_points(coords, dim, mesh.points(), &plane);
            if let Some(bytes) = report_bytes {
                write_report(report, report_of(&r), bytes);
            }
        }
        Ok(())
    })
}

/// Frees a handle from `quadopt_optimizer_create()`. NULL is a no-op.
///
/// # Safety
/// `opt` must be NULL or a live handle, not in use by another thread, and not used afterwards.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn quadopt_optimizer_free(opt: *mut QuadoptOptimizer) {
    boundary_or((), || {
        if !opt.is_null() {
            // SAFETY: a non-null `opt` came from Box::into_raw in quadopt_optimizer_create and
            // is freed exactly once by the contract.
            drop(unsafe { Box::from_raw(opt) });
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ffi::test_support::*;
    use crate::ffi::*;
    use std::ptr::{null, null_mut};

    #[test]
    fn handle_gives_the_same_result_as_one_shot_and_checks_the_vertex_count() {
        let (coords, quads) = patch(3);
        let mut handle = null_mut();
        let o = fixed_boundary_options();
        // SAFETY: live buffers; `handle` receives a pointer.
        unsafe {
            assert_eq!(
                quadopt_optimizer_create(coords.as_ptr(), 3, 9, quads.as_ptr(), 4, null(), &mut handle),
                QuadoptStatus::Ok
            );
            assert!(!handle.is_null());
            // The handle works with another stride than it was created with.
            let (mut via_handle, _) = patch(2);
            let mut r1 = quadopt_report_init();
            let s = quadopt_optimizer_optimize(handle, via_handle.as_mut_ptr(), 2, 9, &o, &mut r1);
            assert_eq!(s, QuadoptStatus::Ok);
            let (mut one_shot, _) = patch(2);
            let mut r2 = quadopt_report_init();
            let s = quadopt_optimize(one_shot.as_mut_ptr(), 2, 9, quads.as_ptr(), 4, null(), &o, &mut r2);
            assert_eq!(s, QuadoptStatus::Ok);
            assert_eq!(bits(&via_handle), bits(&one_shot));
            assert_eq!((r1.iterations, r1.output), (r2.iterations, r2.output));

            // Wrong vertex count, NULL handle, non-finite coordinates: nothing written.
            let (mut c, _) = patch(2);
            c.extend([5.0, 5.0]);
            let before = bits(&c);
            let mut report = sentinel_report();
            let s = quadopt_optimizer_optimize(handle, c.as_mut_ptr(), 2, 10, &o, &mut report);
            assert_eq!(s, QuadoptStatus::Mismatch);
            assert!(last_error().contains("10 vertices were given, but the mesh has 9"), "{}", last_error());
            let s = quadopt_optimizer_optimize(null(), c.as_mut_ptr(), 2, 9, &o, &mut report);
            assert_eq!(s, QuadoptStatus::NullPointer);
            c[0] = f64::NAN;
            let s = quadopt_optimizer_optimize(handle, c.as_mut_ptr(), 2, 9, &o, &mut report);
            assert_eq!(s, QuadoptStatus::NonFiniteCoordinate);
            assert_eq!(bits(&c[1..]), before[1..]);
            assert_eq!(bytes_of(&report), bytes_of(&sentinel_report()));

            // create: NULL out and an invalid mesh leave *out untouched.
            let s = quadopt_optimizer_create(coords.as_ptr(), 3, 9, quads.as_ptr(), 4, null(), null_mut());
            assert_eq!(s, QuadoptStatus::NullPointer);
            let mut other = 0x10 as *mut QuadoptOptimizer;
            let s = quadopt_optimizer_create(coords.as_ptr(), 3, 9, quads.as_ptr(), 0, null(), &mut other);
            assert_eq!((s, other as usize), (QuadoptStatus::NoQuads, 0x10));

            quadopt_optimizer_free(handle);
            quadopt_optimizer_free(null_mut());
        }
    }

    #[test]
    fn one_handle_is_safe_to_share_between_threads() {
        let (coords, quads) = patch(2);
        let mut handle = null_mut();
        // SAFETY: live buffers.
        let s = unsafe {
            quadopt_optimizer_create(coords.as_ptr(), 2, 9, quads.as_ptr(), 4, null(), &mut handle)
        };
        assert_eq!(s, QuadoptStatus::Ok);
        // SAFETY: the handle is live until freed below, after every thread has finished.
        let shared: &QuadoptOptimizer = unsafe { &*handle };
        let o = fixed_boundary_options();
        let start = |k: usize| {
            let mut c = coords.clone();
            c[8] = 1.0 + 0.1 * k as f64;
            c[9] = 1.0 - 0.05 * k as f64;
            c
        };
        let expected: Vec<Vec<u64>> = (0..8)
            .map(|k| {
                let mut c = start(k);
                // SAFETY: live buffers.
                let s = unsafe { quadopt_optimizer_optimize(shared, c.as_mut_ptr(), 2, 9, &o, null_mut()) };
                assert_eq!(s, QuadoptStatus::Ok);
                bits(&c)
            })
            .collect();
        std::thread::scope(|scope| {
            for t in 0..4 {
                let (expected, start) = (&expected, &start);
                scope.spawn(move || {
                    // Options hold raw pointers (user data), so each thread makes its own.
                    let o = &fixed_boundary_options();
                    for round in 0..5 {
                        let k = (t + round) % 8;
                        let mut c = start(k);
                        // SAFETY: the handle is shared read-only; each thread owns its coords.
                        let s = unsafe {
                            quadopt_optimizer_optimize(shared, c.as_mut_ptr(), 2, 9, o, null_mut())
                        };
                        assert_eq!(s, QuadoptStatus::Ok);
                        assert_eq!(bits(&c), expected[k], "thread {t} round {round}");
                        // Errors on this thread leave other threads' messages alone.
                        // SAFETY: fails on the count check before any access.
                        let s = unsafe {
                            quadopt_optimizer_optimize(shared, c.as_mut_ptr(), 2, 9 + t, o, null_mut())
                        };
                        assert_eq!(s == QuadoptStatus::Ok, t == 0);
                        if t > 0 {
                            assert!(last_error().contains(&format!("{} vertices were given", 9 + t)));
                        }
                    }
                });
            }
        });
        // SAFETY: created above, freed once.
        unsafe { quadopt_optimizer_free(handle) };
    }
}
