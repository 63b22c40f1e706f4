//! The quality floor: the `best` preset (the full max-min stage, the default run until the
//! presets) may never end worse than the default of December 2026 (before the fast-by-default
//! and max-min work) on any of the project's meshes — every sample
//! in `data/`, its jittered copy and the hard meshes of tests/hard_meshes.rs — nor on the
//! Mesquite meshes when `../shared/meshes/mesquite` next to the repository is present (it is not
//! part of the repository: without it their rows are skipped, with a line saying so).
//!
//! Per mesh, the output's inverted count may not exceed the recorded one and its minimum and
//! average scaled Jacobian may not be lower than the recorded ones by more than `TOLERANCE`;
//! the meshes on which the result is chaotic in the input's last bits (`CHAOTIC`) are judged
//! by medians over perturbed copies instead of one run.
//! The table (time, sweeps, min/avg after the sweeps and at the end against the floor, the
//! max-min stage's share of the time) is printed with `--nocapture`; set
//! `QUADOPT_FLOOR_PRINT=1` to print the rows in this file's format instead.

mod common;
use common::hard::hard_meshes;
use common::samples::{jittered, load, sample_files};
use common::shared;
use quadopt::io::{self, PlanarMesh};
use quadopt::{BoundaryMode, Mesh, Optimizer, Options, StopRule, Topology};
use std::path::PathBuf;

/// Quality lost against the floor that still passes (the optimizer's own tie threshold).
const TOLERANCE: f64 = 1e-3;

/// The max-min stage may not squash quads: the output's smallest edge ratio (shortest over
/// longest edge of a quad) must be at least this fraction of the smaller of the input's and the
/// sweeps' (a run without the stage). The scaled Jacobian does not see aspect ratio, and
/// before the stage's edge floor it made quads 1e-15 thin (Mesquite's horse20x10) that scored
/// 0.97; with it the ratio is at least 0.21 of that on every mesh here.
const EDGE_RATIO_KEPT: f64 = 0.1;

/// Smallest shortest/longest edge ratio over the faces of `mesh`, each over its own edges.
fn edge_ratio(mesh: &Mesh) -> f64 {
    let p = mesh.points();
    mesh.quads()
        .iter()
        .map(|q| {
            let n = quadopt::face::corner_count(q);
            let e: Vec<f64> = (0..n).map(|i| p[q[i] as usize].distance(p[q[(i + 1) % n] as usize])).collect();
            e.iter().copied().fold(f64::INFINITY, f64::min) / e.iter().copied().fold(0.0, f64::max)
        })
        .fold(f64::INFINITY, f64::min)
}

/// Meshes on which the default stopping rule ends lower, by a measured and documented amount
/// (docs/stopping.md; docs/guide/presets.md, "Stopping rules"): (mesh, inverted, min, avg) that the default must reach instead
/// of the floor, which the energy rule (`StopRule::Energy`) must still reach.
///
/// Mesquite's tfi_chevron24x24 is a TFI mesh near a fixed point of the sweeps: its average
/// rises by 2e-3 in the first 100 sweeps, then the sweeps drift away and it climbs from 0.74
/// to 0.82 over the next 900 (the cap). No rule that stops the other 55 meshes within a few
/// times their useful sweeps can tell the plateau from convergence.
#[rustfmt::skip]
const DOCUMENTED_COST: &[(&str, usize, f64, f64)] = &[
    ("mesquite: untangled/tfi_chevron24x24.vtk", 0, 0.707098, 0.744892),
];

