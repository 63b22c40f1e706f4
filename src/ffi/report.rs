//! The report: [`QuadoptQuality`], [`QuadoptReport`] (growable: only the prefix the caller
//! declared is written), its conversion from the crate's [`Report`], and
//! [`quadopt_report_init`].

use crate::quality::{ByFaceKind, QualityStats};
use crate::smooth::{BoundaryMode, Report};
use crate::surface::SurfaceReport;
use std::mem::size_of;

use super::boundary::{boundary_or, require_non_null};
use super::options::QuadoptEffort;
use super::status::{FfiError, QuadoptStatus};

/// Quality statistics of a set of quads (signed scaled Jacobian, Verdict's definition,
/// measured against the mesh's consistent orientation).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct QuadoptQuality {
    /// Smallest scaled Jacobian (the worst quad), in [-1, 1].
    pub min: f64,
    /// Mean scaled Jacobian.
    pub avg: f64,
    /// Largest scaled Jacobian.
    pub max: f64,
    /// Number of quads with a scaled Jacobian <= 0 (inverted or degenerate).
    pub inverted: usize,
}

/// Quality statistics of the faces of one kind (the quads, or the triangles) of a mesh. When
/// the mesh has no face of the kind, `count` is 0 and `min` and `avg` are NaN.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct QuadoptFaceKindQuality {
    /// Number of faces of the kind.
    pub count: usize,
    /// Smallest scaled Jacobian among them (NaN when `count` is 0).
    pub min: f64,
    /// Mean scaled Jacobian over them (NaN when `count` is 0).
    pub avg: f64,
}

