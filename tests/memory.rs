//! The memory the C ABI checks for before building a topology and running the optimizer
//! (`quadopt::ffi::topology_bytes`, `quadopt::ffi::run_bytes`) is an upper bound of what they
//! allocate at their peak, measured by a counting allocator over meshes of different shapes,
//! every method and every boundary mode. If the optimizer's memory grows, this test says by
//! how much the estimate in src/ffi/run.rs must grow.

use quadopt::ffi::{run_bytes, topology_bytes};
use quadopt::synthetic::Synthetic;
use quadopt::{BoundaryMode, Mesh, Method, Optimizer, Options};
#[path = "common/counting_alloc.rs"]
mod counting_alloc;
use counting_alloc::peak_of;

/// A fan of `n` quads around vertex 0, pushed outside it (as in tests/fans.rs): one vertex of
/// degree `n`, most quads inverted.
fn tangled_fan(n: u32) -> Mesh {
    use quadopt::DVec2;
    use std::f64::consts::TAU;
    let mut points = vec![DVec2::new(2.0, 0.3)];
    for i in 0..n {
        let (a, d) = (TAU * f64::from(i) / f64::from(n), TAU * (f64::from(i) + 0.5) / f64::from(n));
        points.push(DVec2::new(a.cos(), a.sin()));
        points.push(DVec2::new(d.cos(), d.sin()) * 1.5);
    }
    let quads = (0..n).map(|i| [0, 1 + 2 * i, 2 + 2 * i, 1 + 2 * ((i + 1) % n)]).collect();
    Mesh::new(points, quads, None).unwrap()
}

/// `mesh` with its vertices numbered in a scattered order (sorted by a multiplicative hash).
fn scattered(mesh: &Mesh) -> Mesh {
    let n = mesh.points().len();
    let mut old_of: Vec<u32> = (0..n as u32).collect();
    old_of.sort_by_key(|&v| v.wrapping_mul(2_654_435_761));
    let mut new_of = vec![0u32; n];
    for (i, &v) in old_of.iter().enumerate() {
        new_of[v as usize] = i as u32;
    }
    let points = old_of.iter().map(|&v| mesh.points()[v as usize]).collect();
    let quads = mesh.quads().iter().map(|q| q.map(|v| new_of[v as usize])).collect();
    Mesh::new(points, quads, None).unwrap()
}

/// (name, mesh): a plain grid, a tangled one, one with many holes, a strip whose every vertex
/// is on the boundary, a tangled fan, a tiny grid and one large enough to be renumbered.
fn meshes() -> Vec<(&'static str, Mesh)> {
    let s = Synthetic { nx: 80, ny: 80, ..Synthetic::default() };
    vec![
        ("grid", s.generate()),
        ("tangled grid", Synthetic { jitter: 0.45, ..s }.generate()),
        ("holes", Synthetic { holes: 200, ..s }.generate()),
        ("strip", Synthetic { nx: 3000, ny: 1, holes: 0, jitter: 0.0, ..s }.generate()),
        ("fan", tangled_fan(2000)),
        ("small", Synthetic { nx: 3, ny: 3, holes: 0, ..s }.generate()),
        // Above 16,384 vertices and numbered at random, the optimizer works on a renumbered
        // copy.
        ("renumbered", scattered(&Synthetic { nx: 150, ny: 150, ..s }.generate())),
    ]
}

#[test]
fn topology_and_runs_stay_within_the_memory_checked_for() {
    // One test, so nothing else allocates while it measures.
    let mut worst = (0.0f64, 0.0f64);
    for (name, mesh) in meshes() {
        let (optimizer, topology) = peak_of(|| Optimizer::new(&mesh));
        let estimate = topology_bytes(&mesh) as usize;
        assert!(
            topology <= estimate,
            "{name}: the topology took {topology} bytes, {estimate} were checked for"
        );
        worst.0 = worst.0.max(topology as f64 / estimate as f64);
        let mut run_worst = 0;
        for method in Method::ALL {
            for boundary in BoundaryMode::ALL {
                let options =
                    Options::default().with_method(method).with_boundary(boundary).with_max_iterations(20);
                let mut m = mesh.clone();
                let (report, run) = peak_of(|| optimizer.run(&mut m, &options, None));
                report.unwrap();
                let estimate = run_bytes(&mesh) as usize;
                assert!(
                    run <= estimate,
                    "{name}, {method:?}, {boundary:?}: the run took {run} bytes, {estimate} were checked for"
                );
                worst.1 = worst.1.max(run as f64 / estimate as f64);
                run_worst = run_worst.max(run);
            }
        }
        let (v, q, b) = (mesh.points().len(), mesh.quads().len(), mesh.boundary_edge_count());
        println!(
            "{name}: V {v} Q {q} B {b} topology {topology} ({:.1}/V) run {run_worst} ({:.1}/V)",
            topology as f64 / v as f64,
            run_worst as f64 / v as f64
        );
    }
    // Report how tight the estimates are (shown with --nocapture).
    println!("largest share of the estimate used: topology {:.2}, run {:.2}", worst.0, worst.1);
}