/// Meshes whose floor run squashed quads into slivers, which the scaled Jacobian scores well:
/// (mesh, the floor run's smallest edge ratio, inverted, min, avg). The default must reach
/// these values instead of the floor, with quads thicker than the floor run's (else the floor
/// itself applies). Measured on the floor's commit (62376c1): graded anisotropic's input has a
/// smallest edge ratio of 1.9e-3, the floor run's output 3.0e-5, today's 9.9e-4;
/// shashkov_quad's 4.4e-3, 2.2e-6 and 1.8e-4 (its sweeps, before the max-min stage, make
/// 1.7e-6). Both are chaotic (see `CHAOTIC`): the values are the medians of the default run
/// over each mesh and 80 perturbed copies, measured on commit e8ecb55, whose max-min stage
/// keeps every edge above its floor (see `EDGE_RATIO_KEPT`). A single run's values, recorded
/// before, were one draw of that spread (graded anisotropic's 0.035/0.476). The stopping
/// rule's average threshold of 4e-3 (e8ecb55, from 1e-3) cost graded anisotropic's median
/// average about 0.012 (0.481 -> 0.468 over 20 copies; it stops after fewer sweeps), shashkov's
/// 0.004: recorded here as a documented cost of the faster default (docs/stopping.md; docs/guide/presets.md, "Stopping rules").
#[rustfmt::skip]
const SQUASHED_FLOOR: &[(&str, f64, usize, f64, f64)] = &[
    // The per-quad guarantee (issue 42) keeps 6 inversions whose removal lowered valid
    // quads below their own values (all under the floor): a documented cost.
    ("hard: graded anisotropic", 3.0e-5, 6, -0.149900, 0.0),
    ("mesquite: untangled/shashkov_quad.vtk", 2.2e-6, 0, 0.054205, 0.722514),
];

/// Meshes on which the max-min stage is chaotic: every interior vertex moved by 1e-7 of its
/// shortest edge (a change no user could see in the input) moves the output's minimum by up
/// to 0.03 and its average by up to 0.14 (graded anisotropic; shashkov_quad 0.02 and 0.04;
/// measured over 80 such copies, the spread is printed). One run of such a mesh says nothing
/// about a change to the optimizer: it is judged by the medians over the mesh and
/// `CHAOTIC_COPIES` copies, against floors recorded as the medians over 80 copies
/// (`SQUASHED_FLOOR`), within `CHAOTIC_TOLERANCE`.
const CHAOTIC: &[&str] = &["hard: graded anisotropic", "mesquite: untangled/shashkov_quad.vtk"];

/// Perturbed copies run for each chaotic mesh (with the mesh itself, an odd count).
const CHAOTIC_COPIES: u64 = 40;

/// What a chaotic mesh's medians may lose against their floor: about three standard errors
/// of the noisiest one, graded anisotropic's average (its copies' averages have an
/// interquartile range of 0.045, so the median of 41 has a standard error near 0.0065; the
/// minima's are near 0.002).
const CHAOTIC_TOLERANCE: f64 = 0.02;

/// The output statistics of the default run on `original` and `CHAOTIC_COPIES` copies whose
/// interior vertices moved by 1e-7 of their shortest edge: (median inverted, min, avg) and
/// the spread of min and avg.
fn medians_over_copies(
    original: &Mesh,
    options: &Options,
    first: &quadopt::QualityStats,
) -> ((usize, f64, f64), f64, f64) {
    let topo = Topology::new(original);
    let mut runs = vec![*first];
    for seed in 1..=CHAOTIC_COPIES {
        let mut copy = jittered(original, &topo, 1e-7, seed);
        runs.push(quadopt::optimize(&mut copy, options).unwrap().output);
    }
    let median = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        (v[v.len() / 2], v[v.len() - 1] - v[0])
    };
    let mut inverted: Vec<usize> = runs.iter().map(|r| r.inverted).collect();
    inverted.sort_unstable();
    let (min, min_spread) = median(runs.iter().map(|r| r.min).collect());
    let (avg, avg_spread) = median(runs.iter().map(|r| r.avg).collect());
    ((inverted[inverted.len() / 2], min, avg), min_spread, avg_spread)
}