/// What an optimization did. Growable: set `struct_size` (`quadopt_report_init()` does); the
/// library writes only the first `struct_size` bytes (at most its own struct) and, on success,
/// sets `struct_size` to the number of bytes it filled. Every size a published header declared
/// is accepted, from the first (200 bytes on LP64, ending before `max_min`) on, 248 (0.2,
/// ending after `reserved2`, before the per-kind fields) and 344 (ending after
/// `output_triangles`, before the surface fields); a `struct_size` smaller than the first is
/// `QUADOPT_STATUS_INVALID_ARGUMENT`. In a mesh with triangles, the quality fields (`input`,
/// `output`, `sweeps`) cover every face; the per-kind fields split `input` and `output` into
/// the quads and the triangles.
///
/// A run on a surface (`surface` is 1) fills the fields as follows: `input`, `output`,
/// `sweeps` and the per-kind fields give the signed measure (each corner against the surface's
/// normal, so a face folded over is inverted) and `input_verdict`, `output_verdict` Verdict's
/// 3D one; `corners` counts the feature corners (never moved); `converged` is 1 when the sweeps
/// stopped before their cap; `initial_energy`, `final_energy` and `hausdorff` (and its
/// relative value) are NaN (not computed on a surface); `max_boundary_deviation` (and its
/// relative value) is the largest distance of a new edge along a feature curve (the boundary,
/// a sharp or a marked edge) from the stretch of the curve it replaces, the measure
/// `max_boundary_deviation` in the options bounds; the three `loops_*` counts are 0.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct QuadoptReport {
    /// `sizeof(QuadoptReport)` as the caller compiled it; on success the bytes filled.
    pub struct_size: u32,
    /// 1 when the energy criterion was met, 0 when the iteration cap was reached.
    pub converged: u32,
    /// Quality of the input.
    pub input: QuadoptQuality,
    /// Quality of the output.
    pub output: QuadoptQuality,
    /// Sweeps performed in the pass whose result was kept.
    pub iterations: usize,
    /// Untangling sweeps performed.
    pub untangle_sweeps: usize,
    /// Quads whose vertex order was reversed internally to make the orientation consistent.
    pub reoriented_quads: usize,
    /// Boundary vertices detected as corners (never moved).
    pub corners: usize,
    /// Vertices the optimizer was allowed to move.
    pub movable: usize,
    /// Quads still inverted in the output.
    pub tangled_quads: usize,
    /// Collective energy of the input.
    pub initial_energy: f64,
    /// Collective energy of the output.
    pub final_energy: f64,
    /// Wall-clock seconds of the run.
    pub seconds: f64,
    /// Largest distance of the new boundary polyline from the original one.
    pub max_boundary_deviation: f64,
    /// Symmetric Hausdorff distance between the new and the original boundary polylines.
    pub hausdorff: f64,
    /// `max_boundary_deviation` divided by the mesh's mean edge length.
    pub max_boundary_deviation_relative: f64,
    /// `hausdorff` divided by the mesh's mean edge length.
    pub hausdorff_relative: f64,
    /// Boundary loops that were optimized in slide mode.
    pub loops_slide: usize,
    /// Boundary loops that were optimized in snap mode.
    pub loops_snap: usize,
    /// Boundary loops whose vertices were kept fixed.
    pub loops_fixed: usize,
    /// 1 when the max-min stage ran and its result was kept, else 0 (then `sweeps` equals
    /// `output`). Added in 0.2: written only when the caller's `struct_size` covers it.
    pub max_min: u32,
    /// Reserved; written as 0.
    pub reserved1: u32,
    /// Quality after the sweeps, before the max-min stage: `output` minus `sweeps` is the
    /// stage's gain.
    pub sweeps: QuadoptQuality,
    /// The preset that ran, a `QuadoptEffort` value; written only when the
    /// caller's `struct_size` covers it.
    pub effort: u32,
    /// Reserved; written as 0.
    pub reserved2: u32,
    /// `input` over the quads alone. Added with triangle support: written only when the
    /// caller's `struct_size` covers it (as for every field below).
    pub input_quads: QuadoptFaceKindQuality,
    /// `input` over the triangles alone (`count` 0 and NaN `min` and `avg` for a quad mesh).
    pub input_triangles: QuadoptFaceKindQuality,
    /// `output` over the quads alone.
    pub output_quads: QuadoptFaceKindQuality,
    /// `output` over the triangles alone (`count` 0 and NaN `min` and `avg` for a quad mesh).
    pub output_triangles: QuadoptFaceKindQuality,
    /// 1 when the mesh was optimized on its surface in 3D (`quadopt_optimize_surface()`, or
    /// `quadopt_optimize()` with `dim` 3 and a z that varies), 0 for a planar run. Added with
    /// surface support: written only when the caller's `struct_size` covers it (as for every
    /// field below).
    pub surface: u32,
    /// Reserved; written as 0.
    pub reserved3: u32,
    /// Verdict's 3D scaled Jacobian of the input (what VTK's vtkMeshQuality reports: each
    /// corner against the face's own centre normal, so blind to a face folded over). On a
    /// surface, `input` is the signed measure the optimizer ranks by (each corner against the
    /// surface's normal there). In a planar run, equal to `input`.
    pub input_verdict: QuadoptQuality,
    /// Verdict's 3D scaled Jacobian of the output (in a planar run, equal to `output`).
    pub output_verdict: QuadoptQuality,
    /// On a surface: the largest distance of a vertex from the input surface. 0 in a planar
    /// run (every vertex stays in the mesh's plane).
    pub max_distance: f64,
    /// `max_distance` divided by the input's mean edge length.
    pub max_distance_relative: f64,
    /// On a surface: the largest distance of a vertex on a feature curve (the boundary, a sharp
    /// or a marked edge) from that curve's original polyline. In a planar run, equal to
    /// `max_boundary_deviation` (the boundary is the planar run's only curve).
    pub max_feature_distance: f64,
    /// `max_feature_distance` divided by the input's mean edge length.
    pub max_feature_distance_relative: f64,
    /// On a surface: the feature curves found (boundary loops, sharp and marked edges, cut at
    /// the feature corners, which are counted in `corners`). 0 in a planar run.
    pub feature_curves: usize,
    /// On a surface: the smooth patches the feature curves cut the surface into. 0 in a planar
    /// run.
    pub patches: usize,
}

/// Size of the first published `QuadoptReport` (the same growth rule): it ended where
/// `max_min` begins.
pub(super) const REPORT_V1_SIZE: usize = std::mem::offset_of!(QuadoptReport, max_min);

/// Size of the `QuadoptReport` before the per-kind fields (0.2): it ended where `input_quads`
/// begins.
#[cfg(test)]
pub(super) const REPORT_V2_SIZE: usize = std::mem::offset_of!(QuadoptReport, input_quads);

/// Size of the `QuadoptReport` before the surface fields: it ended where `surface` begins.
#[cfg(test)]
pub(super) const REPORT_V3_SIZE: usize = std::mem::offset_of!(QuadoptReport, surface);

