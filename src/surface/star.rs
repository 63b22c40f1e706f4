//! A vertex's star on the surface: the tangent-plane chart its planar computations run in,
//! where a candidate lands on the surface, and the star's score there.
//!
//! The chart of a vertex that moves on the surface is the plane through it orthogonal to the
//! reference patch's normal at its position ([`super::patches`]: the input's area-weighted
//! vertex normals over the patch, interpolated over the reference triangle). Its star's
//! vertices are projected orthogonally onto that plane, which keeps the faces' winding
//! counter-clockwise (the normal is the faces' outward side). A chart position is lifted
//! back into 3D on the plane and then put on the patch at its closest point; the star is
//! always scored there, on the surface, never in the chart.

use std::cell::{Cell, RefCell};

use glam::{DVec2, DVec3};

use super::patches::{OnPatch, Patches, corner_vertices};
use super::tracks::{Slot, Tracks};
use crate::face::Face;
use crate::quality3d::{MovingCorner, signed_scaled_jacobian_unit, verdict_scaled_jacobian};
use crate::topology::Topology;

/// Most patches a moving vertex may touch: a vertex on a feature curve touches two, one on
/// each side (each side of the curve around a manifold vertex is one patch, as only feature
/// edges cut patches); one at which more meet is a corner.
pub const MAX_PATCHES: usize = 2;

/// A plane through a vertex with an orthonormal basis: the vertex's chart.
#[derive(Clone, Copy, Debug)]
pub struct Chart {
    origin: DVec3,
    e1: DVec3,
    e2: DVec3,
}

impl Chart {
    /// The plane through `origin` orthogonal to the unit `normal`, with `e1 x e2 = normal`.
    pub fn new(origin: DVec3, normal: DVec3) -> Chart {
        let e1 = normal.any_orthonormal_vector();
        Chart { origin, e1, e2: normal.cross(e1) }
    }

    /// The orthogonal projection of `p` into the chart.
    pub fn to_chart(self, p: DVec3) -> DVec2 {
        let d = p - self.origin;
        DVec2::new(d.dot(self.e1), d.dot(self.e2))
    }

    /// The point of the plane at chart position `x`.
    pub fn lift(self, x: DVec2) -> DVec3 {
        self.origin + self.e1 * x.x + self.e2 * x.y
    }
}

/// How a vertex may move.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Motion {
    /// Fixed, a corner, not manifold or unused: never moves.
    Still,
    /// On the surface, inside patch `.0`.
    Free(u32),
    /// Along a feature curve.
    Curve(Slot),
}

/// A vertex placed on the surface: its position, its arclength on its curve (on-curve
/// vertices), a triangle hint for its next projection, and the normal of each patch around it.
#[derive(Clone, Copy, Debug)]
pub struct Placed {
    pub point: DVec3,
    pub param: f64,
    pub hint: u32,
    normals: [(u32, DVec3); MAX_PATCHES],
    count: u8,
}

impl Placed {
    /// The normal of patch `patch` at the vertex (the first one if it is not among them).
    pub fn normal_for(&self, patch: u32) -> DVec3 {
        self.normals[..self.count as usize].iter().find(|(p, _)| *p == patch).unwrap_or(&self.normals[0]).1
    }
}

/// The lowest values a face may take in a run, in each measure: min(its input value, the
/// floor), the floor being the larger of the guard's floor and the input's minimum in that
/// measure. Every move the run takes keeps every face of its star at or above both.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bound {
    /// In the signed measure (each corner against the surface's normal).
    pub signed: f64,
    /// In Verdict's measure (each corner against the face's centre normal).
    pub verdict: f64,
}

impl Bound {
    /// The bounds of faces of input values `signed` and `verdict` for the guard's floor
    /// `guard_floor`.
    pub fn of_input(signed: &[f64], verdict: &[f64], guard_floor: f64) -> Vec<Bound> {
        let floor = |values: &[f64]| guard_floor.max(values.iter().copied().fold(f64::INFINITY, f64::min));
        let (fs, fv) = (floor(signed), floor(verdict));
        signed.iter().zip(verdict).map(|(&s, &v)| Bound { signed: s.min(fs), verdict: v.min(fv) }).collect()
    }
}

/// The lexicographic score of a star: fewer faces below their [`Bound`], then fewer inverted
/// faces, then a higher minimum, then a higher sum of the faces' values (in a run, each face's
/// lower value of the two measures, so that a move is judged as both measures see it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Score {
    pub below: u32,
    pub inverted: u32,
    pub min: f64,
    pub sum: f64,
}

