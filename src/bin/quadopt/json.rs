//! Pieces of the `--json` outputs that several commands share.

use quadopt::quality::ByFaceKind;
use quadopt::{QualityStats, Report};
use serde_json::{Value, json};

/// A quality summary as JSON.
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

/// The guarantees-related part of a report, shared by the JSON outputs.
pub fn report_json(r: &Report) -> Value {
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
