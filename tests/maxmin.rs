//! The max-min stage (src/smooth/maxmin/): known optima reached, the global minimum
//! monotone, fixed vertices untouched, boundary vertices on the original boundary, no valid
//! quad inverted, the same result on any thread count.

mod common;

use common::Rng;
use common::grids::Grid;
use quadopt::Features;
use quadopt::quality::{corners, scaled_jacobian};
use quadopt::testing::BoundaryGeometry;
use quadopt::testing::{LocalSolver, MaxMinReport, MaxMinSettings, max_min_stage};
use quadopt::{BoundaryMode, DVec2, Mesh, Topology};

/// Runs the stage on `mesh` in `mode` (corners at the default 45 degrees); returns the new
/// positions and the report.
fn run(mesh: &Mesh, mode: BoundaryMode, settings: &MaxMinSettings) -> (Vec<DVec2>, MaxMinReport) {
    let topo = Topology::new(mesh);
    let features = Features::new(mesh, &topo, 45.0, mode != BoundaryMode::Fixed);
    let geometry = BoundaryGeometry::new(mesh.points(), &topo, &features);
    let mut points = mesh.points().to_vec();
    let mut params = geometry.initial_params();
    let report =
        max_min_stage(&mut points, &mut params, mesh.quads(), &topo, &features, &geometry, settings, None);
    // The parameters describe the positions: every movable boundary vertex sits at its
    // parameter's point of the original boundary.
    for (v, p) in points.iter().enumerate() {
        if let Some(slot) = geometry.slot(v) {
            let at = geometry.eval(geometry.slot_loop(slot), params[slot]);
            assert!((at - *p).length() < 1e-12, "vertex {v} at {p} but its parameter gives {at}");
        }
    }
    (points, report)
}

fn quality(points: &[DVec2], quads: &[[u32; 4]]) -> Vec<f64> {
    quads.iter().map(|q| scaled_jacobian(&corners(points, q))).collect()
}

fn assert_monotone(report: &MaxMinReport) {
    assert!(report.history.len() >= 2, "no round recorded: {:?}", report.history);
    for w in report.history.windows(2) {
        assert!(w[1] >= w[0], "the global minimum fell from {} to {}: {:?}", w[0], w[1], report.history);
    }
    assert_eq!(report.history[0], report.before.min);
    assert_eq!(*report.history.last().unwrap(), report.after.min);
}

#[test]
fn interior_vertex_reaches_the_centre_of_a_symmetric_star() {
    // 2x2 unit squares with the centre dragged off: the star's minimum is 1 only with every
    // corner at 90 degrees, i.e. at the centre (1, 1).
    for solver in [LocalSolver::Grid, LocalSolver::ActiveSet, LocalSolver::GridActiveSet] {
        let (mut p, q) = Grid::new(2, 2).unit();
        p[4] = DVec2::new(1.37, 0.71);
        let mesh = Mesh::new(p, q, None).unwrap();
        let settings = MaxMinSettings { solver, ..MaxMinSettings::default() };
        let (points, report) = run(&mesh, BoundaryMode::Fixed, &settings);
        let err = (points[4] - DVec2::new(1.0, 1.0)).length();
        match solver {
            // DMO's 3 levels of 8x8 stop at 1/49 of the star's size; still an improvement.
            LocalSolver::Grid => assert!(err < 0.05, "{solver:?}: {}", points[4]),
            // The ascent alone creeps along the smooth peak until its iteration cap.
            LocalSolver::ActiveSet => assert!(err < 1e-5, "{solver:?}: {}, {err} from (1, 1)", points[4]),
            LocalSolver::GridActiveSet => {
                assert!(err < 1e-6, "{solver:?}: centre at {}, {err} from (1, 1)", points[4]);
                assert!((report.after.min - 1.0).abs() < 1e-10, "{solver:?}: {}", report.after.min);
            }
        }
        assert!(report.after.min > report.before.min);
        assert_monotone(&report);
    }
}

#[test]
fn interior_vertex_reaches_the_max_min_point_of_an_uneven_star() {
    // A 2x2 patch of columns 1 and 3 wide with its only interior vertex dragged off: every
    // corner of the star is at 90 degrees (star minimum 1) only at the grid point (1, 1).
    let p = vec![
        DVec2::new(0.0, 0.0),
        DVec2::new(1.0, 0.0),
        DVec2::new(4.0, 0.0),
        DVec2::new(0.0, 1.0),
        DVec2::new(1.3, 1.4), // free
        DVec2::new(4.0, 1.0),
        DVec2::new(0.0, 2.0),
        DVec2::new(1.0, 2.0),
        DVec2::new(4.0, 2.0),
    ];
    let q = vec![[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 7]];
    let mesh = Mesh::new(p, q, None).unwrap();
    let (points, report) = run(&mesh, BoundaryMode::Fixed, &MaxMinSettings::default());
    assert!((points[4] - DVec2::new(1.0, 1.0)).length() < 1e-6, "{}", points[4]);
    assert!((report.after.min - 1.0).abs() < 1e-10);
    assert_monotone(&report);
}

