//! Reports of meshes on curved surfaces: the two measures (the signed one the optimizer ranks
//! by, and Verdict's 3D one) and the distances from the input surface, as text (their JSON is
//! `quadopt::json`'s).

use crate::plural::count;
use quadopt::QualityStats;
use quadopt::io::MeshData;
use quadopt::surface::{SurfaceFidelity, SurfaceOptimizer, SurfaceReport, VertexRole};

/// One line of statistics under a label.
fn line(label: &str, s: &QualityStats) {
    outln!("  {label:34} min {:>7.4}, avg {:.4}, max {:.4}; {} inverted", s.min, s.avg, s.max, s.inverted);
}

/// A surface run as text.
pub fn print_report(r: &SurfaceReport, moved: usize) {
    outln!("scaled Jacobian:");
    line("input, signed against the surface", &r.input);
    line("output, signed against the surface", &r.output);
    line("input, Verdict (3D)", &r.input_verdict);
    line("output, Verdict (3D)", &r.output_verdict);
    outln!(
        "{}, {} untangling, {:.3} s; {} patches, {}, {}, {}, {moved} moved",
        count(r.iterations, "sweep", "sweeps"),
        count(r.untangle_sweeps, "sweep", "sweeps"),
        r.seconds,
        r.patches,
        count(r.feature_curves, "feature curve", "feature curves"),
        count(r.corners, "corner", "corners"),
        count(r.movable, "movable vertex", "movable vertices"),
    );
    print_fidelity(&r.fidelity);
}

/// The distances as text.
pub fn print_fidelity(f: &SurfaceFidelity) {
    outln!(
        "surface: largest distance from the input surface {:.3e} ({:.3e} of the mean edge), of a feature vertex from its curve {:.3e} ({:.3e}), of a curve's new edge from its curve {:.3e} ({:.3e})",
        f.max_distance,
        f.max_distance_relative(),
        f.max_feature_distance,
        f.max_feature_distance_relative(),
        f.max_curve_deviation,
        f.max_curve_deviation_relative()
    );
}

/// Adds what viewers colour by to `data`: each face's signed scaled Jacobian, the fixed flags
/// and the corners (feature corners and fixed vertices).
pub fn annotate(data: &mut MeshData, optimizer: &SurfaceOptimizer, values: &[f64], fixed: &[bool]) {
    data.quality = Some(values.to_vec());
    data.fixed = Some(fixed.to_vec());
    data.corner = Some(optimizer.features().roles().iter().map(|r| *r == VertexRole::Corner).collect());
}
