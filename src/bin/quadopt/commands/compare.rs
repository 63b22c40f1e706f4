//! `quadopt compare IN...`: every method with a fixed boundary and every boundary mode of the
//! embedded polygon method, side by side for each mesh (the paper's Table 2).

use crate::cli::TuneArgs;
use crate::fail::Fail;
use crate::json::{by_kind_json, stats_json};
use crate::mesh_files::{Loaded, load};
use crate::plural::count;
use crate::progress::run;
use quadopt::quality::ByFaceKind;
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
        let Loaded { data, planar } = load(input, &[])?;
        let optimizer = Optimizer::new(&planar.mesh);
        let mut results = Vec::new();
        for options in &configs {
            let mut mesh = planar.mesh.clone();
            results.push(run(&optimizer, &mut mesh, options, !as_json)?);
        }
        let kinds = planar.mesh.quality_by_face_kind();
        rows.push((input, data.points.len(), kinds, planar.mesh.quality(), results));
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
                            run["output_by_kind"] = by_kind_json(&r.output_by_kind);
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
                    out!(" {:>15}", pair(stats(&r.output_by_kind)));
                }
                outln!();
            }
        }
    }
    Ok(())
}

/// One face kind's statistics out of a [`ByFaceKind`].
type KindStats = fn(&ByFaceKind) -> Option<QualityStats>;
