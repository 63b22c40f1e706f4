//! Reports as JSON: the objects `quadopt optimize --json` and `quadopt quality --json` print,
//! built here so that every interface that reports a run (the CLI, the Python package) gives
//! the same keys and values. The CLI adds the names of the files it read and wrote
//! (`input_file`, `output_file`, `picture_file`, `file`), which only it has.
//!
//! Needs the `json` feature (on with the default `cli` feature). Values are `serde_json`'s:
//! a NaN or infinite statistic (the statistics of no face) is `null`.

use crate::quality::{ByFaceKind, QualityStats, histogram};
use crate::smooth::{Options, Report};
use crate::surface::{SurfaceFidelity, SurfaceMeasure, SurfaceReport};
use serde_json::{Value, json};

/// A quality summary: `{"min", "avg", "max", "inverted"}`.
pub fn stats_json(s: &QualityStats) -> Value {
    json!({ "min": s.min, "avg": s.avg, "max": s.max, "inverted": s.inverted })
}

/// The statistics of each face kind, for a mesh with triangles: `{"quads": {"count", "min",
/// "avg", "max", "inverted"}, "triangles": {...}}`, the statistics null for a kind with no
/// face. A pure quad mesh's outputs have no such key (they stay as they were).
pub fn by_kind_json(k: &ByFaceKind) -> Value {
    let kind = |count: usize, s: Option<QualityStats>| {
        let mut v = s.map_or_else(
            || json!({ "min": null, "avg": null, "max": null, "inverted": 0 }),
            |s| stats_json(&s),
        );
        v["count"] = json!(count);
        v
    };
    json!({ "quads": kind(k.quad_count, k.quads), "triangles": kind(k.triangle_count, k.triangles) })
}

/// The guarantees-related part of a planar run's report.
pub fn guarantees_json(r: &Report) -> Value {
    let f = &r.fidelity;
    json!({
        "effort": r.effort.name(),
        "converged": r.converged,
        "untangle_sweeps": r.untangle_sweeps,
        "loop_modes": r.loop_modes.iter().map(|m| m.name()).collect::<Vec<_>>(),
        "boundary_fidelity": {
            "max_deviation": f.max_deviation, "hausdorff": f.hausdorff,
            "max_deviation_relative": f.max_deviation_relative, "hausdorff_relative": f.hausdorff_relative,
        },
        "tangled": r.tangled.iter().map(|t| json!({ "quad": t.quad, "reason": t.reason.describe() })).collect::<Vec<_>>(),
        "max_min": r.max_min.map(|g| json!({
            "before": stats_json(&g.before), "after": stats_json(&g.after),
            "rounds": g.rounds, "seconds": g.seconds,
        })),
    })
}

/// The report of a planar run, as `quadopt optimize --json` prints it without the file names:
/// `moved` vertices changed position, the mesh has `vertices` vertices and `faces` faces.
pub fn optimize_report(
    report: &Report,
    options: &Options,
    moved: usize,
    vertices: usize,
    faces: usize,
) -> Value {
    let mut v = json!({
        "input": stats_json(&report.input),
        "output": stats_json(&report.output),
        "iterations": report.iterations,
        "seconds": report.seconds,
        "converged": report.converged,
        "corners": report.corners,
        "movable": report.movable,
        "moved": moved,
        "reoriented_quads": report.reoriented_quads,
        "method": options.method.name(),
        "boundary": options.boundary.name(),
        "vertices": vertices,
        "quads": report.output_by_kind.quad_count,
    });
    // Per face kind only for a mesh with triangles: a quad mesh's report is as it was.
    if report.output_by_kind.triangle_count > 0 {
        v["triangles"] = json!(report.output_by_kind.triangle_count);
        v["faces"] = json!(faces);
        v["input_by_kind"] = by_kind_json(&report.input_by_kind);
        v["output_by_kind"] = by_kind_json(&report.output_by_kind);
    }
    if let (Value::Object(v), Value::Object(extra)) = (&mut v, guarantees_json(report)) {
        v.extend(extra);
    }
    v
}