#[test]
fn boundary_vertex_slides_to_its_optimum_on_a_straight_edge() {
    // 2x2 grid, every vertex fixed but the bottom middle one (vertex 1, free to slide along
    // y = 0 between (0, 0) and (2, 0)), and the centre pinned at (1.5, 1). By hand: the left
    // quad (0,0) (x,0) (1.5,1) (0,1) has corners 1, 1/r, 1/r, 1 with r = sqrt((1.5-x)^2+1);
    // the right quad (x,0) (2,0) (2,1) (1.5,1) has 1/r, 1, 1, 1/r. The star minimum 1/r is
    // highest (1) at x = 1.5.
    let (mut p, q) = Grid::new(2, 2).unit();
    p[4] = DVec2::new(1.5, 1.0);
    let fixed = (0..9).map(|v| v != 1).collect();
    let mesh = Mesh::new(p.clone(), q, Some(fixed)).unwrap();
    let (points, report) = run(&mesh, BoundaryMode::Slide, &MaxMinSettings::default());
    assert_eq!(points[1].y, 0.0, "left the straight edge: {}", points[1]);
    assert!((points[1].x - 1.5).abs() < 1e-6, "{}", points[1]);
    let star = quality(&points, &mesh.quads()[..2]);
    assert!(star.iter().all(|&v| (v - 1.0).abs() < 1e-10), "{star:?}");
    for v in (0..9).filter(|&v| v != 1) {
        assert_eq!(points[v].to_array().map(f64::to_bits), p[v].to_array().map(f64::to_bits));
    }
    assert_monotone(&report);
}

/// A jittered nx x ny grid with its straight sides free to slide, some interior vertices
/// fixed, and the jitter large enough to leave poor quads.
fn jittered(nx: usize, ny: usize, seed: u64) -> Mesh {
    let grid = Grid::new(nx, ny);
    let mut rng = Rng(seed);
    let p = grid.points(|i, j| {
        let mut p = DVec2::new(i as f64, j as f64);
        let (dx, dy) = (0.38 * rng.next(), 0.38 * rng.next());
        match (grid.on_vertical_side(i, j), grid.on_horizontal_side(i, j)) {
            (false, false) => p += DVec2::new(dx, dy),
            (false, true) => p.x += dx,
            (true, false) => p.y += dy,
            (true, true) => {}
        }
        p
    });
    let fixed = grid.per_vertex(|i, j| grid.is_interior(i, j) && (i * 7 + j * 3) % 11 == 0);
    Mesh::new(p, grid.quads(), Some(fixed)).unwrap()
}

#[test]
fn the_minimum_never_falls_and_fixed_vertices_stay_bit_identical() {
    for seed in 1..6 {
        let mesh = jittered(9, 7, seed);
        let before = quality(mesh.points(), mesh.quads());
        let (points, report) = run(&mesh, BoundaryMode::Slide, &MaxMinSettings::default());
        assert_monotone(&report);
        assert!(report.rounds >= 2 && report.moves > 0);
        assert!(
            report.after.min > report.before.min + 0.05,
            "seed {seed}: min {} -> {}",
            report.before.min,
            report.after.min
        );
        let after = quality(&points, mesh.quads());
        assert_eq!(report.after.min, after.iter().copied().fold(f64::INFINITY, f64::min));
        for (b, a) in before.iter().zip(&after) {
            assert!(*b <= 0.0 || *a > 0.0, "a valid quad was inverted");
        }
        let topo = Topology::new(&mesh);
        let features = Features::new(&mesh, &topo, 45.0, true);
        for (v, p) in points.iter().enumerate() {
            if !features.is_movable(v) {
                assert_eq!(
                    p.to_array().map(f64::to_bits),
                    mesh.points()[v].to_array().map(f64::to_bits),
                    "seed {seed}: vertex {v} is fixed or a corner but moved"
                );
            }
        }
        // Straight sides: the boundary vertices stay on them, in order.
        let (w, h) = (9.0, 7.0);
        for (v, p) in points.iter().enumerate() {
            if features.is_boundary(v) {
                let on_side = p.x == 0.0 || p.x == w || p.y == 0.0 || p.y == h;
                assert!(on_side && p.x >= 0.0 && p.x <= w && p.y >= 0.0 && p.y <= h, "vertex {v} at {p}");
            }
        }
    }
}