/// (mesh, inverted, min, avg) of the default run measured before the speed work (the
/// quad-dominant meshes' rows: when they were added).
#[rustfmt::skip]
const FLOOR: &[(&str, usize, f64, f64)] = &[
    ("mazewheel.vtk", 0, 0.093734, 0.906540),
    ("mazewheel.vtk (jittered)", 0, 0.093734, 0.906545),
    ("patch_notched.vtk", 0, 0.120990, 0.883603),
    ("patch_notched.vtk (jittered)", 0, 0.120990, 0.883604),
    ("patch_slotted.vtk", 0, 0.202309, 0.898356),
    ("patch_slotted.vtk (jittered)", 0, 0.202309, 0.898473),
    ("plate_10holes.vtk", 0, 0.585633, 0.887302),
    ("plate_10holes.vtk (jittered)", 0, 0.585602, 0.887301),
    ("plate_1hole.vtk", 0, 0.669759, 0.904114),
    ("plate_1hole.vtk (jittered)", 0, 0.669669, 0.904098),
    ("plate_1hole_fine.vtk", 0, 0.800311, 0.981470),
    ("plate_1hole_fine.vtk (jittered)", 0, 0.798337, 0.981458),
    ("plate_2holes.vtk", 0, 0.752749, 0.910270),
    ("plate_2holes.vtk (jittered)", 0, 0.762058, 0.910643),
    ("plate_2holes_2squares.vtk", 0, 0.579115, 0.898798),
    ("plate_2holes_2squares.vtk (jittered)", 0, 0.579115, 0.899907),
    ("plate_3holes.vtk", 0, 0.704662, 0.899451),
    ("plate_3holes.vtk (jittered)", 0, 0.706012, 0.899019),
    ("plate_3holes_1square.vtk", 0, 0.677408, 0.883505),
    ("plate_3holes_1square.vtk (jittered)", 0, 0.689203, 0.891006),
    ("plate_6holes_2squares.vtk", 0, 0.565878, 0.913831),
    ("plate_6holes_2squares.vtk (jittered)", 0, 0.573435, 0.913782),
    ("plate_8holes.vtk", 0, 0.514866, 0.906285),
    ("plate_8holes.vtk (jittered)", 0, 0.532263, 0.907543),
    // The quad-dominant samples (issue 32), measured with `best` when they were added (on
    // commit 8c9d49e, after the speed work: no older floor exists for them).
    ("mazewheel_mixed.vtk", 0, 0.256258, 0.917585),
    ("mazewheel_mixed.vtk (jittered)", 0, 0.256258, 0.916446),
    ("patch_notched_mixed.vtk", 0, 0.755929, 0.932921),
    ("patch_notched_mixed.vtk (jittered)", 0, 0.755929, 0.933884),
    ("plate_2holes_mixed.vtk", 0, 0.836907, 0.944144),
    ("plate_2holes_mixed.vtk (jittered)", 0, 0.838002, 0.944451),
    ("hard: graded anisotropic", 0, 0.014283, 0.534057),
    ("hard: boundary layer", 0, 0.999943, 0.999997),
    ("hard: folded layers", 0, 0.999989, 0.999999),
    ("hard: near-touching slit", 0, 0.945770, 0.998906),
    ("hard: jittered plate, holes", 0, 0.999635, 0.999990),
    ("mesquite: tangled/hole_in_square.vtk", 0, 0.089945, 0.687214),
    ("mesquite: tangled/inverted-hole-1.vtk", 0, 1.000000, 1.000000),
    ("mesquite: tangled/par_untangle_original_quad_mesh.1.0.vtk", 0, 0.805890, 0.982400),
    ("mesquite: tangled/par_untangle_original_quad_mesh.2.0.vtk", 0, 0.805890, 0.969893),
    ("mesquite: tangled/par_untangle_original_quad_mesh.2.1.vtk", 0, 1.000000, 1.000000),
    ("mesquite: tangled/rotsq.vtk", 0, 1.000000, 1.000000),
    ("mesquite: tangled/tangled_quad.vtk", 0, 0.999999, 0.999999),
    ("mesquite: untangled/copy-morph-for-ricoh.cub.vtk", 5429, -1.000000, 0.283808),
    ("mesquite: untangled/four_more_quads.vtk", 0, 1.000000, 1.000000),
    ("mesquite: untangled/halfCirc.vtk", 0, 0.844127, 0.994790),
    ("mesquite: untangled/hole_scheme.vtk", 0, 0.965923, 0.965925),
    ("mesquite: untangled/hole_scheme_opp_bias.vtk", 0, 0.994130, 0.994137),
    ("mesquite: untangled/horse20x10_2_4.vtk", 0, 0.762529, 0.888349),
    // Quads and triangles (issue 32), measured when it was added, like the mixed samples.
    ("mesquite: untangled/polarMesh.vtk", 0, 0.298858, 0.922186),
    // (quad_2_not_xy.vtk, a tilted plane stored with 7 digits, is a surface by the one
    // planarity rule: not a planar floor's mesh.)
    ("mesquite: untangled/quads_4by2.vtk", 0, 1.000000, 1.000000),
    ("mesquite: untangled/quads_4by2_bad.vtk", 0, 1.000000, 1.000000),
    ("mesquite: untangled/shashkov_quad.vtk", 0, 0.050000, 0.727982),
    ("mesquite: untangled/shest_grid32.vtk", 0, 0.429952, 0.958956),
    ("mesquite: untangled/square_quad_10_rand.vtk", 0, 0.999990, 0.999998),
    ("mesquite: untangled/square_quad_2.vtk", 0, 1.000000, 1.000000),
    ("mesquite: untangled/subdiv4x4_3_2_3x3.vtk", 0, 0.711626, 0.894159),
    ("mesquite: untangled/tangled_quad.vtk", 0, 0.999999, 0.999999),
    ("mesquite: untangled/tfi_chevron24x24.vtk", 0, 0.707098, 0.832281),
    ("mesquite: untangled/tfi_horse10x4-12.vtk", 0, 0.987685, 0.987687),
    ("mesquite: untangled/tfi_horse10x4-14.vtk", 0, 0.676753, 0.817321),
    ("mesquite: untangled/unstrquad.vtk", 0, 0.569608, 0.931918),
    ("mesquite: untangled/ybiasqr24x24.vtk", 0, 1.000000, 1.000000),
];

