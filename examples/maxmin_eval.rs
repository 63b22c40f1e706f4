//! Evaluates the max-min stage after the default run on mesh files:
//!
//!     cargo run --release --example maxmin_eval -- [--solver grid|active|grid-active] MESH...
//!
//! Prints per mesh the default run's min/avg and time, then the stage's min/avg, rounds,
//! moves and time (and its share of the default run's time).

use quadopt::Features;
use quadopt::testing::BoundaryGeometry;
use quadopt::testing::{LocalSolver, MaxMinSettings, max_min_stage};
use quadopt::{DVec2, Mesh, Options, Topology, io, optimize};
use std::time::Instant;

/// Arclength parameters of `points` on the original loops of `geometry` (the optimized
/// boundary vertices lie on them): each movable boundary vertex's nearest point of its loop.
fn params_of(points: &[DVec2], original: &[DVec2], topo: &Topology, geometry: &BoundaryGeometry) -> Vec<f64> {
    let mut params = geometry.initial_params();
    let mut slot = 0;
    for lp in topo.boundary_loops() {
        let n = lp.len();
        let mut cum = vec![0.0; n + 1];
        for k in 0..n {
            cum[k + 1] = cum[k] + (original[lp[(k + 1) % n] as usize] - original[lp[k] as usize]).length();
        }
        for &v in lp.iter() {
            if geometry.slot(v as usize).is_some() {
                let q = points[v as usize];
                let mut best = (f64::INFINITY, 0.0);
                for k in 0..n {
                    let (a, b) = (original[lp[k] as usize], original[lp[(k + 1) % n] as usize]);
                    let d = b - a;
                    let t = if d.length_squared() > 0.0 {
                        ((q - a).dot(d) / d.length_squared()).clamp(0.0, 1.0)
                    } else {
                        0.0
                    };
                    let dist = (a + t * d - q).length_squared();
                    if dist < best.0 {
                        best = (dist, cum[k] + t * (cum[k + 1] - cum[k]));
                    }
                }
                params[slot] = best.1.rem_euclid(cum[n].max(f64::MIN_POSITIVE));
            }
            slot += 1;
        }
    }
    params
}

/// CPU seconds used so far by all threads of this process (Linux; 0 elsewhere): a measure of
/// cost that does not depend on how busy the machine is.
fn cpu_seconds() -> f64 {
    let Ok(tasks) = std::fs::read_dir("/proc/self/task") else { return 0.0 };
    let mut ns = 0u64;
    for t in tasks.flatten() {
        if let Ok(text) = std::fs::read_to_string(t.path().join("schedstat")) {
            ns += text.split_whitespace().next().and_then(|f| f.parse::<u64>().ok()).unwrap_or(0);
        }
    }
    ns as f64 * 1e-9
}

fn main() {
    let mut settings = MaxMinSettings::default();
    let mut files = Vec::new();
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        if a == "--solver" {
            settings.solver = match args.next().as_deref() {
                Some("grid") => LocalSolver::Grid,
                Some("active") => LocalSolver::ActiveSet,
                Some("grid-active") => LocalSolver::GridActiveSet,
                other => panic!("unknown solver {other:?}"),
            };
        } else if let Some(name) = a.strip_prefix("--") {
            let value: f64 = args.next().and_then(|v| v.parse().ok()).expect("a number");
            match name {
                "delta" => settings.region_delta = value,
                "max-delta" => settings.max_region_delta = value,
                "min-gain" => settings.min_gain = value,
                "avg-tol" => settings.avg_tolerance = value,
                "levels" => settings.grid_levels = value as usize,
                "grid" => settings.grid_size = value as usize,
                "iterations" => settings.active_set_iterations = value as usize,
                "rounds" => settings.max_rounds = value as usize,
                "warm" => settings.warm_start = value != 0.0,
                "smooth-avg" => settings.average_by_smoothing = value != 0.0,
                "margin" => settings.recovery_margin = value,
                "escapes" => settings.escapes = value as usize,
                "switch" => settings.switch_phase = value != 0.0,
                "avg-sweeps" => settings.average_sweeps = value as usize,
                "enough" => settings.average_first = value != 0.0,
                _ => panic!("unknown option --{name}"),
            }
        } else {
            files.push(a);
        }
    }
    println!(
        "{:<40} {:>7} {:>7} {:>7} | {:>7} {:>7} {:>6} {:>6} {:>7} {:>6} {:>6}",
        "mesh", "min0", "avg0", "t_def", "min", "avg", "rounds", "moves", "t_stage", "share", "cpu%"
    );
    for file in files {
        let data = match io::read_mesh(&file) {
            Ok(d) => d,
            Err(e) => {
                eprintln!("{file}: {e}");
                continue;
            }
        };
        let planar = match io::PlanarMesh::new(&data) {
            Ok(p) => p,
            Err(e) => {
                eprintln!("{file}: {e}");
                continue;
            }
        };
        let mut mesh: Mesh = planar.mesh;
        let original = mesh.points().to_vec();
        let topo = Topology::new(&mesh);
        let options = Options::default();
        let features = Features::new(&mesh, &topo, options.feature_angle_deg, true);
        let geometry = BoundaryGeometry::new(&original, &topo, &features);
        let (t0, c0) = (Instant::now(), cpu_seconds());
        let report = optimize(&mut mesh, &options).expect("optimize");
        let (t_default, c_default) = (t0.elapsed().as_secs_f64(), cpu_seconds() - c0);
        let c1 = cpu_seconds();
        let mut points = mesh.points().to_vec();
        let mut params = params_of(&points, &original, &topo, &geometry);
        let stage = max_min_stage(
            &mut points,
            &mut params,
            mesh.quads(),
            &topo,
            &features,
            &geometry,
            &settings,
            None,
        );
        let c_stage = cpu_seconds() - c1;
        let name = std::path::Path::new(&file).file_name().unwrap().to_string_lossy().to_string();
        println!(
            "{:<40} {:>7.4} {:>7.4} {:>7.3} | {:>7.4} {:>7.4} {:>6} {:>6} {:>7.3} {:>5.1}% {:>5.1}%",
            name,
            report.output.min,
            report.output.avg,
            t_default,
            stage.after.min,
            stage.after.avg,
            stage.rounds,
            stage.moves,
            stage.seconds,
            100.0 * stage.seconds / t_default,
            100.0 * c_stage / c_default
        );
        if std::env::var_os("MAXMIN_HISTORY").is_some() {
            let h: Vec<String> = stage.history.iter().map(|m| format!("{m:.4}")).collect();
            println!("  history: {}", h.join(" "));
        }
        assert!(stage.history.windows(2).all(|w| w[1] >= w[0]), "minimum fell: {:?}", stage.history);
    }
}