/// A jittered ring of quads between regular 24-gons of radius 1 and 2 (turning 15 degrees
/// per boundary vertex: no corners); returns the mesh and the boundary rings' vertex ranges.
fn ring_mesh() -> (Mesh, u32, u32) {
    let (n, rings) = (24u32, 3u32);
    let mut rng = Rng(42);
    let mut p = Vec::new();
    for r in 0..=rings {
        let on_boundary = r == 0 || r == rings;
        for k in 0..n {
            let jitter = if on_boundary { 0.0 } else { 0.1 };
            let a = std::f64::consts::TAU * (k as f64 + 3.0 * jitter * rng.next()) / n as f64;
            let radius = 1.0 + r as f64 / rings as f64 + jitter * rng.next();
            p.push(DVec2::new(a.cos(), a.sin()) * radius);
        }
    }
    let mut q = Vec::new();
    for r in 0..rings {
        for k in 0..n {
            let (a, b) = (r * n + k, r * n + (k + 1) % n);
            q.push([a, b, b + n, a + n]);
        }
    }
    (Mesh::new(p, q, None).unwrap(), n, rings)
}

#[test]
fn boundary_vertices_stay_on_the_original_curved_boundary() {
    // The stage must keep every boundary vertex on the input's polygons: not on the circles,
    // not on the current edges.
    let (mesh, n, rings) = ring_mesh();
    let (points, report) = run(&mesh, BoundaryMode::Slide, &MaxMinSettings::default());
    assert_monotone(&report);
    assert!(report.after.min > report.before.min);
    let mut moved = 0;
    for r in [0, rings] {
        let polygon: Vec<DVec2> = (0..n).map(|k| mesh.points()[(r * n + k) as usize]).collect();
        for k in 0..n {
            let v = (r * n + k) as usize;
            moved += usize::from(points[v] != mesh.points()[v]);
            let d = (0..n as usize)
                .map(|i| {
                    let (a, b) = (polygon[i], polygon[(i + 1) % n as usize]);
                    let t = ((points[v] - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
                    (a + t * (b - a) - points[v]).length()
                })
                .fold(f64::INFINITY, f64::min);
            assert!(d < 1e-12, "boundary vertex {v} is {d} off the original boundary");
        }
    }
    assert!(moved > 0, "no boundary vertex moved: the test would check nothing");
}

#[test]
fn a_zero_boundary_deviation_keeps_curved_boundaries_in_place() {
    // Every boundary vertex of the ring is a vertex of the curved original polygon: with a
    // tolerance of 0 any slide would cut a corner of it, so only interior vertices move.
    let (mesh, n, rings) = ring_mesh();
    let settings = MaxMinSettings { max_boundary_deviation: Some(0.0), ..MaxMinSettings::default() };
    let (points, report) = run(&mesh, BoundaryMode::Slide, &settings);
    assert!(report.after.min > report.before.min);
    for r in [0, rings] {
        for k in 0..n {
            let v = (r * n + k) as usize;
            assert_eq!(points[v], mesh.points()[v], "boundary vertex {v} moved");
        }
    }
    assert!((n as usize..(rings * n) as usize).any(|v| points[v] != mesh.points()[v]));
}

#[test]
fn a_tangled_star_never_inverts_a_valid_quad() {
    // One inverted quad (the centre pulled across an edge): the stage may raise it, but the
    // valid quads stay valid and the minimum does not fall.
    let (mut p, q) = Grid::new(3, 3).unit();
    p[5] = DVec2::new(2.3, 1.2); // vertex (1, 1) pushed beyond its right neighbour's column
    let mesh = Mesh::new(p, q, None).unwrap();
    let before = quality(mesh.points(), mesh.quads());
    assert!(before.iter().any(|&v| v <= 0.0), "the setup must be tangled");
    let (points, report) = run(&mesh, BoundaryMode::Fixed, &MaxMinSettings::default());
    let after = quality(&points, mesh.quads());
    for (b, a) in before.iter().zip(&after) {
        assert!(*b <= 0.0 || *a > 0.0, "a valid quad was inverted");
    }
    assert!(report.after.inverted <= report.before.inverted);
    assert_monotone(&report);
}

#[test]
fn the_result_does_not_depend_on_the_thread_count() {
    let mesh = jittered(12, 10, 9);
    let on = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| run(&mesh, BoundaryMode::Slide, &MaxMinSettings::default()))
    };
    let (one, r1) = on(1);
    let (two, r2) = on(2);
    let bits = |p: &[DVec2]| p.iter().flat_map(|q| q.to_array().map(f64::to_bits)).collect::<Vec<u64>>();
    assert_eq!(bits(&one), bits(&two));
    assert_eq!(r1.history, r2.history);
}