/// Every mesh of the floor: samples, jittered samples, hard meshes, and Mesquite's if present;
/// and whether Mesquite's were.
fn meshes() -> (Vec<(String, Mesh)>, bool) {
    let mut out = Vec::new();
    for path in sample_files() {
        let (name, mesh, _) = load(&path);
        let optimizer = Optimizer::new(&mesh);
        let mut base = mesh.clone();
        // The energy rule, as when the floor was recorded: the jittered meshes stay the same.
        let fixed_boundary = Options::best().with_boundary(BoundaryMode::Fixed).with_stop(StopRule::Energy);
        optimizer.run(&mut base, &fixed_boundary, None).unwrap();
        let shaken = jittered(&base, &Topology::new(&base), 0.9, 7);
        out.push((name.clone(), mesh));
        out.push((format!("{name} (jittered)"), shaken));
    }
    for (name, mesh) in hard_meshes() {
        out.push((format!("hard: {name}"), mesh));
    }
    let rows = mesquite_rows();
    let mesquite = shared::mesquite(&format!("the floor's {rows} rows of Mesquite meshes"));
    if let Some(dir) = &mesquite {
        for sub in ["tangled", "untangled"] {
            let mut files: Vec<PathBuf> =
                std::fs::read_dir(dir.join(sub)).unwrap().map(|e| e.unwrap().path()).collect();
            files.sort();
            for path in files {
                let Ok(data) = io::read_mesh(&path) else { continue };
                let Ok(planar) = PlanarMesh::new(&data) else { continue };
                let name = format!("mesquite: {sub}/{}", path.file_name().unwrap().to_string_lossy());
                out.push((name, planar.mesh));
            }
        }
    }
    (out, mesquite.is_some())
}

