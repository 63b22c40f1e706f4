//! `quadopt compare IN...`: every method with a fixed boundary and every boundary mode of the
//! embedded polygon method, side by side for each mesh (the paper's Table 2).

use crate::cli::TuneArgs;
use crate::fail::Fail;
use crate::json::{by_kind_json, stats_json};
use crate::mesh_files::{Curved, Input, Loaded, load_input};
use crate::plural::count;
use crate::progress::{run, run_surface};
use quadopt::quality::ByFaceKind;
use quadopt::surface::SurfaceOptimizer;
use quadopt::{BoundaryMode, Method, Optimizer, Options, QualityStats};
use serde_json::{Value, json};
use std::path::PathBuf;

/// The configurations of the paper's Table 2: every method with a fixed boundary, then the
/// embedded polygon method with each moving boundary mode.
const COMPARE: [(Method, BoundaryMode); 7] = [
    (Method::AngleBased, BoundaryMode::Fixed),
    (Method::Laplacian, BoundaryMode::Fixed),
    (Method::Cotangent, BoundaryMode::Fixed),
    (Method::EmbeddedPolygon, BoundaryMode::Fixed),
    (Method::EmbeddedPolygon, BoundaryMode::Slide),
    (Method::EmbeddedPolygon, BoundaryMode::Snap),
    (Method::EmbeddedPolygon, BoundaryMode::Auto),
];

pub fn compare(inputs: &[PathBuf], tune: &TuneArgs, as_json: bool) -> Result<(), Fail> {
    let configs: Vec<Options> = COMPARE.iter().map(|&(m, b)| tune.options(m, b)).collect::<Result<_, _>>()?;
    let mut rows = Vec::new();
    for input in inputs {
        let row = match load_input(input, &[])? {
            Input::Planar(Loaded { data, planar }) => {
                let optimizer = Optimizer::new(&planar.mesh);
                let mut results = Vec::new();
                for options in &configs {
                    let mut mesh = planar.mesh.clone();
                    let r = run(&optimizer, &mut mesh, options, !as_json)?;
                    results.push(Outcome {
                        output: r.output,
                        by_kind: r.output_by_kind,
                        iterations: r.iterations,
                        seconds: r.seconds,
                        converged: r.converged,
                    });
                }
                let kinds = planar.mesh.quality_by_face_kind();
                (input, data.points.len(), kinds, planar.mesh.quality(), results)
            }
            // On a curved surface, the signed measure; a boundary mode other than fixed slides
            // the feature vertices along their curves.
            Input::Curved(Curved { data, surface }) => {
                let fail = |e: quadopt::Error| Fail::Other(format!("{}: {e}", input.display()));
                let mut results = Vec::new();
                let mut input_stats = None;
                let angle = configs[0].feature_angle_deg;
                let optimizer = SurfaceOptimizer::new(&surface, angle, &[]).map_err(fail)?;
                for options in &configs {
                    let mut mesh = surface.clone();
                    let r = run_surface(&optimizer, &mut mesh, options, !as_json)?;
                    input_stats = Some((r.input_by_kind, r.input));
                    // A surface run converges when the sweeps stop before their cap.
                    let converged = r.iterations < options.sweep_cap();
                    results.push(Outcome {
                        output: r.output,
                        by_kind: r.output_by_kind,
                        iterations: r.iterations,
                        seconds: r.seconds,
                        converged,
                    });
                }
                let (kinds, q) = input_stats.expect("compare runs at least one configuration");
                (input, data.points.len(), kinds, q, results)
            }
        };
        rows.push(row);
    }
    if as_json {
        let meshes: Vec<Value> = rows
            .iter()
            .map(|(input, nv, kinds, q, results)| {
                // Per face kind only for a mesh with triangles: a quad mesh's report is as it was.
                let mixed = kinds.triangle_count > 0;
                let runs: Vec<Value> = results
                    .iter()
                    .zip(&configs)
                    .map(|(r, o)| {
                        let mut run = json!({
                            "method": o.method.name(), "boundary": o.boundary.name(),
                            "output": stats_json(&r.output), "iterations": r.iterations,
                            "seconds": r.seconds, "converged": r.converged,
                        });
                        if mixed {
                            run["output_by_kind"] = by_kind_json(&r.by_kind);
                        }
                        run
                    })
                    .collect();
                let mut mesh = json!({ "file": input.display().to_string(), "vertices": nv,
                        "quads": kinds.quad_count, "input": stats_json(q), "results": runs });
                if mixed {
                    mesh["triangles"] = json!(kinds.triangle_count);
                    mesh["faces"] = json!(kinds.quad_count + kinds.triangle_count);
                    mesh["input_by_kind"] = by_kind_json(kinds);
                }
                mesh
            })
            .collect();
        outln!("{}", json!({ "meshes": meshes }));
        return Ok(());
    }
    out!("{:24} {:>15}", "mesh (min/avg)", "input");
    for o in &configs {
        out!(" {:>15}", format!("{}/{}", o.method.name(), o.boundary.name()));
    }
    outln!();
    let pair = |s: Option<QualityStats>| s.map_or("-".to_string(), |s| format!("{:.3}/{:.3}", s.min, s.avg));
    for (input, _, kinds, q, results) in &rows {
        let name = input.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        out!("{name:24} {:>15}", pair(Some(*q)));
        for r in results {
            out!(" {:>15}", pair(Some(r.output)));
        }
        outln!();
        // A mesh with triangles: a row per face kind under the mesh's.
        if kinds.triangle_count > 0 {
            let by_kind: [(String, KindStats); 2] = [
                (format!("  {}", count(kinds.quad_count, "quad", "quads")), |k| k.quads),
                (format!("  {}", count(kinds.triangle_count, "triangle", "triangles")), |k| k.triangles),
            ];
            for (label, stats) in by_kind {
                out!("{label:24} {:>15}", pair(stats(kinds)));
                for r in results {
                    out!(" {:>15}", pair(stats(&r.by_kind)));
                }
                outln!();
            }
        }
    }
    Ok(())
}

/// One face kind's statistics out of a [`ByFaceKind`].
type KindStats = fn(&ByFaceKind) -> Option<QualityStats>;

/// What a configuration's run gave, on a planar mesh or a surface.
struct Outcome {
    output: QualityStats,
    by_kind: ByFaceKind,
    iterations: usize,
    seconds: f64,
    converged: bool,
}