#[test]
fn cancelling_keeps_a_result_no_worse() {
    let mesh = jittered(9, 7, 3);
    let topo = Topology::new(&mesh);
    let features = Features::new(&mesh, &topo, 45.0, true);
    let geometry = BoundaryGeometry::new(mesh.points(), &topo, &features);
    let mut points = mesh.points().to_vec();
    let mut params = geometry.initial_params();
    let mut calls = 0;
    let mut stop = |_round: usize, _min: f64| {
        calls += 1;
        false
    };
    let report = max_min_stage(
        &mut points,
        &mut params,
        mesh.quads(),
        &topo,
        &features,
        &geometry,
        &MaxMinSettings::default(),
        Some(&mut stop),
    );
    assert_eq!(calls, 1);
    assert!(report.cancelled && report.rounds == 1);
    assert!(report.after.min >= report.before.min);
}

/// An n x n grid of unit squares whose interior vertices are moved by up to `amount` per axis.
fn jittered_grid(n: usize, amount: f64, seed: u64) -> Mesh {
    let grid = Grid::square(n);
    let mut rng = Rng(seed);
    let p = grid.points(|i, j| {
        let p = DVec2::new(i as f64, j as f64);
        if grid.is_interior(i, j) { p + DVec2::new(amount * rng.next(), amount * rng.next()) } else { p }
    });
    Mesh::new(p, grid.quads(), None).unwrap()
}

#[test]
fn the_region_grows_only_while_it_stays_small() {
    // An 80 x 80 grid (6,561 vertices) jittered evenly: every quad is about as good as the
    // worst, so a grown threshold takes in most of the mesh.
    let mesh = jittered_grid(80, 0.3, 7);
    let unbounded = MaxMinSettings { max_grown_region: usize::MAX, ..MaxMinSettings::default() };
    let (_, free) = run(&mesh, BoundaryMode::Fixed, &unbounded);
    assert!(
        free.largest_grown_region > 4096,
        "the grown region never exceeded the cap: {}",
        free.largest_grown_region
    );
    let capped = MaxMinSettings::default();
    assert_eq!(capped.max_grown_region, 4096);
    let (points, report) = run(&mesh, BoundaryMode::Fixed, &capped);
    assert!(report.largest_grown_region <= 4096, "{}", report.largest_grown_region);
    assert_monotone(&report);
    assert!(report.after.min > report.before.min, "{:?}", report.history);
    let values = quality(&points, mesh.quads());
    assert_eq!(values.iter().copied().fold(f64::INFINITY, f64::min), report.after.min);
    // Fixed boundary: the grid's outer vertices did not move.
    for (v, (a, b)) in points.iter().zip(mesh.points()).enumerate() {
        let (i, j) = (v % 81, v / 81);
        if !(1..80).contains(&i) || !(1..80).contains(&j) {
            assert_eq!((a.x.to_bits(), a.y.to_bits()), (b.x.to_bits(), b.y.to_bits()), "vertex {v}");
        }
    }
    println!(
        "capped: {} rounds, min {:.4}, largest grown region {}; unbounded: {} rounds, min {:.4}, {}",
        report.rounds,
        report.after.min,
        report.largest_grown_region,
        free.rounds,
        free.after.min,
        free.largest_grown_region
    );
}

#[test]
fn the_average_recovery_stops_when_a_sweep_gains_little() {
    let mesh = jittered_grid(16, 0.35, 11);
    let with = |gain: f64| {
        let settings = MaxMinSettings { average_min_gain: gain, ..MaxMinSettings::default() };
        run(&mesh, BoundaryMode::Fixed, &settings).1
    };
    // Every recovery sweep raises the average (each move raises its star's), so a sweep
    // always gains less than 1: one sweep; with no threshold it goes on to its cap or until
    // nothing moves.
    let (one, all, default) = (with(1.0), with(0.0), with(MaxMinSettings::default().average_min_gain));
    assert_eq!(one.average_sweeps, 1);
    assert!(
        all.average_sweeps > default.average_sweeps.max(1),
        "{} vs {}",
        all.average_sweeps,
        default.average_sweeps
    );
    assert!(all.average_sweeps <= MaxMinSettings::default().average_sweeps);
    for r in [&one, &all, &default] {
        assert_monotone(r);
    }
    assert!(all.after.avg >= default.after.avg && default.after.avg >= one.after.avg);
    assert!(all.after.avg > one.after.avg);
}