/// The rows of [`FLOOR`] for Mesquite's meshes.
fn mesquite_rows() -> usize {
    FLOOR.iter().filter(|f| f.0.starts_with("mesquite: ")).count()
}

#[test]
fn best_never_ends_below_the_recorded_floor() {
    let print = std::env::var_os("QUADOPT_FLOOR_PRINT").is_some();
    let mut failures = Vec::new();
    let mut checked = 0;
    println!(
        "{:44} {:>7} {:>7} {:>6} {:>16} {:>16} {:>16} {:>6} {:>8}",
        "mesh",
        "quads",
        "ms",
        "sweeps",
        "sweeps min/avg",
        "output min/avg",
        "floor min/avg",
        "stage",
        "edge ratio in/sweeps/out"
    );
    // QUADOPT_FLOOR_STOP=quality|energy measures another stopping rule against the floor;
    // QUADOPT_FLOOR_ONLY=TEXT keeps the meshes whose name contains TEXT.
    let mut options = Options::best();
    match std::env::var("QUADOPT_FLOOR_STOP").as_deref() {
        Ok("quality") => options.stop = StopRule::Quality,
        Ok("energy") => options.stop = StopRule::Energy,
        Ok(other) => panic!("QUADOPT_FLOOR_STOP={other}: expected quality or energy"),
        Err(_) => {}
    }
    let only = std::env::var("QUADOPT_FLOOR_ONLY").ok();
    let (meshes, with_mesquite) = meshes();
    for (name, mut mesh) in meshes {
        if only.as_ref().is_some_and(|o| !name.contains(o.as_str())) {
            continue;
        }
        let original = mesh.clone();
        let report = quadopt::optimize(&mut mesh, &options).unwrap();
        let out = report.output;
        let mut sweeps_only = original.clone();
        quadopt::optimize(&mut sweeps_only, &options.clone().with_max_min(false)).unwrap();
        let ratios = [edge_ratio(&original), edge_ratio(&sweeps_only), edge_ratio(&mesh)];
        let ratio = ratios[2];
        let ratio_bar = EDGE_RATIO_KEPT * ratios[0].min(ratios[1]);
        if ratio < ratio_bar {
            failures.push(format!("{name}: smallest edge ratio {ratio:.2e} < {ratio_bar:.2e}"));
        }
        if print {
            println!("    ({name:?}, {}, {:.6}, {:.6}),", out.inverted, out.min, out.avg);
            continue;
        }
        let floor = FLOOR.iter().find(|f| f.0 == name);
        let stage = report.max_min;
        println!(
            "{name:44} {:>7} {:>7.1} {:>6} {:>16} {:>16} {:>16} {:>5.0}% {:>8.1e}/{:.1e}/{:.1e}",
            mesh.quads().len(),
            report.seconds * 1e3,
            report.iterations,
            stage.map_or("-".into(), |g| format!("{:.3}/{:.3}", g.before.min, g.before.avg)),
            format!("{:.3}/{:.3}", out.min, out.avg),
            floor.map_or("-".into(), |f| format!("{:.3}/{:.3}", f.2, f.3)),
            stage.map_or(0.0, |g| 100.0 * g.seconds / report.seconds),
            ratios[0],
            ratios[1],
            ratios[2],
        );
        let Some(&(_, mut inverted, mut min, mut avg)) = floor else {
            if !name.starts_with("mesquite") {
                failures.push(format!("{name}: no recorded floor"));
            }
            continue;
        };
        checked += 1;
        if let Some(&(_, squashed, i, m, a)) = SQUASHED_FLOOR.iter().find(|c| c.0 == name) {
            if ratio > squashed {
                (inverted, min, avg) = (i, m, a);
            }
        }
        let chaotic = CHAOTIC.contains(&name.as_str());
        let tolerance = if chaotic { CHAOTIC_TOLERANCE } else { TOLERANCE };
        let below = |out: &quadopt::QualityStats, (inverted, min, avg): (usize, f64, f64)| {
            out.inverted > inverted || out.min < min - tolerance || out.avg < avg - tolerance
        };
        let mut out = out;
        if chaotic {
            let ((i, m, a), min_spread, avg_spread) = medians_over_copies(&original, &options, &out);
            println!(
                "    {name}: medians over it and {CHAOTIC_COPIES} copies {m:.6}/{a:.6} (spread {min_spread:.4}/{avg_spread:.4})"
            );
            (out.inverted, out.min, out.avg) = (i, m, a);
        }
        let (floor_of_rule, energy_check) = match DOCUMENTED_COST.iter().find(|c| c.0 == name) {
            Some(&(_, i, m, a)) if options.stop == StopRule::Quality => ((i, m, a), true),
            _ => ((inverted, min, avg), false),
        };
        let (inverted, min, avg) = floor_of_rule;
        if below(&out, floor_of_rule) {
            failures.push(format!(
                "{name}: {} inverted, min {:.6}, avg {:.6}; floor {inverted}, {min:.6}, {avg:.6}",
                out.inverted, out.min, out.avg
            ));
        }
        if energy_check {
            let energy = options.clone().with_stop(StopRule::Energy);
            let mut again = original;
            let out = quadopt::optimize(&mut again, &energy).unwrap().output;
            let f = floor.unwrap();
            if below(&out, (f.1, f.2, f.3)) {
                failures.push(format!(
                    "{name} with the energy rule: {} inverted, min {:.6}, avg {:.6}; floor {}, {:.6}, {:.6}",
                    out.inverted, out.min, out.avg, f.1, f.2, f.3
                ));
            }
        }
    }
    // Every row is checked (Mesquite's only when present): none is left out unsaid.
    let rows = if with_mesquite { FLOOR.len() } else { FLOOR.len() - mesquite_rows() };
    assert!(print || only.is_some() || checked == rows, "{checked} meshes checked against {rows} rows");
    assert!(failures.is_empty(), "{} below the floor:\n{}", failures.len(), failures.join("\n"));
}

