//! Property tests (issue 4, item 6): the optimizer's and the readers' guarantees on random
//! meshes and random input.
//!
//! Meshes are built deterministically from plain generated values (sizes, flags, jitter
//! amounts), so proptest shrinks a failure to a small grid or polygon with little jitter:
//! - structured grids (anisotropic, rotated) with random cells removed (holes, notches,
//!   bowtie vertices, several components);
//! - unstructured quad meshes: a random convex polygon split into a triangle fan from its
//!   centroid, each triangle split into three quads by midpoint subdivision, optionally
//!   refined once more (interior valences 3, 4, 6 and the polygon's vertex count);
//! - every vertex jittered by a fraction of its shortest edge, some vertices folded across
//!   a neighbour (inverted quads), random fixed flags, quads given clockwise or with a
//!   rotated first vertex, some quads split into two triangles (quad-dominant meshes).
//!
//! Properties: no panic for any mesh and any options (valid or not); with default options
//! and every method and boundary mode no more inverted quads and no lower minimum scaled
//! Jacobian than the input, and a report that tells the truth; fixed, corner and
//! non-movable vertices bit-identical; boundary vertices on the original boundary polyline;
//! connectivity unchanged; the same output bit for bit on 1, 2 and 4 threads. Readers: any
//! bytes give `Ok` or `Err` for every format, and write-then-read is bit-identical.
//!
//! Case counts keep the file at a few seconds in release on two cores; raise them with
//! the `PROPTEST_CASES` environment variable for a longer search.

mod common;

use common::grids::Grid;
use proptest::prelude::*;
use proptest::test_runner::TestCaseError;
use quadopt::Features;
use quadopt::io::{self, Encoding, Format, MeshData, MshVersion};
use quadopt::{
    BoundaryMode, DVec2, Effort, Error, Mesh, Method, Optimizer, Options, Report, StopRule, optimize,
};
use quadopt::{Topology, VertexKind};
use std::collections::HashMap;

// ---------------------------------------------------------------------------------------
// Mesh generators
// ---------------------------------------------------------------------------------------

/// Per-vertex and per-quad random values are taken from arrays of this length (index
/// modulo the length), so a case is a fixed-shape value that shrinks element by element.
const TABLE: usize = 128;

/// The connectivity and undisturbed positions a case starts from.
#[derive(Clone, Debug)]
enum Base {
    /// An `nx` by `ny` grid with cell sizes `sx` by `sy`, rotated by `angle`, without the
    /// cells whose `removed` flag is set (cell (i, j) reads flag j * nx + i).
    Grid { nx: usize, ny: usize, sx: f64, sy: f64, angle: f64, removed: Vec<bool> },
    /// A convex polygon: `gaps` (positive, one per vertex) spaced round an ellipse with
    /// semi-axes `a` and `b`; triangle fan from the centroid, three quads per triangle,
    /// `refine` further midpoint subdivisions.
    Polygon { gaps: Vec<f64>, a: f64, b: f64, refine: u8 },
}

/// A generated mesh: a base, then disturbances.
#[derive(Clone, Debug)]
struct Case {
    base: Base,
    /// Jitter amplitude as a fraction of each vertex's shortest edge (above ~0.5 folds quads).
    amplitude: f64,
    /// Jitter directions in [-1, 1]^2, per vertex (modulo [`TABLE`]).
    jitter: Vec<(f64, f64)>,
    /// Whether boundary vertices are jittered too (moves the boundary itself).
    jitter_boundary: bool,
    /// Vertices (modulo the vertex count) moved across their first neighbour: folds.
    folds: Vec<usize>,
    /// Fixed flag per vertex (modulo [`TABLE`]).
    fixed: Vec<bool>,
    /// Give every quad clockwise.
    clockwise: bool,
    /// First-corner rotation per quad (modulo [`TABLE`]).
    rotate: Vec<u8>,
    /// Quads split along their first diagonal into two triangles (modulo [`TABLE`]; empty:
    /// none): quad-dominant meshes.
    split: Vec<bool>,
}

fn grid_base() -> impl Strategy<Value = Base> {
    (
        1usize..=7,
        1usize..=7,
        prop_oneof![Just(1.0), 0.05f64..20.0],
        prop_oneof![Just(1.0), 0.05f64..20.0],
        prop_oneof![Just(0.0), 0.0f64..std::f64::consts::TAU],
        prop::collection::vec(prop::bool::weighted(0.15), 49),
    )
        .prop_map(|(nx, ny, sx, sy, angle, removed)| Base::Grid { nx, ny, sx, sy, angle, removed })
}

fn polygon_base() -> impl Strategy<Value = Base> {
    (prop::collection::vec(0.1f64..1.0, 3..=9), 0.2f64..5.0, 0.2f64..5.0, 0u8..=1)
        .prop_map(|(gaps, a, b, refine)| Base::Polygon { gaps, a, b, refine })
}

fn case() -> impl Strategy<Value = Case> {
    (
        prop_oneof![grid_base(), polygon_base()],
        prop_oneof![Just(0.0), 0.0f64..0.45, 0.45f64..0.95],
        prop::collection::vec((-1.0f64..1.0, -1.0f64..1.0), TABLE),
        prop::bool::weighted(0.2),
        prop_oneof![2 => Just(Vec::new()), 1 => prop::collection::vec(any::<usize>(), 1..3)],
        prop::collection::vec(prop::bool::weighted(0.1), TABLE),
        prop::bool::weighted(0.2),
        prop::collection::vec(0u8..4, TABLE),
        prop_oneof![2 => Just(Vec::new()), 1 => prop::collection::vec(prop::bool::weighted(0.3), TABLE)],
    )
        .prop_map(
            |(base, amplitude, jitter, jitter_boundary, folds, fixed, clockwise, rotate, split)| Case {
                base,
                amplitude,
                jitter,
                jitter_boundary,
                folds,
                fixed,
                clockwise,
                rotate,
                split,
            },
        )
}

