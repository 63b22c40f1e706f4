//! `quadopt quality IN`: the quality of a mesh and its histogram; with `-o`, the mesh
//! annotated with its quality and flags.

use crate::annotation::{annotate, corner_flags};
use crate::cli::EncodingArgs;
use crate::fail::Fail;
use crate::mesh_files::{Curved, Input, Loaded, MeshWriter, load_input};
use crate::picture;
use crate::plural::{count, faces as faces_phrase};
use crate::stdout::report_on_stderr_if_written_to_stdout;
use crate::surface_report;
use quadopt::io::Format;
use quadopt::quality::ByFaceKind;
use quadopt::surface::{SurfaceMesh, SurfaceOptimizer};
use quadopt::{Options, QualityStats};
use serde_json::json;
use std::path::Path;

pub fn quality(
    input: &Path,
    reference: Option<&Path>,
    output: Option<&Path>,
    format: Option<Format>,
    encoding: &EncodingArgs,
    as_json: bool,
) -> Result<(), Fail> {
    let mut surface = None;
    let (mut data, faces, values) = match load_input(input, &[])? {
        Input::Planar(Loaded { mut data, planar }) => {
            if reference.is_some() {
                return Err(Fail::Usage(format!(
                    "--reference measures a mesh on a curved surface; {} is planar",
                    input.display()
                )));
            }
            let values = planar.mesh.quality_values();
            if output.is_some() {
                let corners = corner_flags(&planar.mesh, &Options::default());
                annotate(&mut data, &planar, corners);
            }
            (data, planar.mesh.faces().to_vec(), values)
        }
        // A mesh on a curved surface: the signed value the optimizer ranks by (each corner
        // against the normal of the surface there, so a fold counts as inverted) and Verdict's
        // 3D scaled Jacobian (what VTK's vtkMeshQuality prints), against the mesh's own surface
        // or, with --reference, against that mesh's (the same faces: an input whose output
        // this is), with the distances from it.
        Input::Curved(Curved { mut data, surface: mesh }) => {
            let reference_mesh = match reference {
                None => None,
                Some(path) => match load_input(path, &[])? {
                    Input::Curved(Curved { surface: r, .. }) => Some(r),
                    Input::Planar(Loaded { data: r, .. }) => Some(
                        SurfaceMesh::new(
                            r.points.iter().map(|&p| glam::DVec3::from_array(p)).collect(),
                            r.quads.clone(),
                            None,
                        )
                        .map_err(|e| Fail::Other(format!("{}: {e}", path.display())))?,
                    ),
                },
            };
            let base = reference_mesh.as_ref().unwrap_or(&mesh);
            if base.faces() != mesh.faces() {
                return Err(Fail::Other(format!(
                    "{} does not have the faces of the reference {}",
                    input.display(),
                    reference.map_or(String::new(), |r| r.display().to_string())
                )));
            }
            let optimizer = SurfaceOptimizer::new(base, Options::default().feature_angle_deg, &[])
                .map_err(|e| Fail::Other(format!("{}: {e}", input.display())))?;
            let measure = optimizer.measure(mesh.points())?;
            surface_report::annotate(&mut data, &optimizer, &measure.values, mesh.fixed());
            let values = measure.values.clone();
            surface = Some(measure);
            (data, mesh.faces().to_vec(), values)
        }
    };
    if output.is_none() {
        data.quality = None;
    }
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
        let on_surface = surface
            .as_ref()
            .map(|measure| quadopt::json::SurfaceQuality { measure, against_reference: reference.is_some() });
        let mut v = quadopt::json::quality_summary(&values, &faces, data.points.len(), on_surface);
        v["file"] = json!(input.display().to_string());
        outln!("{v}");
        return Ok(());
    }
    let curved = if surface.is_some() { ", on a curved surface" } else { "" };
    outln!(
        "{}: {}, {}{curved}",
        input.display(),
        count(data.points.len(), "vertex", "vertices"),
        faces_phrase(kinds.quad_count, kinds.triangle_count)
    );
    let line = |label: &str, s: &QualityStats| {
        outln!("{label}: min {:.4}, avg {:.4}, max {:.4}; {} inverted", s.min, s.avg, s.max, s.inverted)
    };
    match &surface {
        None => line("scaled Jacobian", &s),
        Some(m) => {
            line("scaled Jacobian (Verdict, 3D)", &m.verdict);
            line("signed against the surface normal", &s);
            if reference.is_some() {
                surface_report::print_fidelity(&m.fidelity);
            }
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