/// Mesquite's unstrquad (CI-only): the full max-min stage raises the minimum from 0.570 but
/// costs 0.011 of average, so the run rejects it; tried again without its escapes, the stage
/// ends at 0.701 with the average kept (0.932), and the run takes that. balanced's short stage (no escapes) loses too much average there with its one recovery
/// sweep; tried again with the full recovery, it is taken at 0.697.
#[test]
fn a_rejected_stage_is_retried_without_its_escapes() {
    let Some(mesh) =
        mesquite_mesh("a_rejected_stage_is_retried_without_its_escapes", "untangled/unstrquad.vtk")
    else {
        return;
    };
    for (options, least) in [(Options::best(), 0.7), (Options::balanced(), 0.69)] {
        let report = quadopt::optimize(&mut mesh.clone(), &options).unwrap();
        let stage = report.max_min.expect("the retried stage's result is taken");
        let (before, after) = (stage.before, report.output);
        assert!(before.min < 0.6 && after.min > least, "{:?}: {before:?} -> {after:?}", options.effort);
        assert!(after.avg >= before.avg - TOLERANCE, "{:?}: {before:?} -> {after:?}", options.effort);
    }
}

/// Mesquite's mesh `file` (under ../shared/meshes/mesquite) as the optimizer's 2D mesh, or
/// `None` (with a line saying `test` is skipped) when Mesquite's meshes are absent.
fn mesquite_mesh(test: &str, file: &str) -> Option<Mesh> {
    let dir = shared::mesquite(&format!("{test} (Mesquite's {file})"))?;
    let data = io::read_mesh(dir.join(file)).unwrap();
    Some(PlanarMesh::new(&data).unwrap().mesh)
}

