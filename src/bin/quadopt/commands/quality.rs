//! `quadopt quality IN`: the quality of a mesh and its histogram; with `-o`, the mesh
//! annotated with its quality and flags.

use crate::annotation::{annotate, corner_flags};
use crate::cli::EncodingArgs;
use crate::fail::Fail;
use crate::json::{by_kind_json, stats_json};
use crate::mesh_files::{Loaded, Measured, MeshWriter, load_measured};
use crate::picture;
use crate::plural::{count, faces as faces_phrase};
use crate::stdout::report_on_stderr_if_written_to_stdout;
use quadopt::io::Format;
use quadopt::quality::ByFaceKind;
use quadopt::{Options, QualityStats};
use serde_json::json;
use std::path::Path;

pub fn quality(
    input: &Path,
    output: Option<&Path>,
    format: Option<Format>,
    encoding: &EncodingArgs,
    as_json: bool,
) -> Result<(), Fail> {
    let (mut data, faces, values, verdict) = match load_measured(input)? {
        Measured::Planar(Loaded { mut data, planar }) => {
            let values = planar.mesh.quality_values();
            if output.is_some() {
                let corners = corner_flags(&planar.mesh, &Options::default());
                annotate(&mut data, &planar, corners);
            }
            (data, planar.mesh.faces().to_vec(), values, None)
        }
        // A mesh on a curved surface: Verdict's 3D scaled Jacobian (what VTK's vtkMeshQuality
        // prints) next to the value the optimizer ranks by, each corner signed against the
        // surface's normal there (the input's area-weighted vertex normal), so a fold counts
        // as inverted. The signed values are the main statistics, the histogram and -o's
        // array. Such meshes are measured, not yet optimized.
        Measured::Curved { mut data, surface } => {
            let values = surface.signed_quality_values();
            let verdict = QualityStats::from_values(&surface.verdict_quality_values());
            data.quality = Some(values.clone());
            (data, surface.faces().to_vec(), values, Some(verdict))
        }
    };
    if let Some(output) = output {
        encoding.apply(&mut data);
        MeshWriter::for_output(output, format, Format::from_path(input).ok())?.write(output, &data)?;
        // The mesh went to stdout: the report goes to stderr.
        report_on_stderr_if_written_to_stdout(output);
    }
    let s = QualityStats::from_values(&values);
    let h = picture::histogram(&values);
    // Per face kind only for a mesh with triangles: a quad mesh's report is as it was.
    let kinds = ByFaceKind::new(&faces, &values);
    let mixed = kinds.triangle_count > 0;
    if as_json {
        let mut v = stats_json(&s);
        v["file"] = json!(input.display().to_string());
        v["vertices"] = json!(data.points.len());
        v["quads"] = json!(kinds.quad_count);
        if mixed {
            v["triangles"] = json!(kinds.triangle_count);
            v["faces"] = json!(values.len());
            v["by_kind"] = by_kind_json(&kinds);
        }
        if let Some(verdict) = &verdict {
            v["surface"] = json!(true);
            v["verdict"] = stats_json(verdict);
        }
        v["histogram"] = json!(h);
        outln!("{v}");
        return Ok(());
    }
    let curved = if verdict.is_some() { ", on a curved surface (measured; not optimized yet)" } else { "" };
    outln!(
        "{}: {}, {}{curved}",
        input.display(),
        count(data.points.len(), "vertex", "vertices"),
        faces_phrase(kinds.quad_count, kinds.triangle_count)
    );
    let line = |label: &str, s: &QualityStats| {
        outln!("{label}: min {:.4}, avg {:.4}, max {:.4}; {} inverted", s.min, s.avg, s.max, s.inverted)
    };
    match &verdict {
        None => line("scaled Jacobian", &s),
        Some(verdict) => {
            line("scaled Jacobian (Verdict, 3D)", verdict);
            line("signed against the surface normal", &s);
        }
    }
    if mixed {
        print_kinds(&kinds);
    }
    print_histogram(&h);
    Ok(())
}

/// The histogram's bars, a line per bin.
fn print_histogram(h: &[usize]) {
    let most = h.iter().copied().max().unwrap_or(1).max(1);
    for (i, &count) in h.iter().enumerate() {
        let label = if i == 0 {
            "    <= 0.0".to_string()
        } else {
            format!("({:.1}, {:.1}]", (i - 1) as f64 / 10.0, i as f64 / 10.0)
        };
        let bar = "#".repeat((count * 40).div_ceil(most));
        outln!("  {label:>10} {count:>7} {bar}");
    }
}

/// One line per face kind: its count, min, avg, max and inverted count ("-" for a kind the mesh
/// has none of).
pub fn print_kinds(k: &ByFaceKind) {
    for (name, n, stats) in [("quads", k.quad_count, k.quads), ("triangles", k.triangle_count, k.triangles)] {
        match stats {
            Some(s) => outln!(
                "  {name:9} {n:>7}: min {:.4}, avg {:.4}, max {:.4}; {} inverted",
                s.min,
                s.avg,
                s.max,
                s.inverted
            ),
            None => outln!("  {name:9} {n:>7}"),
        }
    }
}