/// The distances of a surface run's output from its input surface.
pub fn fidelity_json(f: &SurfaceFidelity) -> Value {
    json!({
        "max_distance": f.max_distance,
        "max_distance_relative": f.max_distance_relative(),
        "max_feature_distance": f.max_feature_distance,
        "max_feature_distance_relative": f.max_feature_distance_relative(),
        "max_curve_deviation": f.max_curve_deviation,
        "max_curve_deviation_relative": f.max_curve_deviation_relative(),
        "mean_edge": f.mean_edge,
    })
}

/// A surface run's own part of its report: the keys of a planar run's report that apply,
/// `"surface": true`, Verdict's statistics and the distances.
pub fn surface_report_json(r: &SurfaceReport) -> Value {
    let mut v = json!({
        "surface": true,
        "input": stats_json(&r.input),
        "output": stats_json(&r.output),
        "input_verdict": stats_json(&r.input_verdict),
        "output_verdict": stats_json(&r.output_verdict),
        "iterations": r.iterations,
        "untangle_sweeps": r.untangle_sweeps,
        "seconds": r.seconds,
        "effort": r.effort.name(),
        "cancelled": r.cancelled,
        "patches": r.patches,
        "feature_curves": r.feature_curves,
        "corners": r.corners,
        "movable": r.movable,
        "surface_fidelity": fidelity_json(&r.fidelity),
        "max_min": r.max_min.map(|g| json!({
            "before": stats_json(&g.before), "after": stats_json(&g.after),
            "rounds": g.rounds, "seconds": g.seconds,
        })),
    });
    if r.output_by_kind.triangle_count > 0 {
        v["input_by_kind"] = by_kind_json(&r.input_by_kind);
        v["output_by_kind"] = by_kind_json(&r.output_by_kind);
    }
    v
}

/// The report of a run on a curved surface, as `quadopt optimize --json` prints it without the
/// file names: `moved` vertices changed position, `setup_seconds` went into building the
/// optimizer (features, patches, reference trees) before the run, the mesh has `vertices`
/// vertices and `faces` faces.
pub fn surface_optimize_report(
    report: &SurfaceReport,
    options: &Options,
    moved: usize,
    setup_seconds: f64,
    vertices: usize,
    faces: usize,
) -> Value {
    let mut v = surface_report_json(report);
    v["moved"] = json!(moved);
    v["setup_seconds"] = json!(setup_seconds);
    v["method"] = json!(options.method.name());
    v["boundary"] = json!(options.boundary.name());
    v["vertices"] = json!(vertices);
    v["quads"] = json!(report.output_by_kind.quad_count);
    if report.output_by_kind.triangle_count > 0 {
        v["triangles"] = json!(report.output_by_kind.triangle_count);
        v["faces"] = json!(faces);
    }
    v
}

/// What a mesh on a curved surface adds to [`quality_summary`]: its measure, and whether that
/// was taken against another mesh's surface (a reference: then the distances from it are
/// reported too).
#[derive(Clone, Copy, Debug)]
pub struct SurfaceQuality<'a> {
    /// The measure of the mesh.
    pub measure: &'a SurfaceMeasure,
    /// Whether it was taken against a reference surface.
    pub against_reference: bool,
}

/// The quality of a mesh as `quadopt quality --json` prints it without the file name: the
/// statistics of `values` (one per face of `faces`; on a surface, the signed measure), the
/// mesh's `vertices` count and faces, the statistics by face kind for a mesh with triangles,
/// the histogram of [`histogram`]'s bins, and on a curved surface `"surface": true` and
/// Verdict's statistics.
pub fn quality_summary(
    values: &[f64],
    faces: &[[u32; 4]],
    vertices: usize,
    surface: Option<SurfaceQuality>,
) -> Value {
    let s = QualityStats::from_values(values);
    let kinds = ByFaceKind::new(faces, values);
    let mut v = stats_json(&s);
    v["vertices"] = json!(vertices);
    v["quads"] = json!(kinds.quad_count);
    if kinds.triangle_count > 0 {
        v["triangles"] = json!(kinds.triangle_count);
        v["faces"] = json!(values.len());
        v["by_kind"] = by_kind_json(&kinds);
    }
    if let Some(m) = surface {
        v["surface"] = json!(true);
        v["verdict"] = stats_json(&m.measure.verdict);
        if m.against_reference {
            v["surface_fidelity"] = fidelity_json(&m.measure.fidelity);
        }
    }
    v["histogram"] = json!(histogram(values));
    v
}
