//! The library's one planarity rule for C and C++ callers: [`quadopt_is_planar`] and
//! [`QuadoptPlanarity`]. The rule is `PlanarFrame::fit` (`src/io/planar.rs`), which the
//! command-line tool and the `dim` 3 entry points apply too; the C++ adapters
//! (`include/quadopt/planar.hpp`) call this function to decide.

use crate::error::Error;
use crate::io::PlanarFrame;

use super::boundary::{boundary, read_points_3d_flat, read_quads_checked, require_non_null};
use super::status::{FfiError, QuadoptStatus};

/// Whether a mesh in 3D lies in a plane, by the rule every interface applies (see
/// `quadopt_is_planar()`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct QuadoptPlanarity {
    /// 1 when the vertices used by a face lie on one plane to within rounding, else 0.
    pub planar: u32,
    /// When `planar` is 0: the used vertex farthest from the best-fit plane (0-based); else 0.
    pub vertex: usize,
    /// When `planar` is 0: that vertex's distance from the best-fit plane; else 0.
    pub distance: f64,
    /// When `planar` is 0: the largest distance accepted (see `quadopt_is_planar()`); else 0.
    pub tolerance: f64,
}

/// Decides whether a mesh in 3D is planar, by the library's one planarity rule, the one
/// `quadopt_optimize()` and `quadopt_quality()` apply to `dim` 3 coordinates, the
/// command-line tool to its files and the C++ adapters to their meshes: the mesh is planar
/// when the vertices used by a face lie on one plane to within rounding. That is, one
/// coordinate (x, y or z) is the same at every used vertex, or every used vertex is within
/// 1e-12 times the bounding-box diagonal of the used vertices, plus 16 machine epsilons times
/// their largest coordinate in magnitude, of the least-squares plane. A mesh in a tilted plane
/// whose coordinates were rounded to doubles is planar; anything farther lies on a curved
/// surface (a sheet whose z wobbles by 1e-4 of its size, a tilted plane stored with 6
/// significant digits) and is optimized on that surface, never flattened.
///
/// - `coords`: `3 * vertex_count` doubles (x, y, z per vertex); NULL only if `vertex_count` is
///   0. A NaN or infinite coordinate of any vertex is `QUADOPT_STATUS_NON_FINITE_COORDINATE`.
/// - `quads`: `4 * quad_count` vertex indices as in `quadopt_optimize()` (a triangle's fourth
///   is `QUADOPT_NO_VERTEX`); only which vertices they use is read, and an index out of range
///   is no vertex. NULL with `quad_count` 0: every vertex counts.
/// - `out`: receives the answer (required); not written on error.
///
/// # Safety
/// Every non-NULL pointer must point to (aligned) memory of the size described, valid for the
/// duration of the call.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn quadopt_is_planar(
    coords: *const f64,
    vertex_count: usize,
    quads: *const u32,
    quad_count: usize,
    out: *mut QuadoptPlanarity,
) -> QuadoptStatus {
    boundary("quadopt_is_planar", || {
        require_non_null(out.cast_const(), "out")?;
        // SAFETY: forwarded from this function's contract.
        let points = unsafe { read_points_3d_flat(coords, vertex_count) }?;
        // SAFETY: forwarded from this function's contract.
        let faces = unsafe { read_quads_checked(quads, quad_count) }?;
        let used = if faces.is_empty() {
            None
        } else {
            Some(crate::io::planar::used_vertices(vertex_count, faces)?)
        };
        let answer = match PlanarFrame::fit(points, used.as_deref()) {
            Ok(_) => QuadoptPlanarity { planar: 1, ..QuadoptPlanarity::default() },
            Err(Error::NotPlanar { vertex, distance, tolerance }) => {
                QuadoptPlanarity { planar: 0, vertex, distance, tolerance }
            }
            Err(e) => return Err(FfiError::from(e)),
        };
        // SAFETY: `out` is non-null and aligned (checked) and writable by the contract.
        unsafe { out.write(answer) };
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ffi::test_support::*;
    use std::ptr::{null, null_mut};

    /// An `n` x `n` grid of unit squares: its faces.
    fn grid_faces(n: u32) -> Vec<u32> {
        let id = |i: u32, j: u32| j * (n + 1) + i;
        (0..n * n)
            .flat_map(|c| {
                let (i, j) = (c % n, c / n);
                [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]
            })
            .collect()
    }

    fn planarity(coords: &[f64], faces: &[u32]) -> (QuadoptStatus, QuadoptPlanarity) {
        let mut out = QuadoptPlanarity { planar: 7, vertex: 7, distance: 7.0, tolerance: 7.0 };
        // SAFETY: live buffers of the stated lengths.
        let s = unsafe {
            quadopt_is_planar(coords.as_ptr(), coords.len() / 3, faces.as_ptr(), faces.len() / 4, &mut out)
        };
        (s, out)
    }

    #[test]
    fn the_rule_accepts_rounded_tilted_planes_and_refuses_a_wobble() {
        let n = 6u32;
        let faces = grid_faces(n);
        let place = |f: &dyn Fn(f64, f64) -> [f64; 3]| -> Vec<f64> {
            (0..(n + 1) * (n + 1)).flat_map(|v| f(f64::from(v % (n + 1)), f64::from(v / (n + 1)))).collect()
        };
        // z = c, x = c: planar; the tilted plane z = 0.3 x + 0.7 y (rounded), also far from the
        // origin: planar.
        for coords in [
            place(&|s, t| [s, t, 2.5]),
            place(&|s, t| [-1.0, s, t]),
            place(&|s, t| [s, t, 0.3 * s + 0.7 * t]),
            place(&|s, t| [1e6 + 0.1 * s, -3e5 + 0.1 * t, 0.3 * (1e6 + 0.1 * s) + 0.7 * (-3e5 + 0.1 * t)]),
        ] {
            let (s, p) = planarity(&coords, &faces);
            assert_eq!((s, p), (QuadoptStatus::Ok, QuadoptPlanarity { planar: 1, ..Default::default() }));
        }
        // A wobble of 1e-4 (and one of 1e-9) of the size in z: not planar, naming the farthest
        // vertex.
        for amplitude in [1e-4, 1e-9] {
            let coords = place(&|s, t| [s, t, amplitude * (s * 1.3).sin() * (t * 0.7).cos()]);
            let (s, p) = planarity(&coords, &faces);
            assert_eq!((s, p.planar), (QuadoptStatus::Ok, 0), "{amplitude}");
            assert!(p.distance > p.tolerance && p.tolerance < 1e-10, "{p:?}");
            assert!((p.vertex as u32) < (n + 1) * (n + 1));
        }
        // Only the vertices used by a face count; with no face, all.
        let mut coords = place(&|s, t| [s, t, 0.0]);
        coords.extend([0.5, 0.5, 9.0]);
        assert_eq!(planarity(&coords, &faces).1.planar, 1);
        assert_eq!(planarity(&coords, &[]).1.planar, 0);
        // Errors: nothing written.
        coords[4] = f64::NAN;
        let (s, p) = planarity(&coords, &faces);
        assert_eq!((s, p.planar), (QuadoptStatus::NonFiniteCoordinate, 7));
        // SAFETY: fails on the checks.
        let s = unsafe { quadopt_is_planar(coords.as_ptr(), 3, null(), 0, null_mut()) };
        assert_eq!(s, QuadoptStatus::NullPointer);
        assert!(last_error().contains("quadopt_is_planar: out is NULL"), "{}", last_error());
    }
}
