//! `quadopt optimize IN -o OUT`: optimize a mesh, write it (and optionally a before/after
//! picture), report the run.

use crate::annotation::{annotate, corner_flags};
use crate::cli::{EncodingArgs, OptArgs};
use crate::fail::Fail;
use crate::mesh_files::{Curved, Input, Loaded, MeshWriter, load_input, marked_edges};
use crate::picture;
use crate::picture_files::{PictureFormat, write_picture};
use crate::plural::{count, face_words, faces};
use crate::progress::{run, run_surface};
use crate::stdout::{is_stdout, report_on_stderr_if_written_to_stdout};
use crate::surface_report;
use quadopt::io::Format;
use quadopt::surface::SurfaceOptimizer;
use quadopt::{Optimizer, Options, Report};
use serde_json::json;
use std::path::Path;

pub fn optimize(
    input: &Path,
    output: &Path,
    format: Option<Format>,
    encoding: &EncodingArgs,
    opts: &OptArgs,
    picture: Option<&Path>,
    as_json: bool,
) -> Result<(), Fail> {
    let options = opts.options()?;
    if picture.is_some_and(is_stdout) {
        return Err(Fail::Usage("--picture needs a file name (- is where draw writes to stdout)".into()));
    }
    let picture_format = picture.map(PictureFormat::of).transpose()?;
    let writer = MeshWriter::for_output(output, format, Format::from_path(input).ok())?;
    let Loaded { mut data, mut planar } = match load_input(input, &opts.fix_physical)? {
        Input::Planar(loaded) => {
            opts.check_planar()?;
            loaded
        }
        Input::Curved(curved) => {
            let out =
                Output { path: output, writer, encoding, picture: picture.zip(picture_format), as_json };
            return optimize_surface(input, curved, &options, opts, out);
        }
    };
    // Before the optimizer's topology exists, so that the run's peak memory is not raised.
    let corners = corner_flags(&planar.mesh, &options);
    // `write_back` puts the quads back: meanwhile the file's copy is 16 bytes a quad for
    // nothing, as is the topology once the run is over (the writers need memory too).
    data.quads = Vec::new();
    // The input as it was, for the picture only (a copy of the 2D mesh).
    let before =
        picture.map(|_| planar.mesh.try_clone()).transpose().map_err(|e| Fail::Other(e.to_string()))?;
    let optimizer = Optimizer::new(&planar.mesh);
    let report = run(&optimizer, &mut planar.mesh, &options, !as_json)?;
    drop(optimizer);
    if let (Some(path), Some(f), Some(before)) = (picture, picture_format, &before) {
        let title = input.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        let headings = [
            "input".to_string(),
            format!("optimized ({}, {})", options.method.name(), options.boundary.name()),
        ];
        let p = picture::layout::before_after(
            before,
            &planar.mesh,
            &title,
            headings.each_ref().map(String::as_str),
        );
        write_picture(path, f, &p)?;
    }
    drop(before);
    let moved = planar.write_back(&mut data);
    annotate(&mut data, &planar, corners);
    encoding.apply(&mut data);
    writer.write(output, &data)?;
    report_on_stderr_if_written_to_stdout(output);
    let mixed = report.output_by_kind.triangle_count > 0;
    if as_json {
        let mut v =
            quadopt::json::optimize_report(&report, &options, moved, data.points.len(), data.quads.len());
        v["input_file"] = json!(input.display().to_string());
        v["output_file"] = json!(output.display().to_string());
        if let Some(path) = picture {
            v["picture_file"] = json!(path.display().to_string());
        }
        outln!("{v}");
        return Ok(());
    }
    outln!(
        "{}: {}, {}",
        input.display(),
        count(data.points.len(), "vertex", "vertices"),
        faces(report.output_by_kind.quad_count, report.output_by_kind.triangle_count)
    );
    outln!(
        "method {}, boundary {}, effort {}",
        options.method.name(),
        options.boundary.name(),
        report.effort
    );
    // A mesh with triangles has a row per face kind under the input's and the output's, and a
    // wider first column for their names.
    let w = if mixed { 11 } else { 8 };
    outln!("{:w$} {:>9} {:>9} {:>9} {:>9}", "", "min", "avg", "max", "inverted");
    let sweeps = report.max_min.map(|g| ("sweeps", g.before, None));
    let rows = [("input", report.input, Some(&report.input_by_kind))].into_iter().chain(sweeps).chain([(
        "output",
        report.output,
        Some(&report.output_by_kind),
    )]);
    for (name, s, kinds) in rows {
        outln!("{name:w$} {:>9.4} {:>9.4} {:>9.4} {:>9}", s.min, s.avg, s.max, s.inverted);
        if let Some(k) = kinds.filter(|_| mixed) {
            for (kind, s) in [("  quads", k.quads), ("  triangles", k.triangles)] {
                match s {
                    Some(s) => {
                        outln!("{kind:w$} {:>9.4} {:>9.4} {:>9.4} {:>9}", s.min, s.avg, s.max, s.inverted)
                    }
                    None => outln!("{kind:w$} {:>9} {:>9} {:>9} {:>9}", "-", "-", "-", 0),
                }
            }
        }
    }
    outln!(
        "{} ({}), {:.3} s; {}, {}, {moved} moved, {} reoriented",
        count(report.iterations, "iteration", "iterations"),
        if report.converged { "converged" } else { "iteration cap" },
        report.seconds,
        count(report.corners, "corner", "corners"),
        count(report.movable, "movable vertex", "movable vertices"),
        count(report.reoriented_quads, face_words(mixed).0, face_words(mixed).1)
    );
    let f = &report.fidelity;
    let modes: Vec<&str> = report.loop_modes.iter().map(|m| m.name()).collect();
    outln!(
        "boundary: modes per loop [{}]; largest deviation {:.3e} ({:.3e} of the mean edge), Hausdorff {:.3e} ({:.3e})",
        modes.join(", "),
        f.max_deviation,
        f.max_deviation_relative,
        f.hausdorff,
        f.hausdorff_relative
    );
    print_tangled(&report, mixed);
    if let Some(path) = picture {
        outln!("wrote the picture {}", path.display());
    }
    if is_stdout(output) {
        outln!("wrote the mesh to stdout");
    } else {
        outln!("wrote {}", output.display());
    }
    Ok(())
}