/// Reads the caller's declared report size, if a report was asked for.
///
/// # Safety
/// `report` must be NULL or point to a readable, aligned `struct_size` field.
pub(super) unsafe fn report_size(report: *const QuadoptReport) -> Result<Option<usize>, FfiError> {
    if report.is_null() {
        return Ok(None);
    }
    require_non_null(report, "report")?;
    // SAFETY: non-null and aligned; every version of the struct starts with `struct_size`.
    let declared = unsafe { report.cast::<u32>().read() } as usize;
    let ours = size_of::<QuadoptReport>();
    if declared < REPORT_V1_SIZE {
        return Err(FfiError::new(
            QuadoptStatus::InvalidArgument,
            format!(
                "report->struct_size is {declared}, smaller than the first QuadoptReport ({REPORT_V1_SIZE} bytes)"
            ),
        ));
    }
    Ok(Some(declared.min(ours)))
}

/// Writes the first `bytes` bytes of `value` to `report`, with `struct_size = bytes`.
///
/// # Safety
/// `report` must be aligned and point to at least `bytes <= sizeof(QuadoptReport)` writable
/// bytes (checked by [`report_size`] from the caller's declaration).
pub(super) unsafe fn write_report(report: *mut QuadoptReport, mut value: QuadoptReport, bytes: usize) {
    value.struct_size = bytes as u32;
    // SAFETY: `bytes` <= size_of::<QuadoptReport>() so the source read stays inside `value`;
    // the destination holds `bytes` writable bytes by this function's contract; `value` is a
    // local, so the two cannot overlap.
    unsafe { std::ptr::copy_nonoverlapping((&raw const value).cast::<u8>(), report.cast::<u8>(), bytes) };
}

pub(super) fn quality_of(s: &QualityStats) -> QuadoptQuality {
    QuadoptQuality { min: s.min, avg: s.avg, max: s.max, inverted: s.inverted }
}

/// The statistics of one face kind: `count` faces whose statistics are `stats` (`None` when
/// there are none, then NaN).
fn kind_of(count: usize, stats: Option<QualityStats>) -> QuadoptFaceKindQuality {
    match stats {
        Some(s) if count > 0 => QuadoptFaceKindQuality { count, min: s.min, avg: s.avg },
        _ => QuadoptFaceKindQuality { count, min: f64::NAN, avg: f64::NAN },
    }
}

/// The quads' and the triangles' statistics of `k`.
fn kinds_of(k: &ByFaceKind) -> (QuadoptFaceKindQuality, QuadoptFaceKindQuality) {
    (kind_of(k.quad_count, k.quads), kind_of(k.triangle_count, k.triangles))
}

pub(super) fn report_of(r: &Report) -> QuadoptReport {
    let (input_quads, input_triangles) = kinds_of(&r.input_by_kind);
    let (output_quads, output_triangles) = kinds_of(&r.output_by_kind);
    let count = |mode| r.loop_modes.iter().filter(|&&m| m == mode).count();
    QuadoptReport {
        struct_size: size_of::<QuadoptReport>() as u32,
        converged: u32::from(r.converged),
        input: quality_of(&r.input),
        output: quality_of(&r.output),
        iterations: r.iterations,
        untangle_sweeps: r.untangle_sweeps,
        reoriented_quads: r.reoriented_quads,
        corners: r.corners,
        movable: r.movable,
        tangled_quads: r.tangled.len(),
        initial_energy: r.initial_energy,
        final_energy: r.final_energy,
        seconds: r.seconds,
        max_boundary_deviation: r.fidelity.max_deviation,
        hausdorff: r.fidelity.hausdorff,
        max_boundary_deviation_relative: r.fidelity.max_deviation_relative,
        hausdorff_relative: r.fidelity.hausdorff_relative,
        loops_slide: count(BoundaryMode::Slide),
        loops_snap: count(BoundaryMode::Snap),
        loops_fixed: count(BoundaryMode::Fixed),
        max_min: u32::from(r.max_min.is_some()),
        reserved1: 0,
        sweeps: quality_of(&r.max_min.map_or(r.output, |g| g.before)),
        effort: QuadoptEffort::of(r.effort) as u32,
        reserved2: 0,
        input_quads,
        input_triangles,
        output_quads,
        output_triangles,
        surface: 0,
        reserved3: 0,
        input_verdict: quality_of(&r.input),
        output_verdict: quality_of(&r.output),
        max_distance: 0.0,
        max_distance_relative: 0.0,
        max_feature_distance: r.fidelity.max_deviation,
        max_feature_distance_relative: r.fidelity.max_deviation_relative,
        feature_curves: 0,
        patches: 0,
    }
}