impl Score {
    /// The score of no face, to [`add`](Self::add) faces to.
    pub const EMPTY: Score = Score { below: 0, inverted: 0, min: f64::INFINITY, sum: 0.0 };

    /// Counts one more face, of signed value `value`.
    #[inline]
    pub fn add(&mut self, value: f64) {
        self.inverted += u32::from(value <= 0.0);
        self.min = self.min.min(value);
        self.sum += value;
    }

    /// Strictly better.
    pub fn better_than(&self, other: &Score) -> bool {
        if self.below != other.below {
            return self.below < other.below;
        }
        if self.inverted != other.inverted {
            return self.inverted < other.inverted;
        }
        if self.min != other.min {
            return self.min > other.min;
        }
        self.sum > other.sum
    }
}

/// The positions and normals a sweep reads.
#[derive(Clone, Debug)]
pub struct State {
    pub points: Vec<DVec3>,
    /// Arclength of each on-curve vertex along its curve.
    pub params: Vec<f64>,
    /// The reference triangle each free vertex was last projected onto.
    pub hints: Vec<u32>,
    /// Per face, the normal of its patch at each corner ([`corner_vertices`] order).
    pub normals: Vec<[DVec3; 4]>,
}

/// What every star computation reads besides the [`State`].
pub struct Surface<'a> {
    pub faces: &'a [Face],
    pub topo: &'a Topology,
    pub patches: &'a Patches,
    pub tracks: &'a Tracks,
    pub motion: &'a [Motion],
    /// Per face, the values it may not fall below (empty: no bounds, as when measuring).
    pub bounds: &'a [Bound],
    /// `Options::max_boundary_deviation`: each new edge along a feature curve within this
    /// times its length of the stretch of the curve it replaces (`None`: unlimited).
    pub curve_tolerance: Option<f64>,
}

