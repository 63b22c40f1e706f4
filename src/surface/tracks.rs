//! Feature curves as tracks: each curve's original polyline parametrized by arclength, so a
//! vertex on a curve moves by changing one number and stays exactly on the polyline.

use glam::DVec3;

use super::features::{FeatureCurve, SurfaceFeatures, VertexRole};
use crate::smooth::boundary::ChordDeviation;

/// The polyline vertices of a stretch that [`Track::chord_deviation`] holds at most (a chord
/// spanning more compares its first ones against the chord, and its samples against them).
const STRETCH_MAX: usize = 34;

/// Sample points per chord for the new -> original direction, as in the plane.
const CHORD_SAMPLES: usize = 8;

/// One feature curve's original polyline, by arclength.
#[derive(Clone, Debug)]
pub struct Track {
    /// The polyline's points at the input positions (a closed curve's first again at the end).
    points: Vec<DVec3>,
    /// Arclength at each point, from 0.
    arclength: Vec<f64>,
    /// The curve's vertices, in order (a closed curve's first not repeated).
    vertices: Vec<u32>,
    closed: bool,
}

impl Track {
    fn new(curve: &FeatureCurve, points: &[DVec3]) -> Track {
        let mut pts: Vec<DVec3> = curve.vertices.iter().map(|&v| points[v as usize]).collect();
        if curve.closed {
            pts.push(pts[0]);
        }
        let mut arclength = Vec::with_capacity(pts.len());
        let mut s = 0.0;
        arclength.push(0.0);
        for w in pts.windows(2) {
            s += (w[1] - w[0]).length();
            arclength.push(s);
        }
        Track { points: pts, arclength, vertices: curve.vertices.clone(), closed: curve.closed }
    }

    /// The polyline's length.
    pub fn length(&self) -> f64 {
        *self.arclength.last().unwrap_or(&0.0)
    }

    /// The point at arclength `s` (taken modulo the length on a closed curve, clamped to the
    /// ends on an open one).
    pub fn at(&self, s: f64) -> DVec3 {
        let len = self.length();
        let s = if self.closed && len > 0.0 { s.rem_euclid(len) } else { s.clamp(0.0, len) };
        // The last segment starting at or before s.
        let i = self.arclength.partition_point(|&a| a <= s).clamp(1, self.points.len() - 1) - 1;
        let (a, b) = (self.arclength[i], self.arclength[i + 1]);
        if b <= a {
            return self.points[i];
        }
        let t = ((s - a) / (b - a)).clamp(0.0, 1.0);
        self.points[i] + (self.points[i + 1] - self.points[i]) * t
    }

    /// The distance from `p` to the polyline's segment at arclength `s` and its two neighbours:
    /// an upper bound of the distance to the polyline, in constant time (for a vertex placed
    /// at `s`).
    pub fn distance_near(&self, p: DVec3, s: f64) -> f64 {
        let len = self.length();
        let s = if self.closed && len > 0.0 { s.rem_euclid(len) } else { s.clamp(0.0, len) };
        let i = self.arclength.partition_point(|&a| a <= s).clamp(1, self.points.len() - 1) - 1;
        let last = self.points.len() - 2;
        (i.saturating_sub(1)..=(i + 1).min(last))
            .map(|k| (super::closest_point_on_segment(p, self.points[k], self.points[k + 1]).0 - p).length())
            .fold(f64::INFINITY, f64::min)
    }

    /// Calls `visit` with the polyline's vertices strictly between arclengths `s0 < s1`
    /// (unwrapped around a closed curve's start, as [`Tracks::interval`] gives them), in order.
    fn for_each_vertex_between(&self, s0: f64, s1: f64, mut visit: impl FnMut(DVec3)) {
        let len = self.length();
        if !(s0 < s1) || !(len > 0.0) || !len.is_finite() {
            return;
        }
        if !self.closed {
            let from = self.arclength.partition_point(|&a| a <= s0);
            for i in from..self.points.len() {
                if self.arclength[i] >= s1 {
                    break;
                }
                visit(self.points[i]);
            }
            return;
        }
        // Shift s0 into [0, len); the last point repeats the first, so only the others count,
        // once per turn the stretch makes.
        let turns = (s0 / len).floor();
        // A stretch of more than one turn holds every point: at most one turn is walked (and
        // an infinite or huge `s1` never loops).
        let (s0, s1) = (s0 - turns * len, (s1 - turns * len).min(s0 - turns * len + len));
        let last = self.points.len() - 1;
        let mut offset = 0.0;
        while offset < s1 {
            let from = if offset == 0.0 { self.arclength[..last].partition_point(|&a| a <= s0) } else { 0 };
            for i in from..last {
                let a = self.arclength[i] + offset;
                if a >= s1 {
                    return;
                }
                if a > s0 {
                    visit(self.points[i]);
                }
            }
            offset += len;
        }
    }