/// One line per face still inverted, with the reason ("quad" for a pure quad mesh, "face" for
/// a mesh with triangles).
fn print_tangled(r: &Report, mixed: bool) {
    let (one, _) = face_words(mixed);
    if !r.tangled.is_empty() {
        outln!("still inverted ({one} numbers are 0-based):");
    }
    for t in r.tangled.iter().take(20) {
        outln!("  {one} {}: {}", t.quad, t.reason.describe());
    }
    if r.tangled.len() > 20 {
        outln!("  ... and {} more", r.tangled.len() - 20);
    }
}

/// Where `optimize` writes.
struct Output<'a> {
    path: &'a Path,
    writer: MeshWriter,
    encoding: &'a EncodingArgs,
    picture: Option<(&'a Path, PictureFormat)>,
    as_json: bool,
}

/// `optimize` for a mesh on a curved surface: every vertex stays on the input surface (and a
/// feature vertex on its curve); the written mesh keeps the file's faces and 3D coordinates.
fn optimize_surface(
    input: &Path,
    curved: Curved,
    options: &Options,
    opts: &OptArgs,
    out: Output,
) -> Result<(), Fail> {
    let Curved { mut data, mut surface } = curved;
    let marked = marked_edges(&data, &surface, opts.feature_edges.as_deref(), &opts.feature_physical)?;
    let setup = std::time::Instant::now();
    let optimizer = SurfaceOptimizer::new(&surface, options.feature_angle_deg, &marked)
        .map_err(|e| Fail::Other(format!("{}: {e}", input.display())))?;
    let setup_seconds = setup.elapsed().as_secs_f64();
    let before = out.picture.map(|_| surface.clone());
    let report = run_surface(&optimizer, &mut surface, options, !out.as_json)?;
    if let (Some((path, format)), Some(before)) = (out.picture, &before) {
        let title = input.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        let headings = [
            "input".to_string(),
            format!("optimized ({}, effort {})", options.method.name(), options.effort),
        ];
        let p = picture::surface::before_after(
            (before, &optimizer.measure(before.points())?.values),
            (&surface, &report.output_values),
            &title,
            headings.each_ref().map(String::as_str),
        );
        write_picture(path, format, &p)?;
    }
    let mut moved = 0;
    for (p, q) in data.points.iter_mut().zip(surface.points()) {
        let q = q.to_array();
        if *p != q {
            *p = q;
            moved += 1;
        }
    }
    // The run's own values of its output: what its report summarizes.
    surface_report::annotate(&mut data, &optimizer, &report.output_values, surface.fixed());
    out.encoding.apply(&mut data);
    out.writer.write(out.path, &data)?;
    report_on_stderr_if_written_to_stdout(out.path);
    let mixed = report.output_by_kind.triangle_count > 0;
    if out.as_json {
        // "setup_seconds": building the features, patches and reference trees, before the run.
        let mut v = quadopt::json::surface_optimize_report(
            &report,
            options,
            moved,
            setup_seconds,
            data.points.len(),
            data.quads.len(),
        );
        v["input_file"] = json!(input.display().to_string());
        v["output_file"] = json!(out.path.display().to_string());
        if let Some((path, _)) = out.picture {
            v["picture_file"] = json!(path.display().to_string());
        }
        outln!("{v}");
        return Ok(());
    }
    outln!(
        "{}: {}, {}, on a curved surface",
        input.display(),
        count(data.points.len(), "vertex", "vertices"),
        faces(report.output_by_kind.quad_count, report.output_by_kind.triangle_count)
    );
    outln!(
        "method {}, feature curves {}, effort {}",
        options.method.name(),
        if options.boundary == quadopt::BoundaryMode::Fixed { "fixed" } else { "slide" },
        report.effort
    );
    surface_report::print_report(&report, moved);
    if mixed {
        outln!("input by face kind (signed):");
        super::quality::print_kinds(&report.input_by_kind);
        outln!("output by face kind (signed):");
        super::quality::print_kinds(&report.output_by_kind);
    }
    if let Some((path, _)) = out.picture {
        outln!("wrote the picture {}", path.display());
    }
    if is_stdout(out.path) {
        outln!("wrote the mesh to stdout");
    } else {
        outln!("wrote {}", out.path.display());
    }
    Ok(())
}