/// Points and quads of a base (quads counter-clockwise).
fn base_mesh(base: &Base) -> (Vec<DVec2>, Vec<[u32; 4]>) {
    match base {
        Base::Grid { nx, ny, sx, sy, angle, removed } => {
            let (grid, rot) = (Grid::new(*nx, *ny), DVec2::from_angle(*angle));
            let p = grid.points(|i, j| rot.rotate(DVec2::new(i as f64 * sx, j as f64 * sy)));
            (p, grid.quads_without(|i, j| removed[(j * nx + i) % removed.len()]))
        }
        Base::Polygon { gaps, a, b, refine } => {
            let total: f64 = gaps.iter().sum();
            let mut t: f64 = 0.0;
            let mut p: Vec<DVec2> = Vec::new();
            for g in gaps {
                p.push(DVec2::new(a * t.cos(), b * t.sin()));
                t += g / total * std::f64::consts::TAU;
            }
            let k = p.len();
            let centre = p.iter().copied().sum::<DVec2>() / k as f64;
            p.push(centre);
            let mut mids = HashMap::new();
            let mut quads = Vec::new();
            for i in 0..k {
                let tri = [k as u32, i as u32, ((i + 1) % k) as u32];
                let g = p.len() as u32;
                p.push((p[tri[0] as usize] + p[tri[1] as usize] + p[tri[2] as usize]) / 3.0);
                let m: Vec<u32> =
                    (0..3).map(|e| midpoint(&mut p, &mut mids, tri[e], tri[(e + 1) % 3])).collect();
                // Triangle (t0, t1, t2), midpoints m0 = t0t1, m1 = t1t2, m2 = t2t0.
                quads.push([tri[0], m[0], g, m[2]]);
                quads.push([tri[1], m[1], g, m[0]]);
                quads.push([tri[2], m[2], g, m[1]]);
            }
            for _ in 0..*refine {
                let mut mids = HashMap::new();
                let mut finer = Vec::with_capacity(quads.len() * 4);
                for q in &quads {
                    let c = p.len() as u32;
                    p.push(q.iter().map(|&v| p[v as usize]).sum::<DVec2>() / 4.0);
                    let m: Vec<u32> =
                        (0..4).map(|e| midpoint(&mut p, &mut mids, q[e], q[(e + 1) % 4])).collect();
                    for e in 0..4 {
                        finer.push([q[e], m[e], c, m[(e + 3) % 4]]);
                    }
                }
                quads = finer;
            }
            (p, quads)
        }
    }
}

/// The midpoint vertex of edge (a, b), created once.
fn midpoint(p: &mut Vec<DVec2>, mids: &mut HashMap<(u32, u32), u32>, a: u32, b: u32) -> u32 {
    *mids.entry((a.min(b), a.max(b))).or_insert_with(|| {
        p.push(0.5 * (p[a as usize] + p[b as usize]));
        p.len() as u32 - 1
    })
}

/// Builds the case's arrays (not validated).
fn build_arrays(case: &Case) -> (Vec<DVec2>, Vec<[u32; 4]>, Vec<bool>) {
    let (mut p, mut q) = base_mesh(&case.base);
    let n = p.len();
    let mut shortest = vec![f64::INFINITY; n];
    let mut uses = vec![0usize; n];
    for quad in &q {
        for e in 0..4 {
            let (a, b) = (quad[e] as usize, quad[(e + 1) % 4] as usize);
            let l = (p[a] - p[b]).length();
            shortest[a] = shortest[a].min(l);
            shortest[b] = shortest[b].min(l);
            uses[a] += 1;
        }
    }
    let boundary = boundary_flags(n, &q);
    let original = p.clone();
    for v in 0..n {
        if shortest[v].is_finite() && (case.jitter_boundary || !boundary[v]) {
            let (dx, dy) = case.jitter[v % TABLE];
            p[v] += case.amplitude * shortest[v] * DVec2::new(dx, dy);
        }
    }
    for &f in &case.folds {
        let v = f % n;
        // Its first quad neighbour: move v 1.5 times across it, inverting the quads between.
        if let Some(quad) = q.iter().find(|quad| quad.contains(&(v as u32))) {
            let k = quad.iter().position(|&x| x as usize == v).unwrap();
            let u = quad[(k + 1) % 4] as usize;
            p[v] = original[u] + 0.5 * (original[u] - original[v]);
        }
    }
    for (i, quad) in q.iter_mut().enumerate() {
        if case.clockwise {
            quad.reverse();
        }
        quad.rotate_left(case.rotate[i % TABLE] as usize);
    }
    if !case.split.is_empty() {
        q = q
            .iter()
            .enumerate()
            .flat_map(|(i, &[a, b, c, d])| {
                if case.split[i % TABLE] {
                    vec![quadopt::face::triangle(a, b, c), quadopt::face::triangle(a, c, d)]
                } else {
                    vec![[a, b, c, d]]
                }
            })
            .collect();
    }
    let fixed = (0..n).map(|v| case.fixed[v % TABLE]).collect();
    (p, q, fixed)
}