impl Surface<'_> {
    /// The signed scaled Jacobian of face `f` at `state`, `v` placed at `at` if given.
    pub fn face_value(&self, state: &State, f: usize, moved: Option<(usize, &Placed)>) -> f64 {
        let face = &self.faces[f];
        let cv = corner_vertices(face);
        let mut q = cv.map(|u| state.points[u as usize]);
        let mut n = state.normals[f];
        if let Some((v, at)) = moved {
            let normal = at.normal_for(self.patches.of_face(f));
            for k in 0..4 {
                if cv[k] as usize == v {
                    q[k] = at.point;
                    if !self.patches.is_own(f, k) {
                        n[k] = normal;
                    }
                }
            }
        }
        signed_scaled_jacobian_unit(&q, &n)
    }

    /// Verdict's scaled Jacobian of face `f` at `state`, `v` placed at `at` if given.
    pub fn face_verdict(&self, state: &State, f: usize, moved: Option<(usize, &Placed)>) -> f64 {
        let cv = corner_vertices(&self.faces[f]);
        let mut q = cv.map(|u| state.points[u as usize]);
        if let Some((v, at)) = moved {
            for k in 0..4 {
                if cv[k] as usize == v {
                    q[k] = at.point;
                }
            }
        }
        verdict_scaled_jacobian(&q)
    }

    /// What face `f`, of signed value `signed` at `state` with `v` at `at`, adds to a star's
    /// score: the lower of its two measures (the signed one alone when there are no bounds),
    /// and whether it is below its bound in either (a NaN is).
    #[inline]
    fn scored(&self, state: &State, f: usize, signed: f64, moved: Option<(usize, &Placed)>) -> (f64, bool) {
        match self.bounds.get(f) {
            None => (signed, false),
            Some(b) => {
                let verdict = self.face_verdict(state, f, moved);
                (signed.min(verdict), !(signed >= b.signed) || !(verdict >= b.verdict))
            }
        }
    }

    /// The score of `v`'s star, with `v` at `at` (else where it is).
    pub fn star_score(&self, state: &State, v: usize, at: Option<&Placed>) -> Score {
        let mut s = Score::EMPTY;
        for &f in self.topo.vertex_quads(v) {
            let moved = at.map(|a| (v, a));
            let (value, below) =
                self.scored(state, f as usize, self.face_value(state, f as usize, moved), moved);
            s.below += u32::from(below);
            s.add(value);
        }
        s
    }

    /// [`star_score`](Self::star_score) of `v` at `at`, from `star` built for `v` at `state`
    /// ([`LocalStar::build`]): the same value, bit for bit, from the faces' fixed corners
    /// computed once per star rather than once per candidate.
    pub fn star_score_at(&self, state: &State, v: usize, star: &LocalStar, at: &Placed) -> Score {
        debug_assert_eq!(star.global.first(), Some(&(v as u32)));
        let mut moving = star.moving.borrow_mut();
        if !star.moving_ready.get() {
            // On the first score of this star: a star whose first move is certified
            // (src/surface/slack.rs) is never scored.
            moving.clear();
            for &f in self.topo.vertex_quads(v) {
                let face = &self.faces[f as usize];
                let cv = corner_vertices(face);
                moving.push(match cv.iter().position(|&u| u as usize == v) {
                    Some(k) if !crate::face::is_triangle(face) => {
                        let q = cv.map(|u| state.points[u as usize]);
                        Some(MovingCorner::new(&q, &state.normals[f as usize], k))
                    }
                    _ => None,
                });
            }
            star.moving_ready.set(true);
        }
        let mut s = Score::EMPTY;
        for (&f, corner) in self.topo.vertex_quads(v).iter().zip(moving.iter()) {
            let f = f as usize;
            let value = match corner {
                Some(c) => {
                    let k = c.corner();
                    let normal = if self.patches.is_own(f, k) {
                        state.normals[f][k]
                    } else {
                        at.normal_for(self.patches.of_face(f))
                    };
                    c.value(at.point, normal)
                }
                None => self.face_value(state, f, Some((v, at))),
            };
            let (value, below) = self.scored(state, f, value, Some((v, at)));
            s.below += u32::from(below);
            s.add(value);
        }
        s
    }

    /// `v` as placed now.
    pub fn current(&self, state: &State, v: usize) -> Placed {
        let mut placed = Placed {
            point: state.points[v],
            param: state.params[v],
            hint: state.hints[v],
            normals: [(u32::MAX, DVec3::Z); MAX_PATCHES],
            count: 0,
        };
        // A free vertex's faces are all in its patch: the first one gives its normal.
        let faces = self.topo.vertex_quads(v);
        let faces =
            if matches!(self.motion[v], Motion::Free(_)) { &faces[..faces.len().min(1)] } else { faces };
        for &f in faces {
            let f = f as usize;
            let patch = self.patches.of_face(f);
            if placed.normals[..placed.count as usize].iter().any(|(p, _)| *p == patch) {
                continue;
            }
            if let Some(k) = corner_vertices(&self.faces[f]).iter().position(|&u| u as usize == v) {
                if (placed.count as usize) < MAX_PATCHES {
                    placed.normals[placed.count as usize] = (patch, state.normals[f][k]);
                    placed.count += 1;
                }
            }
        }
        placed
    }

    /// Free vertex `v` of patch `patch` at the closest point of its patch to `p`.
    pub fn place_free(&self, patch: u32, p: DVec3, hint: u32) -> Placed {
        let OnPatch { point, triangle, normal } = self.patches.project(patch, p, hint);
        let mut normals = [(u32::MAX, DVec3::Z); MAX_PATCHES];
        normals[0] = (patch, normal);
        Placed { point, param: 0.0, hint: triangle, normals, count: 1 }
    }

    /// Whether on-curve vertex `v` may go to arclength `s` by the curve tolerance: both its
    /// new edges along the curve within the tolerance of the stretches they replace.
    pub fn curve_allows(&self, state: &State, slot: Slot, s: f64) -> bool {
        self.curve_tolerance.is_none_or(|tol| {
            let (lo, hi) = self.tracks.interval(slot, &state.params);
            let track = self.tracks.track(slot.track);
            track.chord_within(lo, s, tol) && track.chord_within(s, hi, tol)
        })
    }

    /// On-curve vertex `v` at arclength `s` of its track, with the normal of each patch
    /// around it there.
    pub fn place_on_curve(&self, v: usize, slot: Slot, s: f64) -> Placed {
        let point = self.tracks.track(slot.track).at(s);
        let mut placed =
            Placed { point, param: s, hint: 0, normals: [(u32::MAX, DVec3::Z); MAX_PATCHES], count: 0 };
        for &f in self.topo.vertex_quads(v) {
            let patch = self.patches.of_face(f as usize);
            if placed.normals[..placed.count as usize].iter().any(|(p, _)| *p == patch) {
                continue;
            }
            if (placed.count as usize) < MAX_PATCHES {
                // Walked from the face's triangle at the vertex's input position.
                let from = self.patches.triangle_at(f as usize, v as u32);
                let normal = self.patches.project(patch, point, from).normal;
                placed.normals[placed.count as usize] = (patch, normal);
                placed.count += 1;
            }
        }
        placed
    }

    /// Moves `v` to `at` in `state`.
    pub fn apply(&self, state: &mut State, v: usize, at: &Placed) {
        state.points[v] = at.point;
        state.params[v] = at.param;
        state.hints[v] = at.hint;
        for &f in self.topo.vertex_quads(v) {
            let f = f as usize;
            // One patch (a free vertex): its normal, whatever the face's patch.
            let normal = if at.count == 1 { at.normals[0].1 } else { at.normal_for(self.patches.of_face(f)) };
            let cv = corner_vertices(&self.faces[f]);
            for (k, &u) in cv.iter().enumerate() {
                if u as usize == v && !self.patches.is_own(f, k) {
                    state.normals[f][k] = normal;
                }
            }
        }
    }
}