/// The report of a run on a surface (see [`QuadoptReport`] for the fields a planar run fills
/// otherwise). `sweep_cap` is the run's cap on sweeps, `reoriented` the faces the mesh
/// reversed to make its orientation consistent.
pub(super) fn surface_report_of(r: &SurfaceReport, sweep_cap: usize, reoriented: usize) -> QuadoptReport {
    let (input_quads, input_triangles) = kinds_of(&r.input_by_kind);
    let (output_quads, output_triangles) = kinds_of(&r.output_by_kind);
    let f = &r.fidelity;
    QuadoptReport {
        struct_size: size_of::<QuadoptReport>() as u32,
        converged: u32::from(r.iterations < sweep_cap),
        input: quality_of(&r.input),
        output: quality_of(&r.output),
        iterations: r.iterations,
        untangle_sweeps: r.untangle_sweeps,
        reoriented_quads: reoriented,
        corners: r.corners,
        movable: r.movable,
        tangled_quads: r.output.inverted,
        initial_energy: f64::NAN,
        final_energy: f64::NAN,
        seconds: r.seconds,
        max_boundary_deviation: f.max_curve_deviation,
        hausdorff: f64::NAN,
        max_boundary_deviation_relative: f.max_curve_deviation_relative(),
        hausdorff_relative: f64::NAN,
        loops_slide: 0,
        loops_snap: 0,
        loops_fixed: 0,
        max_min: u32::from(r.max_min.is_some()),
        reserved1: 0,
        sweeps: quality_of(&r.max_min.map_or(r.output, |g| g.before)),
        effort: QuadoptEffort::of(r.effort) as u32,
        reserved2: 0,
        input_quads,
        input_triangles,
        output_quads,
        output_triangles,
        surface: 1,
        reserved3: 0,
        input_verdict: quality_of(&r.input_verdict),
        output_verdict: quality_of(&r.output_verdict),
        max_distance: f.max_distance,
        max_distance_relative: f.max_distance_relative(),
        max_feature_distance: f.max_feature_distance,
        max_feature_distance_relative: f.max_feature_distance_relative(),
        feature_curves: r.feature_curves,
        patches: r.patches,
    }
}