/// Vertices on an edge used by one quad.
fn boundary_flags(n: usize, quads: &[[u32; 4]]) -> Vec<bool> {
    let mut count: HashMap<(u32, u32), u32> = HashMap::new();
    for q in quads {
        for e in 0..4 {
            let (a, b) = (q[e], q[(e + 1) % 4]);
            *count.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    let mut flags = vec![false; n];
    for (&(a, b), &c) in &count {
        if c == 1 {
            flags[a as usize] = true;
            flags[b as usize] = true;
        }
    }
    flags
}

/// The case's mesh, or the typed error validation gives.
fn build(case: &Case) -> Result<Mesh, Error> {
    let (p, q, fixed) = build_arrays(case);
    Mesh::with_faces(p, q, Some(fixed))
}

/// The case's mesh; cases that do not validate (every cell removed) are rejected.
fn valid(case: &Case) -> Result<Mesh, TestCaseError> {
    match build(case) {
        Ok(m) => Ok(m),
        Err(Error::NoQuads) => Err(TestCaseError::reject("every cell removed")),
        Err(e) => Err(TestCaseError::fail(format!("a generated mesh failed to validate: {e}"))),
    }
}

/// Proptest settings with `cases` cases, unless the `PROPTEST_CASES` environment variable
/// asks for another number.
fn config(cases: u32) -> ProptestConfig {
    let cases = std::env::var("PROPTEST_CASES").ok().and_then(|c| c.parse().ok()).unwrap_or(cases);
    ProptestConfig { cases, max_global_rejects: 4096, ..ProptestConfig::default() }
}

#[test]
fn generated_meshes_really_are_varied_and_hard() {
    // The generators must produce what the module docs claim, or the properties prove little.
    use proptest::strategy::ValueTree;
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    let (mut inverted, mut holes, mut bowties, mut fixed, mut clockwise, mut polygons, mut n) =
        (0, 0, 0, 0, 0, 0, 0);
    let (mut largest, mut mixed) = (0, 0);
    for _ in 0..400 {
        let case = case().new_tree(&mut runner).unwrap().current();
        let Ok(mesh) = build(&case) else { continue };
        n += 1;
        let topo = Topology::new(&mesh);
        inverted += usize::from(mesh.quality().inverted > 0);
        holes += usize::from(topo.loop_count() > 1);
        bowties += usize::from((0..topo.vertex_count()).any(|v| topo.kind(v) == VertexKind::NonManifold));
        fixed += usize::from(mesh.fixed().iter().any(|&f| f));
        clockwise += usize::from(mesh.has_clockwise_component());
        polygons += usize::from(matches!(case.base, Base::Polygon { .. }));
        mixed += usize::from(mesh.triangle_count() > 0);
        largest = largest.max(mesh.points().len());
    }
    assert!(n >= 390, "{n} of 400 cases validate");
    // Both tangled and valid inputs, so the quality property is tested on valid meshes too.
    assert!((n - inverted) * 4 >= n, "only {} of {n} meshes are valid", n - inverted);
    for (what, count) in [
        ("inverted", inverted),
        ("holes", holes),
        ("bowties", bowties),
        ("fixed", fixed),
        ("clockwise", clockwise),
        ("polygons", polygons),
        ("triangles", mixed),
    ] {
        assert!(count * 20 >= n, "only {count} of {n} meshes have {what}");
    }
    assert!(largest >= 100, "largest mesh has {largest} vertices");
}

// ---------------------------------------------------------------------------------------
// Option generators
// ---------------------------------------------------------------------------------------

fn method() -> impl Strategy<Value = Method> {
    prop::sample::select(Method::ALL.to_vec())
}

fn boundary_mode() -> impl Strategy<Value = BoundaryMode> {
    prop::sample::select(BoundaryMode::ALL.to_vec())
}

/// Options from drawn values, every field set; the stopping rule is drawn with the energy
/// rule's own flag, the max-min stage with the guard's flag and the effort preset with the
/// iteration cap, so both rules, both stage settings and every preset are covered without
/// extra draws.
fn drawn_options(
    (method, boundary, lambda): (Method, BoundaryMode, f64),
    (tau, tau_absolute, max_iterations): (f64, bool, usize),
    (feature_angle_deg, guard, guard_floor): (f64, bool, f64),
    (untangle, keep_best, max_boundary_deviation): (bool, bool, Option<f64>),
) -> Options {
    Options::DEFAULT
        .with_method(method)
        .with_boundary(boundary)
        .with_lambda(lambda)
        .with_stop(if tau_absolute { StopRule::Energy } else { StopRule::Quality })
        .with_max_min(guard)
        .with_tau(tau)
        .with_tau_absolute(tau_absolute)
        .with_max_iterations(max_iterations)
        .with_feature_angle_deg(feature_angle_deg)
        .with_guard(guard)
        .with_guard_floor(guard_floor)
        .with_untangle(untangle)
        .with_keep_best(keep_best)
        .with_max_boundary_deviation(max_boundary_deviation)
        .with_effort(Effort::ALL[max_iterations % Effort::ALL.len()])
}

/// Valid options of every kind, with a small iteration cap.
fn valid_options() -> impl Strategy<Value = Options> {
    (
        (method(), boundary_mode(), prop_oneof![Just(1.0), 0.01f64..=1.0]),
        (prop_oneof![Just(1e-7), Just(0.0), 1e-12f64..1e-2], any::<bool>(), 1usize..40),
        (prop_oneof![Just(45.0), 0.0f64..=180.0], any::<bool>(), prop_oneof![Just(0.05), 1e-6f64..=1.0]),
        (any::<bool>(), any::<bool>(), prop::option::of(0.0f64..1.0)),
    )
        .prop_map(|(a, b, c, d)| drawn_options(a, b, c, d))
}

/// Any f64, weighted towards values at and beyond the edges of the option ranges.
fn wild_f64() -> impl Strategy<Value = f64> {
    prop_oneof![
        Just(f64::NAN),
        Just(f64::INFINITY),
        Just(f64::NEG_INFINITY),
        Just(0.0),
        Just(-0.0),
        Just(1.0),
        Just(180.0),
        Just(f64::MIN_POSITIVE),
        -2.0f64..200.0,
        any::<u64>().prop_map(f64::from_bits),
    ]
}

/// Options that may be invalid in every field.
fn any_options() -> impl Strategy<Value = Options> {
    (
        (method(), boundary_mode(), wild_f64(), wild_f64(), any::<bool>(), 0usize..30),
        (wild_f64(), any::<bool>(), wild_f64(), any::<bool>(), any::<bool>()),
        prop::option::of(wild_f64()),
    )
        .prop_map(|((m, b, lambda, tau, tau_abs, iters), (fa, guard, floor, untangle, best), dev)| {
            drawn_options((m, b, lambda), (tau, tau_abs, iters), (fa, guard, floor), (untangle, best, dev))
        })
}

// ---------------------------------------------------------------------------------------
// Checks
// ---------------------------------------------------------------------------------------

fn same_bits(a: DVec2, b: DVec2) -> bool {
    a.x.to_bits() == b.x.to_bits() && a.y.to_bits() == b.y.to_bits()
}

fn bbox_diagonal(points: &[DVec2]) -> f64 {
    let (lo, hi) =
        points.iter().fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(l, h), &p| (l.min(p), h.max(p)));
    (hi - lo).length()
}

/// Distance from `p` to the closed polyline through `loop_points`.
fn distance_to_loop(p: DVec2, loop_points: &[DVec2]) -> f64 {
    let n = loop_points.len();
    (0..n)
        .map(|i| {
            let (a, b) = (loop_points[i], loop_points[(i + 1) % n]);
            let d = b - a;
            let len2 = d.length_squared();
            let t = if len2 > 0.0 { ((p - a).dot(d) / len2).clamp(0.0, 1.0) } else { 0.0 };
            (a + d * t - p).length()
        })
        .fold(f64::INFINITY, f64::min)
}

/// Fixed, corner, non-manifold, unused and (in `Fixed` mode) boundary vertices did not move
/// by a single bit; every boundary vertex lies on its original boundary loop.
fn check_preserved(before: &Mesh, after: &Mesh, options: &Options) -> Result<(), TestCaseError> {
    let topo = Topology::new(before);
    let features =
        Features::new(before, &topo, options.feature_angle_deg, options.boundary != BoundaryMode::Fixed);
    for v in 0..before.points().len() {
        let (a, b) = (before.points()[v], after.points()[v]);
        let pinned = before.fixed()[v]
            || features.is_corner(v)
            || matches!(topo.kind(v), VertexKind::Unused | VertexKind::NonManifold)
            || (features.is_boundary(v) && options.boundary == BoundaryMode::Fixed);
        prop_assert!(!pinned || same_bits(a, b), "pinned vertex {v} moved from {a} to {b}");
        prop_assert!(pinned != features.is_movable(v), "vertex {v}: movable flag disagrees");
    }
    let tol = 1e-9 * bbox_diagonal(before.points());
    for lp in topo.boundary_loops() {
        let orig: Vec<DVec2> = lp.iter().map(|&v| before.points()[v as usize]).collect();
        for &v in lp {
            let d = distance_to_loop(after.points()[v as usize], &orig);
            prop_assert!(d <= tol, "boundary vertex {v} is {d:e} off the original boundary (tol {tol:e})");
        }
    }
    Ok(())
}

/// Everything in a report except the wall-clock time.
fn report_without_time(r: &Report) -> Report {
    let mut r = r.clone();
    r.seconds = 0.0;
    if let Some(g) = &mut r.max_min {
        g.seconds = 0.0;
    }
    r
}

// ---------------------------------------------------------------------------------------
// Optimizer properties
// ---------------------------------------------------------------------------------------

proptest! {
    #![proptest_config(config(96))]

    /// Any mesh, any options (valid or not), any vertex count, any cancellation: the result
    /// is `Ok` or a typed `Err`, and invalid options give `InvalidOption`.
    #[test]
    fn never_panics(case in case(), options in any_options(), cancel_after in prop::option::of(0usize..5),
                    wrong_count in any::<bool>()) {
        let mut mesh = match build(&case) {
            Ok(m) => m,
            // Validation errors are typed; only NoQuads can come from these generators.
            Err(e) => { prop_assert_eq!(e, Error::NoQuads); return Ok(()); }
        };
        let optimizer = Optimizer::new(&mesh);
        let mut calls = 0usize;
        let mut cb = |_: &quadopt::Progress| { calls += 1; cancel_after.is_none_or(|c| calls <= c) };
        if wrong_count {
            let (mut p, q, _) = build_arrays(&case);
            p.push(DVec2::ZERO);
            let mut other = Mesh::with_faces(p, q, None).unwrap();
            let r = optimizer.run(&mut other, &Options::default(), None);
            prop_assert!(matches!(r, Err(Error::VertexCountMismatch { .. })), "{:?}", r);
        }
        let result = optimizer.run(&mut mesh, &options, Some(&mut cb));
        match options.validate() {
            Err(e) => {
                prop_assert!(matches!(e, Error::InvalidOption { .. }), "{:?}", e);
                prop_assert_eq!(result.unwrap_err(), e);
            }
            Ok(()) => {
                let r = result.unwrap();
                prop_assert!(mesh.points().iter().all(|p| p.is_finite()), "non-finite output");
                prop_assert!(r.iterations <= options.max_iterations);
            }
        }
    }
}

proptest! {
    #![proptest_config(config(16))]

    /// Default options, every method and boundary mode: no more inverted quads than the
    /// input, minimum scaled Jacobian not below the input's, and the report's output
    /// statistics are those of the returned mesh.
    #[test]
    fn default_options_never_lose_quality(case in case()) {
        let mesh = valid(&case)?;
        let input = mesh.quality();
        for method in Method::ALL {
            for boundary in BoundaryMode::ALL {
                let mut out = mesh.clone();
                let r = optimize(&mut out, &Options::default().with_method(method).with_boundary(boundary)).unwrap();
                let got = out.quality();
                prop_assert_eq!(r.input, input);
                prop_assert_eq!(r.output, got, "{:?}/{:?}: report differs from the mesh", method, boundary);
                prop_assert!(got.inverted <= input.inverted,
                    "{:?}/{:?}: inverted {} -> {}", method, boundary, input.inverted, got.inverted);
                prop_assert!(got.min >= input.min,
                    "{:?}/{:?}: min {} -> {}", method, boundary, input.min, got.min);
                prop_assert_eq!(r.tangled.len(), got.inverted, "{:?}/{:?}: the diagnosis {:?} against the output's values {:?}",
                    method, boundary, r.tangled, out.quality_values());
                let (before, after) = (mesh.quality_values(), out.quality_values());
                let new = (0..before.len()).find(|&q| before[q] > 0.0 && after[q] <= 0.0);
                prop_assert!(new.is_none(), "{:?}/{:?}: quad {:?} was valid and is inverted", method, boundary, new);
            }
        }
    }
}

proptest! {
    #![proptest_config(config(64))]

    /// Any valid options: fixed, corner and other non-movable vertices bit-identical, and
    /// boundary vertices on the original boundary polyline (<= 1e-9 of the bbox diagonal).
    #[test]
    fn pinned_vertices_and_boundary_are_preserved(case in case(), options in valid_options()) {
        let mesh = valid(&case)?;
        let mut out = mesh.clone();
        optimize(&mut out, &options).unwrap();
        check_preserved(&mesh, &out, &options)?;
    }

    /// Default options (full iteration cap): the same preservation guarantees.
    #[test]
    fn default_options_preserve_pinned_vertices_and_boundary(case in case(), method in method(),
                                                             boundary in boundary_mode()) {
        let mesh = valid(&case)?;
        let options = Options::default().with_method(method).with_boundary(boundary);
        let mut out = mesh.clone();
        optimize(&mut out, &options).unwrap();
        check_preserved(&mesh, &out, &options)?;
    }

    /// Connectivity, orientation bookkeeping and fixed flags never change.
    #[test]
    fn topology_is_unchanged(case in case(), options in valid_options()) {
        let mesh = valid(&case)?;
        let mut out = mesh.clone();
        optimize(&mut out, &options).unwrap();
        prop_assert_eq!(out.points().len(), mesh.points().len());
        prop_assert_eq!(out.quads(), mesh.quads());
        prop_assert_eq!(out.quads_as_given(), mesh.quads_as_given());
        prop_assert_eq!(out.fixed(), mesh.fixed());
        prop_assert_eq!(out.reoriented(), mesh.reoriented());
        let (t0, t1) = (Topology::new(&mesh), Topology::new(&out));
        prop_assert_eq!(t0.loop_count(), t1.loop_count());
        for v in 0..t0.vertex_count() {
            prop_assert_eq!(t0.ring(v), t1.ring(v));
            prop_assert_eq!(t0.kind(v), t1.kind(v));
        }
    }
}

proptest! {
    #![proptest_config(config(32))]

    /// The output (positions and report) is bit-identical on 1, 2 and 4 threads.
    #[test]
    fn output_does_not_depend_on_thread_count(case in case(), options in valid_options(),
                                              full in any::<bool>()) {
        let mesh = valid(&case)?;
        let options = if full { Options::default().with_method(options.method).with_boundary(options.boundary) } else { options };
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            let mut out = mesh.clone();
            let r = pool.install(|| optimize(&mut out, &options)).unwrap();
            (out.points().iter().map(|p| (p.x.to_bits(), p.y.to_bits())).collect::<Vec<_>>(), report_without_time(&r))
        };
        let one = run(1);
        for threads in [2, 4] {
            let other = run(threads);
            prop_assert!(one.0 == other.0, "positions differ between 1 and {} threads", threads);
            prop_assert_eq!(&one.1, &other.1, "reports differ between 1 and {} threads", threads);
        }
    }
}