#[test]
fn the_average_recovery_covers_at_most_its_budget_of_vertices() {
    let mesh = jittered_grid(16, 0.35, 11);
    let vertices = mesh.points().len();
    let with = |per_vertex: f64| {
        let settings = MaxMinSettings {
            average_min_gain: 0.0,
            recovery_searches_per_vertex: per_vertex,
            min_recovery_searches: 0,
            ..MaxMinSettings::default()
        };
        run(&mesh, BoundaryMode::Fixed, &settings).1
    };
    // Without a budget the recovery runs several sweeps; each covers at most every vertex.
    let free = with(f64::INFINITY);
    assert!(free.average_sweeps >= 3, "{}", free.average_sweeps);
    // A budget of one vertex: the first sweep only (it always runs). Of 1.5 x the vertices:
    // fewer sweeps than without, each start within the budget.
    assert_eq!(with(1.0 / vertices as f64).average_sweeps, 1);
    let half = with(1.5);
    assert!(half.average_sweeps >= 1 && half.average_sweeps < free.average_sweeps);
    for r in [&free, &half] {
        assert_monotone(r);
    }
    assert!(free.after.avg >= half.after.avg);
    // The default's floor keeps the whole recovery on a mesh this small.
    let default = run(
        &mesh,
        BoundaryMode::Fixed,
        &MaxMinSettings { average_min_gain: 0.0, ..MaxMinSettings::default() },
    )
    .1;
    assert_eq!(default.average_sweeps, free.average_sweeps);
    assert_eq!(default.after, free.after);
}

/// The edges of face `q`, as pairs of vertex indices (three for a triangle).
fn face_edges(q: &[u32; 4]) -> impl Iterator<Item = (usize, usize)> + '_ {
    let n = quadopt::face::corner_count(q);
    (0..n).map(move |i| (q[i] as usize, q[(i + 1) % n] as usize))
}

/// Per face, min(0.1 x its longest edge, 0.5 x its shortest edge).
fn edge_floors(points: &[DVec2], quads: &[[u32; 4]]) -> Vec<f64> {
    quads
        .iter()
        .map(|q| {
            let e: Vec<f64> = face_edges(q).map(|(a, b)| points[a].distance(points[b])).collect();
            let longest = e.iter().copied().fold(0.0, f64::max);
            let shortest = e.iter().copied().fold(f64::INFINITY, f64::min);
            (0.1 * longest).min(0.5 * shortest)
        })
        .collect()
}

/// The scaled Jacobian does not see aspect ratio: a stage free to move would squash quads into
/// thin rectangles that score near 1 (it did, down to 1e-15 of a quad's size). No edge may end
/// shorter than a tenth of its quad's longest edge or half its shortest when the stage began,
/// on the jittered grids, on the hard meshes and on the sample meshes.
#[test]
fn no_edge_is_squashed_below_its_floor() {
    let mut meshes: Vec<(String, Mesh)> =
        (1..6).map(|s| (format!("jittered {s}"), jittered(9, 7, s))).collect();
    meshes.extend((1..4).map(|s| (format!("jittered grid {s}"), jittered_grid(12, 0.45, s))));
    meshes.extend(common::hard::hard_meshes().into_iter().map(|(n, m)| (n.to_string(), m)));
    for path in common::samples::sample_files() {
        let (name, mesh, _) = common::samples::load(&path);
        meshes.push((name, mesh));
    }
    for (name, mesh) in meshes {
        let floors = edge_floors(mesh.points(), mesh.quads());
        let (points, report) = run(&mesh, BoundaryMode::Slide, &MaxMinSettings::default());
        for (qi, q) in mesh.quads().iter().enumerate() {
            for (a, b) in face_edges(q) {
                let length = points[a].distance(points[b]);
                // Rounding: the floor is compared on squared lengths.
                assert!(
                    length >= floors[qi] * (1.0 - 1e-12),
                    "{name}: edge {a}-{b} of quad {qi} is {length:e} long, its floor {:e} ({} moves)",
                    floors[qi],
                    report.moves
                );
            }
        }
    }
}