    /// How far the chord from arclength `s0` to `s1` (unwrapped, `s0 < s1`) is from the
    /// stretch of the polyline between them, as in the plane
    /// ([`crate::smooth::boundary::BoundaryGeometry::chord_deviation`]): the stretch's
    /// vertices against the chord, and sample points of the chord against the stretch.
    pub fn chord_deviation(&self, s0: f64, s1: f64) -> ChordDeviation {
        let (a, b) = (self.at(s0), self.at(s1));
        let mut stretch = [DVec3::ZERO; STRETCH_MAX];
        let mut count = 1;
        stretch[0] = a;
        let mut original_to_new = 0.0f64;
        self.for_each_vertex_between(s0, s1, |p| {
            original_to_new = original_to_new.max((super::closest_point_on_segment(p, a, b).0 - p).length());
            if count < STRETCH_MAX - 1 {
                stretch[count] = p;
                count += 1;
            }
        });
        stretch[count] = b;
        let stretch = &stretch[..=count];
        let mut new_to_original = 0.0f64;
        if stretch.len() > 2 {
            for k in 1..CHORD_SAMPLES {
                let q = a + (b - a) * (k as f64 / CHORD_SAMPLES as f64);
                let d = stretch
                    .windows(2)
                    .map(|w| (super::closest_point_on_segment(q, w[0], w[1]).0 - q).length())
                    .fold(f64::INFINITY, f64::min);
                new_to_original = new_to_original.max(d);
            }
        }
        ChordDeviation { new_to_original, original_to_new }
    }

    /// Whether the chord from arclength `s0` to `s1` (unwrapped, `s0 < s1`) is within
    /// `tolerance` times its length of the stretch it replaces (a shape tolerance, as
    /// `Options::max_boundary_deviation` in the plane).
    pub fn chord_within(&self, s0: f64, s1: f64, tolerance: f64) -> bool {
        s0 < s1 && self.chord_deviation(s0, s1).largest() <= tolerance * (self.at(s1) - self.at(s0)).length()
    }

    /// The arclength of the polyline's point closest to `p`.
    pub fn closest_param(&self, p: DVec3) -> f64 {
        let mut best = (f64::INFINITY, 0.0);
        for (i, w) in self.points.windows(2).enumerate() {
            let (q, t) = super::closest_point_on_segment(p, w[0], w[1]);
            let d = (q - p).length();
            if d < best.0 {
                best = (d, self.arclength[i] + t * (self.arclength[i + 1] - self.arclength[i]));
            }
        }
        best.1
    }

    /// The distance from `p` to the polyline.
    pub fn distance(&self, p: DVec3) -> f64 {
        self.points
            .windows(2)
            .map(|w| (super::closest_point_on_segment(p, w[0], w[1]).0 - p).length())
            .fold(f64::INFINITY, f64::min)
    }
}

/// Where a vertex sits on its curve.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Slot {
    pub track: u32,
    pub index: u32,
}

/// The tracks of every feature curve, and each on-curve vertex's place on its track.
#[derive(Clone, Debug)]
pub struct Tracks {
    tracks: Vec<Track>,
    /// Per vertex: its curve and index in it, for an on-curve vertex.
    slots: Vec<Option<Slot>>,
}

impl Tracks {
    /// The tracks of `features`' curves at the input `points`.
    pub fn new(features: &SurfaceFeatures, points: &[DVec3]) -> Tracks {
        let tracks: Vec<Track> = features.curves().iter().map(|c| Track::new(c, points)).collect();
        let mut slots = vec![None; points.len()];
        for (v, role) in features.roles().iter().enumerate() {
            if let VertexRole::OnCurve(c) = *role {
                let index = features.curves()[c as usize].vertices.iter().position(|&u| u as usize == v);
                slots[v] = index.map(|i| Slot { track: c, index: i as u32 });
            }
        }
        Tracks { tracks, slots }
    }

    /// The track of curve `c`.
    pub fn track(&self, c: u32) -> &Track {
        &self.tracks[c as usize]
    }

    /// The slot of vertex `v`, if it is on a curve.
    pub fn slot(&self, v: usize) -> Option<Slot> {
        self.slots[v]
    }

    /// Each vertex's arclength at the input: its track's arclength at its index (0 off the
    /// curves).
    pub fn initial_params(&self) -> Vec<f64> {
        self.slots
            .iter()
            .map(|s| s.map_or(0.0, |s| self.tracks[s.track as usize].arclength[s.index as usize]))
            .collect()
    }