// ---------------------------------------------------------------------------------------
// Reader properties
// ---------------------------------------------------------------------------------------

/// Tokens that stress number parsing and counts.
fn nasty_token() -> impl Strategy<Value = String> {
    prop_oneof![
        Just("18446744073709551615".to_string()),
        Just("18446744073709551616".to_string()),
        Just("4294967295".to_string()),
        Just("4294967296".to_string()),
        Just("-1".to_string()),
        Just("-9223372036854775808".to_string()),
        Just("0".to_string()),
        Just("1e309".to_string()),
        Just("nan".to_string()),
        Just("inf".to_string()),
        Just("$EndNodes".to_string()),
        Just("$Elements".to_string()),
        Just("OFFSETS vtktypeint64".to_string()),
        Just("CONNECTIVITY vtktypeint64".to_string()),
        Just("POINT_DATA".to_string()),
        Just("SCALARS fixed int 1".to_string()),
        Just("FIELD FieldData 1".to_string()),
        Just("f 1 2 3 4".to_string()),
        Just("v 1 2".to_string()),
        Just("1/2/3".to_string()),
        Just("\n".to_string()),
        Just("\n\n".to_string()),
        Just("#".to_string()),
        Just("\u{e9}".to_string()),
        (0u64..30).prop_map(|v| v.to_string()),
        "[ -~]{0,8}",
    ]
}