/// Mesquite's copy-morph-for-ricoh (CI-only), a 3D surface flattened onto a plane: untangling
/// cannot remove its folds and only adds inverted quads, so it stops after
/// 20 sweeps without a new lowest count instead of running to its cap of 200; the run's
/// guarantees hold all the same.
#[test]
fn untangling_stops_when_it_stops_paying() {
    let file = "untangled/copy-morph-for-ricoh.cub.vtk";
    let Some(mut mesh) = mesquite_mesh("untangling_stops_when_it_stops_paying", file) else {
        return;
    };
    let report = quadopt::optimize(&mut mesh, &Options::fast()).unwrap();
    assert!(report.untangle_sweeps <= 25, "{} untangling sweeps", report.untangle_sweeps);
    assert!(report.output.inverted <= report.input.inverted && report.output.min >= report.input.min);
}

/// Mesquite's hole_scheme_opp_bias (CI-only): 174 equal quads that the sweeps cannot improve.
/// `fast` stops once two sweeps in a row leave the kept iterate as it was, and loses nothing
/// against its full budget of sweeps.
#[test]
fn fast_stops_when_its_sweeps_stop_changing_what_it_keeps() {
    let file = "untangled/hole_scheme_opp_bias.vtk";
    let Some(mesh) = mesquite_mesh("fast_stops_when_its_sweeps_stop_changing_what_it_keeps", file) else {
        return;
    };
    let fast = quadopt::optimize(&mut mesh.clone(), &Options::fast()).unwrap();
    // The same sweeps without the stale stop: the balanced preset's, capped at fast's budget.
    let budget = Options::balanced().with_max_min(false).with_max_iterations(quadopt::Effort::FAST_SWEEPS);
    let full = quadopt::optimize(&mut mesh.clone(), &budget).unwrap();
    assert!(fast.iterations < full.iterations, "{} sweeps against {}", fast.iterations, full.iterations);
    assert_eq!(
        (fast.output.inverted, fast.output.min, fast.output.avg),
        (full.output.inverted, full.output.min, full.output.avg)
    );
}

/// Mesquite's polarMesh (CI-only): 216 quads and 24 triangles around its centre, a vertex of
/// 24 triangles. Their 24 angles there add up to 360 degrees, so the smallest is at most 15,
/// and a triangle's scaled Jacobian is at most that of its corner there, sin(15 deg) * 2/sqrt(3)
/// = 0.298858: the input (0.298858 less 2.3e-7) is at that bound already. Every preset keeps
/// the faces, ends within 1e-6 of the bound (never above it, never below the input's minimum)
/// and reports the two kinds apart.
#[test]
fn polar_mesh_keeps_its_triangles_at_their_bound() {
    let Some(mesh) =
        mesquite_mesh("polar_mesh_keeps_its_triangles_at_their_bound", "untangled/polarMesh.vtk")
    else {
        return;
    };
    let bound = 15f64.to_radians().sin() * 2.0 / 3f64.sqrt();
    assert_eq!((mesh.quads().len(), mesh.triangle_count()), (240, 24));
    for options in [Options::fast(), Options::balanced(), Options::best()] {
        let mut out = mesh.clone();
        let report = quadopt::optimize(&mut out, &options).unwrap();
        let (input, output) = (report.input, report.output);
        let effort = options.effort;
        assert_eq!(out.quads(), mesh.quads(), "{effort:?}: the faces changed");
        assert_eq!(output.inverted, 0, "{effort:?}");
        assert!(output.min >= input.min && output.min > bound - 1e-6, "{effort:?}: {input:?} -> {output:?}");
        assert!(output.min <= bound + 1e-12, "{effort:?}: {output:?} above the bound {bound}");
        let kinds = report.output_by_kind;
        assert_eq!((kinds.quad_count, kinds.triangle_count), (216, 24), "{effort:?}");
        let triangles = kinds.triangles.unwrap();
        assert_eq!(triangles.min, output.min, "{effort:?}: the worst face is not a triangle");
        assert!(kinds.quads.unwrap().min > triangles.min, "{effort:?}: {kinds:?}");
    }
}