/// A zeroed report with `struct_size = sizeof(QuadoptReport)`, ready to pass to an optimize
/// function. By value, so only safe with this version of the header; across versions zero
/// your own `QuadoptReport` and set its `struct_size = sizeof(QuadoptReport)`.
#[unsafe(no_mangle)]
pub extern "C" fn quadopt_report_init() -> QuadoptReport {
    let init =
        || QuadoptReport { struct_size: size_of::<QuadoptReport>() as u32, ..QuadoptReport::default() };
    boundary_or(init(), init)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ffi::test_support::*;
    use crate::ffi::*;
    use std::ptr::null;

    #[test]
    fn larger_structs_from_newer_callers_are_read_and_written_by_prefix() {
        /// A caller compiled against a future header: the v1 struct plus new fields.
        #[repr(C)]
        #[derive(Clone, Copy)]
        struct Newer<T: Copy> {
            v1: T,
            extra: [u64; 4],
        }
        let (coords, quads) = patch(2);
        let mut options = Newer { v1: fixed_boundary_options(), extra: [u64::MAX; 4] };
        options.v1.struct_size = size_of::<Newer<QuadoptOptions>>() as u32;
        let mut report = Newer { v1: sentinel_report(), extra: [0x1234_5678; 4] };
        report.v1.struct_size = size_of::<Newer<QuadoptReport>>() as u32;
        let mut c = coords.clone();
        // SAFETY: both structs hold at least the bytes they declare.
        let status = unsafe {
            quadopt_optimize(
                c.as_mut_ptr(),
                2,
                9,
                quads.as_ptr(),
                4,
                null(),
                (&raw const options).cast(),
                (&raw mut report).cast(),
            )
        };
        assert_eq!(status, QuadoptStatus::Ok, "{}", last_error());
        assert_eq!(report.extra, [0x1234_5678; 4], "bytes beyond this version's report were written");
        assert_eq!(report.v1.struct_size as usize, size_of::<QuadoptReport>(), "bytes filled");
        assert_eq!(report.v1.loops_fixed, 1);
        assert!((c[8] - 1.0).abs() < 1e-3);
    }

    #[test]
    fn older_report_sizes_are_filled_by_prefix_and_get_no_per_kind_fields() {
        for size in [REPORT_V1_SIZE, REPORT_V2_SIZE, REPORT_V3_SIZE] {
            let (coords, quads) = patch(2);
            let mut report = QuadoptReport { struct_size: size as u32, ..sentinel_report() };
            report.input_quads.count = 0xDEAD;
            report.output_triangles.min = -9.0;
            let untouched = bytes_of(&report)[size..].to_vec();
            let mut c = coords.clone();
            let o = fixed_boundary_options();
            // SAFETY: live buffers; the report holds more than its declared bytes.
            let s =
                unsafe { quadopt_optimize(c.as_mut_ptr(), 2, 9, quads.as_ptr(), 4, null(), &o, &mut report) };
            assert_eq!(s, QuadoptStatus::Ok, "{}", last_error());
            assert_eq!(report.struct_size as usize, size, "bytes filled");
            assert_eq!(report.output.inverted, 0);
            assert_eq!(
                bytes_of(&report)[size..],
                untouched[..],
                "bytes beyond struct_size {size} were written"
            );
        }
    }

    #[test]
    fn the_per_kind_fields_split_a_quad_mesh_and_nan_the_absent_kind() {
        let (mut coords, quads) = patch(2);
        let mut r = quadopt_report_init();
        let o = fixed_boundary_options();
        // SAFETY: live buffers of the stated lengths.
        let s = unsafe { quadopt_optimize(coords.as_mut_ptr(), 2, 9, quads.as_ptr(), 4, null(), &o, &mut r) };
        assert_eq!(s, QuadoptStatus::Ok, "{}", last_error());
        assert_eq!((r.input_quads.count, r.output_quads.count), (4, 4));
        assert_eq!((r.input_quads.min, r.input_quads.avg), (r.input.min, r.input.avg));
        assert_eq!((r.output_quads.min, r.output_quads.avg), (r.output.min, r.output.avg));
        for t in [r.input_triangles, r.output_triangles] {
            assert_eq!(t.count, 0);
            assert!(t.min.is_nan() && t.avg.is_nan(), "{t:?}");
        }
    }

    #[test]
    fn per_kind_statistics_convert_with_nan_for_an_absent_kind() {
        let faces = [[0, 1, 2, 3], crate::face::triangle(1, 4, 2), crate::face::triangle(2, 4, 5)];
        let k = ByFaceKind::new(&faces, &[0.5, 0.25, 0.75]);
        let (q, t) = kinds_of(&k);
        assert_eq!(q, QuadoptFaceKindQuality { count: 1, min: 0.5, avg: 0.5 });
        assert_eq!(t, QuadoptFaceKindQuality { count: 2, min: 0.25, avg: 0.5 });
        let (q, t) = kinds_of(&ByFaceKind::new(&faces[1..], &[0.25, 0.75]));
        assert_eq!((q.count, t.count), (0, 2));
        assert!(q.min.is_nan() && q.avg.is_nan());
    }

    #[test]
    fn report_init_is_zeroed_with_struct_size() {
        let r = quadopt_report_init();
        assert_eq!(r.struct_size as usize, size_of::<QuadoptReport>());
        assert_eq!(bytes_of(&r)[4..], vec![0; size_of::<QuadoptReport>() - 4][..]);
    }

    #[test]
    fn struct_layouts_have_no_padding_on_64_bit() {
        // The spec's field order packs without holes on LP64 (checked so that the byte copies
        // of the prefix protocol never copy padding, and as a guard against reordering).
        if size_of::<usize>() == 8 {
            assert_eq!(size_of::<QuadoptOptions>(), 96);
            assert_eq!(size_of::<QuadoptReport>(), 464);
            assert_eq!(REPORT_V3_SIZE, 344, "the report before the surface fields");
            assert_eq!(std::mem::offset_of!(QuadoptReport, input_verdict), 352);
            assert_eq!(std::mem::offset_of!(QuadoptReport, patches), 456);
            assert_eq!(size_of::<QuadoptFaceKindQuality>(), 24);
            assert_eq!(REPORT_V2_SIZE, 248, "0.2's report");
            assert_eq!(std::mem::offset_of!(QuadoptReport, output_triangles), 320);
            assert_eq!(size_of::<QuadoptQuality>(), 32);
            assert_eq!(size_of::<QuadoptProgress>(), 48);
            assert_eq!(std::mem::offset_of!(QuadoptOptions, progress), 64);
            assert_eq!(std::mem::offset_of!(QuadoptReport, loops_fixed), 192);
            assert_eq!(std::mem::offset_of!(QuadoptOptions, max_min), 80);
            assert_eq!(std::mem::offset_of!(QuadoptReport, sweeps), 208);
            assert_eq!(std::mem::offset_of!(QuadoptOptions, effort), 88);
            assert_eq!(std::mem::offset_of!(QuadoptReport, effort), 240);
        }
        assert_eq!(size_of::<QuadoptStatus>(), size_of::<std::ffi::c_int>());
    }
}