/// A small valid file of `format`, then random edits: deleted spans, inserted tokens,
/// replaced tokens.
fn mutated_file() -> impl Strategy<Value = (Format, Vec<u8>)> {
    (
        prop::sample::select(Format::ALL.to_vec()),
        any::<bool>(),
        any::<bool>(),
        prop::collection::vec(
            (any::<prop::sample::Index>(), 0usize..4, prop::option::of(nasty_token())),
            0..6,
        ),
    )
        .prop_map(|(format, v2, with_fixed, edits)| {
            let mut data = MeshData::new(
                vec![
                    [0.0, 0.0, 0.0],
                    [1.0, 0.0, 0.0],
                    [1.0, 1.0, 0.0],
                    [0.0, 1.0, 0.0],
                    [2.0, 0.0, 0.0],
                    [2.0, 1.0, 0.0],
                ],
                vec![[0, 1, 2, 3], [1, 4, 5, 2]],
            );
            data.msh_version = Some(if v2 { MshVersion::V2_2 } else { MshVersion::V4_1 });
            data.vtk_polydata = v2;
            // VTU: ASCII, or base64 (zlib-compressed with the fixed flags).
            data.encoding = if v2 && format == Format::Vtu { Encoding::Binary } else { Encoding::Ascii };
            data.compressed = with_fixed;
            if with_fixed {
                data.fixed = Some(vec![true, false, false, true, false, true]);
            }
            let text = io::write_mesh_string(format, &data).unwrap();
            let mut toks: Vec<String> = text.split(' ').map(str::to_string).collect();
            for (at, delete, insert) in edits {
                if toks.is_empty() {
                    break;
                }
                let i = at.index(toks.len());
                let end = (i + delete).min(toks.len());
                toks.splice(i..end, insert);
            }
            (format, toks.join(" ").into_bytes())
        })
}

