//! `quadopt compare IN...`: every method with a fixed boundary and every boundary mode of the
//! embedded polygon method, side by side for each mesh (the paper's Table 2).

use crate::cli::TuneArgs;
use crate::fail::Fail;
use crate::json::stats_json;
use crate::mesh_files::{Loaded, load};
use crate::progress::run;
use quadopt::{BoundaryMode, Method, Optimizer, Options};
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
        rows.push((input, data.points.len(), data.quads.len(), planar.mesh.quality(), results));
    }
    if as_json {
        let meshes: Vec<Value> = rows
            .iter()
            .map(|(input, nv, nq, q, results)| {
                let runs: Vec<Value> = results
                    .iter()
                    .zip(&configs)
                    .map(|(r, o)| {
                        json!({
                            "method": o.method.name(), "boundary": o.boundary.name(),
                            "output": stats_json(&r.output), "iterations": r.iterations,
                            "seconds": r.seconds, "converged": r.converged,
                        })
                    })
                    .collect();
                json!({ "file": input.display().to_string(), "vertices": nv, "quads": nq,
                        "input": stats_json(q), "results": runs })
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
    for (input, _, _, q, results) in &rows {
        let name = input.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        out!("{name:24} {:>15}", format!("{:.3}/{:.3}", q.min, q.avg));
        for r in results {
            out!(" {:>15}", format!("{:.3}/{:.3}", r.output.min, r.output.avg));
        }
        outln!();
    }
    Ok(())
}
