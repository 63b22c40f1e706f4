//! `quadopt` with no arguments: optimizes every bundled sample mesh and prints a report like
//! the paper's Table 1.

use crate::fail::Fail;
use crate::mesh_files::{Curved, Input, Loaded, load_input};
use crate::plural::count;
use crate::progress::{run, run_surface};
use quadopt::io::Format;
use quadopt::quality::ByFaceKind;
use quadopt::surface::SurfaceOptimizer;
use quadopt::{Optimizer, Options, QualityStats};
use std::path::{Path, PathBuf};

/// The bundled sample meshes: `data/` of the crate, else `./data`.
fn data_dir() -> PathBuf {
    let bundled = Path::new(env!("CARGO_MANIFEST_DIR")).join("data");
    if bundled.is_dir() { bundled } else { PathBuf::from("data") }
}

pub fn run_data_dir() -> Result<(), Fail> {
    let dir = data_dir();
    let mut files: Vec<PathBuf> = match std::fs::read_dir(&dir) {
        Ok(entries) => entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.is_file() && Format::from_path(p).is_ok())
            .collect(),
        Err(e) => {
            return Err(Fail::Other(format!(
                "no sample meshes: cannot read the data directory {}: {e} (run `quadopt --help` for the commands)",
                dir.display()
            )));
        }
    };
    if files.is_empty() {
        return Err(Fail::Other(format!(
            "no sample meshes (.obj, .off, .vtk, .msh, .vtu) in {} (run `quadopt --help` for the commands)",
            dir.display()
        )));
    }
    files.sort();
    let options = Options::default();
    // Relative to the working directory when inside it: what a user would type.
    let shown =
        std::env::current_dir().ok().and_then(|cwd| dir.strip_prefix(cwd).ok().map(Path::to_path_buf));
    outln!(
        "quadopt: {} in {}, method {}, boundary {}",
        count(files.len(), "mesh", "meshes"),
        shown.as_deref().unwrap_or(&dir).display(),
        options.method.name(),
        options.boundary.name()
    );
    outln!(
        "{:28} {:>7} {:>7}  {:>23}  {:>23}  {:>9} {:>6} {:>8}",
        "model",
        "#V",
        "#F",
        "input min/avg/max",
        "output min/avg/max",
        "inverted",
        "iters",
        "time (s)"
    );
    let mut failed = 0;
    let mut surfaces = Vec::new();
    for path in &files {
        let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        let result = load_input(path, &[]).and_then(|input| match input {
            Input::Planar(Loaded { data, mut planar }) => {
                let r = run(&Optimizer::new(&planar.mesh), &mut planar.mesh, &options, true)?;
                Ok((
                    data,
                    Row {
                        input: r.input,
                        output: r.output,
                        kinds: (r.input_by_kind, r.output_by_kind),
                        iterations: r.iterations,
                        seconds: r.seconds,
                    },
                    None,
                ))
            }
            Input::Curved(Curved { data, mut surface }) => {
                let optimizer = SurfaceOptimizer::new(&surface, options.feature_angle_deg, &[])
                    .map_err(|e| Fail::Other(e.to_string()))?;
                let r = run_surface(&optimizer, &mut surface, &options, true)?;
                let row = Row {
                    input: r.input,
                    output: r.output,
                    kinds: (r.input_by_kind, r.output_by_kind),
                    iterations: r.iterations,
                    seconds: r.seconds,
                };
                Ok((data, row, Some((r.fidelity.max_distance_relative(), r.output_verdict))))
            }
        });
        match result {
            Ok((data, r, surface)) => {
                let (i, o) = (&r.input, &r.output);
                outln!(
                    "{name:28} {:>7} {:>7}  {:>7.3} {:>7.3} {:>7.3}  {:>7.3} {:>7.3} {:>7.3}  {:>4}->{:<4} {:>6} {:>8.3}",
                    data.points.len(),
                    data.quads.len(),
                    i.min,
                    i.avg,
                    i.max,
                    o.min,
                    o.avg,
                    o.max,
                    i.inverted,
                    o.inverted,
                    r.iterations,
                    r.seconds
                );
                // A mesh with triangles: a row per face kind under the mesh's (its count under #F).
                if r.kinds.0.triangle_count > 0 {
                    print_kinds(&r.kinds.0, &r.kinds.1);
                }
                // On a curved surface: the output's Verdict minimum and distance from the input
                // surface, under the table.
                if let Some((distance, verdict)) = surface {
                    surfaces.push((name, distance, verdict));
                }
            }
            Err(Fail::Usage(m) | Fail::Other(m)) => {
                failed += 1;
                outln!("{name:28} error: {m}");
            }
        }
    }
    if !surfaces.is_empty() {
        outln!(
            "on curved surfaces: min/avg/max signed against the surface's normal; the output's Verdict (3D) minimum and largest distance from the input surface (relative to the mean edge):"
        );
        for (name, distance, verdict) in &surfaces {
            outln!("  {name:26} Verdict min {:.3}, distance {distance:.1e}", verdict.min);
        }
    }
    if failed > 0 {
        return Err(Fail::Other(format!(
            "{failed} of {} could not be optimized",
            count(files.len(), "mesh", "meshes")
        )));
    }
    Ok(())
}

/// The rows of each face kind of a mesh with triangles: count, then input and output min / avg
/// / max and inverted counts, in the columns of the mesh's row ("-" for a kind it has none of).
fn print_kinds(input: &ByFaceKind, output: &ByFaceKind) {
    let three = |s: Option<QualityStats>| match s {
        Some(s) => format!("{:>7.3} {:>7.3} {:>7.3}", s.min, s.avg, s.max),
        None => format!("{:>7} {:>7} {:>7}", "-", "-", "-"),
    };
    let inverted = |s: Option<QualityStats>| s.map_or(0, |s| s.inverted);
    let kinds: [(&str, usize, KindStats); 2] =
        [("  quads", input.quad_count, |k| k.quads), ("  triangles", input.triangle_count, |k| k.triangles)];
    for (name, n, stats) in kinds {
        let (i, o) = (stats(input), stats(output));
        let row = format!(
            "{name:28} {:>7} {n:>7}  {}  {}  {:>4}->{:<4}",
            "",
            three(i),
            three(o),
            inverted(i),
            inverted(o)
        );
        outln!("{}", row.trim_end());
    }
}

/// One face kind's statistics out of a [`ByFaceKind`].
type KindStats = fn(&ByFaceKind) -> Option<QualityStats>;

/// A sample's row: the signed statistics before and after, per face kind, the sweeps and time.
struct Row {
    input: QualityStats,
    output: QualityStats,
    kinds: (ByFaceKind, ByFaceKind),
    iterations: usize,
    seconds: f64,
}