proptest! {
    #![proptest_config(config(400))]

    /// Arbitrary bytes: every reader returns `Ok` or `Err`, never panics; an `Ok` mesh has
    /// every index in range.
    #[test]
    fn readers_never_panic_on_arbitrary_bytes(bytes in prop::collection::vec(any::<u8>(), 0..256)) {
        for format in Format::ALL {
            if let Ok(d) = io::read_mesh_bytes(&bytes, format) {
                prop_assert!(d.check().is_ok());
            }
        }
    }

    /// Valid files with random edits (the bytes reach deep into each reader).
    #[test]
    fn readers_never_panic_on_mutated_files((format, bytes) in mutated_file()) {
        if let Ok(d) = io::read_mesh_bytes(&bytes, format) {
            prop_assert!(d.check().is_ok());
            prop_assert!(d.quads.iter().flat_map(quadopt::face::vertices).all(|&v| (v as usize) < d.points.len()));
        }
    }
}

/// Any f64 but NaN (whose payload no text format keeps).
fn coordinate() -> impl Strategy<Value = f64> {
    prop_oneof![
        any::<u64>().prop_map(f64::from_bits).prop_filter("NaN", |x| !x.is_nan()),
        -10.0f64..10.0,
        Just(-0.0),
        Just(f64::MIN_POSITIVE / 3.0),
    ]
}

fn mesh_data() -> impl Strategy<Value = MeshData> {
    (1usize..24)
        .prop_flat_map(|n| {
            (
                prop::collection::vec([coordinate(), coordinate(), coordinate()], n),
                prop::collection::vec([0..n as u32, 0..n as u32, 0..n as u32, 0..n as u32], 0..16),
                prop::option::of(prop::collection::vec(any::<bool>(), n)),
                prop::option::of(prop_oneof![Just(MshVersion::V2_2), Just(MshVersion::V4_1)]),
                any::<bool>(),
            )
        })
        .prop_map(|(points, quads, fixed, msh_version, vtk_polydata)| MeshData {
            points,
            quads,
            fixed,
            msh_version,
            vtk_polydata,
            ..MeshData::default()
        })
}

fn point_bits(points: &[[f64; 3]]) -> Vec<[u64; 3]> {
    points.iter().map(|p| p.map(f64::to_bits)).collect()
}

proptest! {
    #![proptest_config(config(200))]

    /// Write then read gives back the same points (bit for bit), quads and, where the format
    /// stores them, fixed flags, MSH version and VTK dataset kind; VTU in every encoding, with
    /// and without zlib; binary MSH.
    #[test]
    fn write_read_round_trips_bit_identical(data in mesh_data()) {
        let vtu_variants = [Encoding::Ascii, Encoding::Binary, Encoding::Appended]
            .into_iter()
            .flat_map(|e| [(e, false), (e, true)]);
        let variants = Format::ALL
            .into_iter()
            .filter(|&f| f != Format::Vtu)
            .map(|f| (f, Encoding::Ascii, false))
            .chain(vtu_variants.map(|(e, z)| (Format::Vtu, e, z)))
            .chain([(Format::Msh, Encoding::Binary, false)]);
        for (format, encoding, compressed) in variants {
            let data = MeshData { encoding, compressed, ..data.clone() };
            let bytes = io::write_mesh_bytes(format, &data).unwrap();
            let back = io::read_mesh_bytes(&bytes, format).unwrap();
            prop_assert_eq!(point_bits(&back.points), point_bits(&data.points), "{:?}", format);
            prop_assert_eq!(&back.quads, &data.quads, "{:?}", format);
            match format {
                Format::Vtk => {
                    prop_assert_eq!(&back.fixed, &data.fixed);
                    prop_assert_eq!(back.vtk_polydata, data.vtk_polydata);
                }
                Format::Msh if encoding == Encoding::Binary => {
                    // Binary is 4.1 only.
                    prop_assert_eq!(back.msh_version, Some(MshVersion::V4_1));
                    prop_assert_eq!(&back.fixed, &data.fixed);
                }
                Format::Msh => {
                    prop_assert_eq!(back.msh_version, Some(data.msh_version.unwrap_or_default()));
                }
                Format::Vtu => {
                    prop_assert_eq!(&back.fixed, &data.fixed);
                    prop_assert_eq!(back.encoding, encoding);
                    prop_assert_eq!(back.compressed, compressed && encoding != Encoding::Ascii);
                }
                Format::Obj | Format::Off => prop_assert_eq!(&back.fixed, &None),
            }
            // A second trip writes the same bytes.
            prop_assert_eq!(io::write_mesh_bytes(format, &back).unwrap(), bytes);
        }
    }
}

