//! Guarded moves: a vertex whose star (its incident quads) is valid may not move to a place
//! that lowers its star's minimum scaled Jacobian below min(current value, floor).
//!
//! The paper's method ignores where v may go without folding its star, so on graded and
//! anisotropic meshes it can lower the minimum quality or create inversions (DESIGN.md
//! section 5). Vertices in a tangled star are not guarded, so untangling is never blocked.

use crate::quality::{corners, scaled_jacobian, scaled_jacobian_below};
use crate::topology::Topology;
use glam::DVec2;

/// Step halvings tried before a guarded vertex stays where it is.
const MAX_HALVINGS: usize = 8;

/// The corners of each quad around `v`, with `v` placed at `at`.
fn star_quads<'a>(
    points: &'a [DVec2],
    quads: &'a [[u32; 4]],
    topo: &'a Topology,
    v: usize,
    at: DVec2,
) -> impl Iterator<Item = [DVec2; 4]> + 'a {
    topo.vertex_quads(v).iter().map(move |&qi| {
        let q = &quads[qi as usize];
        let mut c = corners(points, q);
        for (k, &u) in q.iter().enumerate() {
            if u as usize == v {
                c[k] = at;
            }
        }
        c
    })
}

/// Minimum scaled Jacobian of the quads around `v` with `v` placed at `at`.
pub fn star_min(points: &[DVec2], quads: &[[u32; 4]], topo: &Topology, v: usize, at: DVec2) -> f64 {
    star_quads(points, quads, topo, v, at).map(|c| scaled_jacobian(&c)).fold(f64::INFINITY, f64::min)
}

/// Whether every quad around `v` with `v` placed at `at` is at or above `floor`: the answer of
/// `star_min(..) >= floor` (a NaN value passes in both), stopping at the first quad below.
pub fn star_at_least(
    points: &[DVec2],
    quads: &[[u32; 4]],
    topo: &Topology,
    v: usize,
    at: DVec2,
    floor: f64,
) -> bool {
    !star_quads(points, quads, topo, v, at).any(|c| scaled_jacobian_below(&c, floor))
        && f64::INFINITY >= floor
}

/// Minimum and average scaled Jacobian of the quads around `v` with `v` placed at `at`.
pub fn star_min_avg(
    points: &[DVec2],
    quads: &[[u32; 4]],
    topo: &Topology,
    v: usize,
    at: DVec2,
) -> (f64, f64) {
    let (mut min, mut sum) = (f64::INFINITY, 0.0);
    for c in star_quads(points, quads, topo, v, at) {
        let sj = scaled_jacobian(&c);
        min = min.min(sj);
        sum += sj;
    }
    (min, sum / topo.vertex_quads(v).len().max(1) as f64)
}

/// The position actually taken by `v` when it wants to go to `target`: the target itself if
/// the star is tangled or stays acceptable, else the longest acceptable step among
/// 1/2, 1/4, ... of the way.
///
/// When no step towards the target is acceptable, the smoothing direction is making the
/// star's worst quad worse, and a guarded vertex would stay stuck there for good (measured:
/// freshly untangled meshes stuck at a minimum near 0). It then tries the direction that
/// raises the star's smallest corner area ([`super::untangle`]'s local program) and takes
/// the longest step along it that strictly improves the star's minimum; else it stays.
pub fn guarded_position(
    points: &[DVec2],
    quads: &[[u32; 4]],
    topo: &Topology,
    v: usize,
    target: DVec2,
    floor: f64,
) -> DVec2 {
    let p = points[v];
    if target == p {
        return p;
    }
    // A target at or above the floor is acceptable whatever the current value (the bar is
    // min(current, floor)), so the current star is only evaluated when needed.
    if star_at_least(points, quads, topo, v, target, floor) {
        return target;
    }
    let current = star_min(points, quads, topo, v, p);
    if current <= 0.0 {
        return target;
    }
    let required = current.min(floor);
    if let Some(q) = longest_step(points, quads, topo, v, target, |m| m >= required) {
        return q;
    }
    super::untangle::untangle_vertex(points, quads, topo, v)
        .and_then(|t| longest_step(points, quads, topo, v, t, |m| m > current))
        .unwrap_or(p)
}

/// The first of p + d, p + d/2, p + d/4, ... (d = target - p) whose star minimum satisfies
/// `accept`.
fn longest_step(
    points: &[DVec2],
    quads: &[[u32; 4]],
    topo: &Topology,
    v: usize,
    target: DVec2,
    accept: impl Fn(f64) -> bool,
) -> Option<DVec2> {
    let p = points[v];
    let mut step = target - p;
    for _ in 0..=MAX_HALVINGS {
        let candidate = p + step;
        if accept(star_min(points, quads, topo, v, candidate)) {
            return Some(candidate);
        }
        step *= 0.5;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::QuadMesh;

    /// 2x2 unit squares; vertex 4 is the centre.
    fn grid_2x2() -> (QuadMesh, Topology) {
        let mut p = Vec::new();
        for j in 0..3 {
            for i in 0..3 {
                p.push(DVec2::new(i as f64, j as f64));
            }
        }
        let m = QuadMesh::new(p, vec![[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 7]], None).unwrap();
        let t = Topology::new(&m);
        (m, t)
    }

    #[test]
    fn star_at_least_answers_as_star_min_does() {
        let (m, t) = grid_2x2();
        let mut rnd = crate::test_rng::xorshift(0x2545_f491_4f6c_dd1d);
        let (mut yes, mut no) = (0, 0);
        for k in 0..20_000 {
            // The centre anywhere around its star (folded stars included), floors across [-1, 1]
            // and NaN.
            let at = DVec2::new(1.0 + 1.5 * rnd(), 1.0 + 1.5 * rnd());
            let floor = if k % 100 == 0 { f64::NAN } else { rnd() };
            let want = star_min(m.points(), m.quads(), &t, 4, at) >= floor;
            assert_eq!(star_at_least(m.points(), m.quads(), &t, 4, at, floor), want, "{at} {floor}");
            if want { yes += 1 } else { no += 1 }
        }
        assert!(yes > 1000 && no > 1000, "{yes} {no}");
    }

    #[test]
    fn guarded_move_never_folds_a_valid_star() {
        // 2x2 grid, centre vertex 4; a target far outside its star would fold it.
        let (m, t) = grid_2x2();
        let target = DVec2::new(5.0, 1.0);
        let got = guarded_position(m.points(), m.quads(), &t, 4, target, 0.05);
        assert!(star_min(m.points(), m.quads(), &t, 4, got) >= 0.05);
        assert!(got.x > 1.0 && got.x < 2.0, "took a partial step: {got}");
        // An acceptable target is taken as is.
        let ok = DVec2::new(1.1, 1.0);
        assert_eq!(guarded_position(m.points(), m.quads(), &t, 4, ok, 0.05), ok);
    }
}
