//! Feature curves as tracks: each curve's original polyline parametrized by arclength, so a
//! vertex on a curve moves by changing one number and stays exactly on the polyline.

use glam::DVec3;

use super::features::{FeatureCurve, SurfaceFeatures, VertexRole};

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
}