// ---------------------------------------------------------------------------------------
// Regressions
// ---------------------------------------------------------------------------------------

/// A mesh saved from a property failure (tests/data/fuzz/), with its fixed flags.
fn saved_mesh(name: &str) -> Mesh {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/fuzz").join(name);
    let data = io::read_mesh(&path).unwrap();
    io::PlanarMesh::new(&data).unwrap().mesh
}

/// Per method and boundary mode: (inverted quads in the output, quads valid in the input
/// but inverted in the output).
fn new_inversions(mesh: &Mesh) -> Vec<(Method, BoundaryMode, usize, usize)> {
    let before = mesh.quality_values();
    let mut out = Vec::new();
    for method in Method::ALL {
        for boundary in BoundaryMode::ALL {
            let mut m = mesh.clone();
            optimize(&mut m, &Options::default().with_method(method).with_boundary(boundary)).unwrap();
            let after = m.quality_values();
            let new = before.iter().zip(&after).filter(|&(&a, &b)| a > 0.0 && b <= 0.0).count();
            out.push((method, boundary, after.iter().filter(|&&v| v <= 0.0).count(), new));
        }
    }
    out
}

/// The counterexample below still keeps the guarantees the optimizer makes: fewer inverted
/// quads than its 20, minimum not lower, pinned vertices and boundary preserved.
#[test]
fn tangled_polygon_mesh_keeps_the_count_guarantees() {
    let mesh = saved_mesh("property_new_inverted_quad.vtk");
    let input = mesh.quality();
    assert_eq!(input.inverted, 20);
    for method in Method::ALL {
        for boundary in BoundaryMode::ALL {
            let options = Options::default().with_method(method).with_boundary(boundary);
            let mut out = mesh.clone();
            let r = optimize(&mut out, &options).unwrap();
            assert!(
                r.output.inverted <= input.inverted && r.output.min >= input.min,
                "{method:?} {boundary:?}"
            );
            check_preserved(&mesh, &out, &options).unwrap();
        }
    }
}

/// Found by a property test of the stronger reading of "no new inverted quads" (no quad
/// that is valid in the input is inverted in the output), minimized by proptest: a refined
/// hexagon, 85 vertices and 72 quads, jittered by 0.73 of the shortest edge, 20 quads
/// inverted, 4 fixed vertices (its boundary jittered too, so some inversions cannot be
/// repaired). Ranking iterates by the inverted count alone returned 16 inverted quads, 8 of
/// them valid in the input (e.g. quad 24: 0.0783 -> -0.0252, angle-based, fixed boundary),
/// trading new inversions for repaired ones. The optimizer now never returns an iterate that
/// inverts a quad valid in the input.
#[test]
fn no_quad_valid_in_the_input_becomes_inverted() {
    let mesh = saved_mesh("property_new_inverted_quad.vtk");
    let bad: Vec<_> = new_inversions(&mesh).into_iter().filter(|r| r.3 > 0).collect();
    assert!(bad.is_empty(), "(method, mode, inverted of 20, newly inverted): {bad:?}");
}

/// Runs `f` on another thread and fails if it takes longer than `seconds` (a hang found by
/// fuzzing must fail the test, not stall the suite).
fn within_seconds<T: Send + 'static>(seconds: u64, what: &str, f: impl FnOnce() -> T + Send + 'static) -> T {
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(f());
    });
    rx.recv_timeout(std::time::Duration::from_secs(seconds))
        .unwrap_or_else(|_| panic!("{what}: no result within {seconds} s"))
}

/// Boundary loop lengths of a mesh (the original polylines).
fn loop_lengths(mesh: &Mesh) -> Vec<f64> {
    let topo = Topology::new(mesh);
    topo.boundary_loops()
        .map(|lp| {
            let n = lp.len();
            (0..n)
                .map(|i| (mesh.points()[lp[(i + 1) % n] as usize] - mesh.points()[lp[i] as usize]).length())
                .sum()
        })
        .collect()
}