/// A free vertex's star in its chart: the star's vertices in local numbering (0 is the
/// vertex), its ring and full ring in local numbers, and its faces.
#[derive(Default)]
pub struct LocalStar {
    pub global: Vec<u32>,
    pub points: Vec<DVec2>,
    pub ring: Vec<u32>,
    pub full_ring: Vec<u32>,
    pub faces: Vec<Face>,
    /// Per face of the star (in [`Topology::vertex_quads`] order), its fixed corners for
    /// [`Surface::star_score_at`], made there on the star's first score; `None` for a
    /// triangle, which is measured in full.
    moving: RefCell<Vec<Option<MovingCorner>>>,
    moving_ready: Cell<bool>,
    scratch: Vec<u32>,
    /// `global`'s local numbers, once the star has [`LINEAR_STAR_MAX`] vertices.
    index: std::collections::HashMap<u32, u32>,
}

/// Vertices of a star up to which a linear search finds a vertex's local number (faster than a
/// map in the usual stars of 9 to 20 vertices).
const LINEAR_STAR_MAX: usize = 64;

impl LocalStar {
    fn local(&mut self, u: u32, chart: &Chart, state: &State) -> u32 {
        // A linear search in a usual star; a map in a large one (a fan of thousands of faces
        // around a cone's apex), where the search would make the star's cost quadratic.
        if self.global.len() < LINEAR_STAR_MAX {
            if let Some(i) = self.global.iter().position(|&g| g == u) {
                return i as u32;
            }
        } else {
            if self.index.is_empty() {
                self.index.extend(self.global.iter().enumerate().map(|(i, &g)| (g, i as u32)));
            }
            if let Some(&i) = self.index.get(&u) {
                return i;
            }
            self.index.insert(u, self.global.len() as u32);
        }
        self.global.push(u);
        self.points.push(chart.to_chart(state.points[u as usize]));
        (self.global.len() - 1) as u32
    }

    /// Fills in [`full_ring`](Self::full_ring) of `v`'s star, [built](Self::build) already
    /// (only the angle-based target reads it).
    pub fn build_full_ring(&mut self, surface: &Surface, v: usize) {
        let mut scratch = std::mem::take(&mut self.scratch);
        surface.topo.full_ring_into(surface.faces, v, &mut scratch);
        self.full_ring.clear();
        for &u in &scratch {
            // Every vertex of the full ring is a corner of a face of the star.
            let local = if self.index.is_empty() {
                self.global.iter().position(|&g| g == u).unwrap_or(0) as u32
            } else {
                self.index.get(&u).copied().unwrap_or(0)
            };
            self.full_ring.push(local);
        }
        self.scratch = scratch;
    }

    /// Fills in `v`'s star in `chart` (all but its full ring).
    pub fn build(&mut self, surface: &Surface, state: &State, v: usize, chart: &Chart) {
        self.global.clear();
        self.index.clear();
        self.points.clear();
        self.ring.clear();
        self.full_ring.clear();
        self.faces.clear();
        self.moving_ready.set(false);
        self.local(v as u32, chart, state);
        for &u in surface.topo.ring(v) {
            let l = self.local(u, chart, state);
            self.ring.push(l);
        }
        for &f in surface.topo.vertex_quads(v) {
            let face = surface.faces[f as usize];
            let mut local = face;
            for k in 0..crate::face::corner_count(&face) {
                local[k] = self.local(face[k], chart, state);
            }
            self.faces.push(local);
        }
    }
}