    /// The edges of every curve at `params`, each as its track, its two vertices and the
    /// arclengths of its ends (unwrapped around a closed curve's start, so the second is the
    /// larger; on an open curve a pair out of order is an edge whose vertices passed each
    /// other).
    pub fn edges<'a>(
        &'a self,
        params: &'a [f64],
    ) -> impl Iterator<Item = (&'a Track, [u32; 2], f64, f64)> + 'a {
        self.tracks.iter().flat_map(move |t| {
            let n = t.vertices.len();
            let param = move |k: usize| match k {
                // An open curve's ends are corners at their input arclength.
                0 if !t.closed => t.arclength[0],
                k if k + 1 == n && !t.closed => t.arclength[n - 1],
                k => params[t.vertices[k] as usize],
            };
            let count = if t.closed { n } else { n.saturating_sub(1) };
            (0..count).map(move |k| {
                let (s0, s1) = (param(k), param((k + 1) % n));
                // A closed curve's arclengths may have wrapped past its start either way.
                let s1 = if t.closed { s0 + (s1 - s0).rem_euclid(t.length()) } else { s1 };
                (t, [t.vertices[k], t.vertices[(k + 1) % n]], s0, s1)
            })
        })
    }

    /// The vertices of every curve edge at `params` that is not within `tolerance` times its
    /// length of the stretch it replaces ([`Track::chord_within`]), or whose ends passed each
    /// other.
    pub fn beyond(&self, params: &[f64], tolerance: f64) -> Vec<[u32; 2]> {
        self.edges(params).filter(|&(t, _, s0, s1)| !t.chord_within(s0, s1, tolerance)).map(|e| e.1).collect()
    }

    /// The open interval of arclength that `slot`'s vertex may move in: between its two
    /// neighbours along the curve, at their current `params` (unwrapped around a closed
    /// curve's start, so the interval is increasing).
    pub fn interval(&self, slot: Slot, params: &[f64]) -> (f64, f64) {
        let t = &self.tracks[slot.track as usize];
        let i = slot.index as usize;
        let n = t.vertices.len();
        let param = |k: usize| params[t.vertices[k] as usize];
        if t.closed {
            let len = t.length();
            let own = param(i);
            // Neighbours' params unwrapped to bracket the vertex's own.
            let mut lo = param((i + n - 1) % n);
            let mut hi = param((i + 1) % n);
            while lo > own {
                lo -= len;
            }
            while hi < own {
                hi += len;
            }
            (lo, hi)
        } else {
            // An open curve's ends are corners: they keep their input arclength.
            let lo = if i == 1 { t.arclength[0] } else { param(i - 1) };
            let hi = if i + 2 == n { t.arclength[n - 1] } else { param(i + 1) };
            (lo, hi)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_track_evaluates_on_its_polyline() {
        let pts = vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 2.0, 0.0)];
        let curve = FeatureCurve { vertices: vec![0, 1, 2], closed: false };
        let t = Track::new(&curve, &pts);
        assert_eq!(t.length(), 3.0);
        assert_eq!(t.at(0.5), DVec3::new(0.5, 0.0, 0.0));
        assert_eq!(t.at(2.0), DVec3::new(1.0, 1.0, 0.0));
        assert_eq!(t.at(1.0), DVec3::X);
        assert_eq!(t.at(9.0), pts[2]);
        assert!(t.distance(DVec3::new(0.5, 0.5, 0.0)) - 0.5 < 1e-15);
        let closed = Track::new(&FeatureCurve { vertices: vec![0, 1, 2], closed: true }, &pts);
        assert!((closed.length() - (3.0 + 5f64.sqrt())).abs() < 1e-15);
        assert_eq!(closed.at(closed.length() + 0.5), DVec3::new(0.5, 0.0, 0.0));
    }

    #[test]
    fn a_chord_deviates_by_the_vertices_it_cuts_off() {
        // The unit square as a closed curve: arclengths 0, 1, 2, 3 at its corners.
        let pts = vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y];
        let t = Track::new(&FeatureCurve { vertices: vec![0, 1, 2, 3], closed: true }, &pts);
        // Along one side: nothing cut off.
        assert_eq!(t.chord_deviation(0.25, 0.75).largest(), 0.0);
        assert!(t.chord_within(0.25, 0.75, 0.0));
        // Across corner (1, 0): the corner is sqrt(2)/4 off the chord from (0.5, 0) to (1, 0.5).
        let d = t.chord_deviation(0.5, 1.5);
        assert!((d.original_to_new - 0.125f64.sqrt()).abs() < 1e-15, "{d:?}");
        assert!(d.new_to_original > 0.0 && d.new_to_original <= d.original_to_new + 1e-15);
        assert!(!t.chord_within(0.5, 1.5, 0.3) && t.chord_within(0.5, 1.5, 0.6));
        // Across the curve's start, unwrapped either way: the corner at the origin is cut off.
        for (s0, s1) in [(-0.5, 0.5), (3.5, 4.5), (7.5, 8.5)] {
            let d = t.chord_deviation(s0, s1);
            assert!((d.original_to_new - 0.125f64.sqrt()).abs() < 1e-15, "{s0}..{s1}: {d:?}");
        }
        // Spanning two corners: both cut off, the farther counts.
        assert_eq!(t.chord_deviation(0.5, 2.5).original_to_new, 0.5);
        // Out of order: no chord; a stretch beyond one turn (or infinite) ends.
        assert!(!t.chord_within(1.5, 0.5, 1.0));
        assert!(!t.chord_within(0.5, f64::INFINITY, 1.0));
        assert!(!t.chord_within(0.5, 1e300, 1.0));
        // An open polyline: its inner vertex is cut off by a chord across it.
        let open = Track::new(&FeatureCurve { vertices: vec![0, 1, 2], closed: false }, &pts);
        assert!((open.chord_deviation(0.5, 1.5).original_to_new - 0.125f64.sqrt()).abs() < 1e-15);
        assert_eq!(open.closest_param(DVec3::new(1.2, 0.5, 0.0)), 1.5);
    }
}