/// Files saved from fuzz-target hangs (tests/data/fuzz/read_*/): each reads, maps to 2D and
/// used to hang the optimizer (every run never returned, in `fidelity::measure` and
/// `boundary::update`, which unwrapped arclengths with `while s <= s0 { s += len }` on a
/// boundary loop of length 0: a single vertex where two fans of quads meet). Now each
/// optimizes at once, keeping the guarantees.
#[test]
fn saved_fuzz_files_read_and_optimize() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/fuzz");
    let mut optimized = 0;
    for format in Format::ALL {
        let Ok(entries) = std::fs::read_dir(dir.join(format!("read_{}", format.extension()))) else {
            continue;
        };
        for entry in entries {
            let path = entry.unwrap().path();
            let bytes = std::fs::read(&path).unwrap();
            let name = path.display().to_string();
            let data = io::read_mesh_bytes(&bytes, format).unwrap_or_else(|e| panic!("{name}: {e}"));
            let mesh = io::PlanarMesh::new(&data).unwrap_or_else(|e| panic!("{name}: {e}")).mesh;
            assert!(loop_lengths(&mesh).contains(&0.0), "{name}: no boundary loop of length 0");
            let options = Options::default().with_max_iterations(5);
            let (before, opts) = (mesh.clone(), options.clone());
            let (out, r) = within_seconds(30, &name, move || {
                let mut out = mesh;
                let r = optimize(&mut out, &opts).unwrap();
                (out, r)
            });
            assert!(out.points().iter().all(|p| p.is_finite()), "{name}");
            assert!(r.output.inverted <= r.input.inverted && r.output.min >= r.input.min, "{name}: {r:?}");
            check_preserved(&before, &out, &options).unwrap();
            optimized += 1;
        }
    }
    assert_eq!(optimized, 3, "saved reader inputs");
}

/// Saved from the `optimize` fuzz target (tests/data/fuzz/optimize/): a 10 x 1 strip with one
/// boundary vertex at x = -1.06e270 panicked in `f64::clamp` (the loop length overflows to
/// infinity, the arclength bracket becomes NaN), with the angle-based method, automatic
/// boundary mode and extreme but valid options.
#[test]
fn huge_coordinate_on_the_boundary_does_not_panic() {
    let (mut p, q) = Grid::new(10, 1).unit();
    p[13] = DVec2::new(-1.0568409687981505e270, 5.431728992907e-312);
    let mesh = Mesh::new(p, q, None).unwrap();
    assert_eq!(loop_lengths(&mesh), vec![f64::INFINITY]);
    let options = Options::DEFAULT
        .with_method(Method::AngleBased)
        .with_boundary(BoundaryMode::Auto)
        .with_lambda(3.7857706061224e-270)
        .with_stop(StopRule::Energy)
        .with_max_min(true)
        .with_tau(2.5193042437317942e93)
        .with_tau_absolute(true)
        .with_max_iterations(32)
        .with_feature_angle_deg(7.291701411337593e-304)
        .with_guard(true)
        .with_guard_floor(7.0076790360759e-310)
        .with_untangle(false)
        .with_keep_best(false)
        .with_max_boundary_deviation(None);
    options.validate().unwrap();
    for boundary in BoundaryMode::ALL {
        let options = options.clone().with_boundary(boundary);
        let mut out = mesh.clone();
        optimize(&mut out, &options).unwrap();
        assert!(out.points().iter().all(|p| p.is_finite()), "{boundary:?}");
        check_preserved(&mesh, &out, &options).unwrap();
    }
}

/// Saved from the `optimize` fuzz target (tests/data/fuzz/optimize/): a 3 x 2 grid whose
/// corner vertex 0 sits at x = -8.2e298. The angle-based method rotates interior vertex 5
/// about that diagonal neighbour; the target overflows, and without the guard vertices 5 and
/// 6 became NaN (33 sweeps, every boundary mode). Now a non-finite target leaves the vertex
/// where it is.
#[test]
fn overflowing_target_leaves_the_vertex_in_place() {
    let (mut p, q) = Grid::new(3, 2).unit();
    p[0] = DVec2::new(-8.161677500224396e298, 1.37978955024905e-309);
    let mesh = Mesh::new(p, q, None).unwrap();
    for method in Method::ALL {
        for boundary in BoundaryMode::ALL {
            let options = Options::default()
                .with_method(method)
                .with_boundary(boundary)
                .with_tau_absolute(true)
                .with_max_iterations(33)
                .with_guard(false)
                .with_untangle(false)
                .with_keep_best(false);
            let mut out = mesh.clone();
            optimize(&mut out, &options).unwrap();
            assert!(
                out.points().iter().all(|p| p.is_finite()),
                "{method:?} {boundary:?}: {:?}",
                out.points()
            );
            check_preserved(&mesh, &out, &options).unwrap();
        }
    }
}

/// Found by the `ffi` fuzz target (tests/data/fuzz/ffi/): a 4 x 2 grid with corner vertex 0
/// at x = 1.07e116. The stretched quad dominates the total signed area, so the mesh counts
/// as given clockwise: all 8 quads count as inverted (7 at -1, the stretched one at 0).
/// With the default options the report says 6 inverted (min -0.854), measured in the input's
/// orientation; but the output's total signed area has changed sign, so measuring the output
/// coordinates afresh (orientation inferred again from the geometry, as `quadopt_quality`, a
/// re-read output file or the CLI's quality command do) gives the other orientation and 7
/// inverted (min -0.999). Not fixed (orientation is decided in src/mesh.rs,
/// outside this helper's files); reported to the lead.
#[test]
#[ignore = "output orientation is re-inferred from the geometry; see the doc comment"]
fn remeasured_output_quality_matches_the_report() {
    let (mut p, q) = Grid::new(4, 2).unit();
    p[0] = DVec2::new(1.0658546981484702e116, 1.83e-322);
    let mesh = Mesh::new(p, q.clone(), None).unwrap();
    let mut out = mesh.clone();
    let r = optimize(&mut out, &Options::default()).unwrap();
    let again = Mesh::new(out.points().to_vec(), q, None).unwrap();
    assert_eq!(
        again.quality(),
        r.output,
        "input {:?} (clockwise: {}), output clockwise when re-read: {}",
        r.input,
        mesh.has_clockwise_component(),
        again.has_clockwise_component()
    );
}
