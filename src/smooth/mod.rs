//! The optimizer: options, the iteration loop, termination and the report.
//!
//! Every method is a per-vertex update that reads only the previous positions (a Jacobi
//! sweep), so a sweep runs in parallel and gives the same result on any number of threads.
//! Interior vertices are moved by the chosen [`Method`]; boundary vertices by the embedded
//! polygon's boundary rule (Section 3.3) in the chosen [`BoundaryMode`], whatever the method.
//! Termination follows Section 3.2: the collective torsion-spring energy (Eq. 1, see
//! [`energy`]) is computed every sweep and the run stops when |E_new - E_old| < tau, or at the
//! iteration cap.

pub mod angle_based;
pub mod boundary;
pub mod embedded_polygon;
pub mod energy;
pub mod laplacian;

use crate::error::{Error, Result};
use crate::features::Features;
use crate::mesh::QuadMesh;
use crate::quality::QualityStats;
use crate::topology::Topology;
use boundary::BoundaryGeometry;
use glam::DVec2;
use rayon::prelude::*;
use std::str::FromStr;
use std::time::Instant;

/// How interior vertices are moved.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Method {
    /// The embedded polygon method of Akram, Si and Chen (Sections 3.1-3.2).
    #[default]
    EmbeddedPolygon,
    /// Uniform Laplacian: each vertex moves towards the average of its edge-neighbours.
    Laplacian,
    /// Cotangent-weighted Laplacian.
    Cotangent,
    /// Xu and Newman's angle-based smoothing (2005): bisectors at edge and diagonal neighbours.
    AngleBased,
}

impl Method {
    /// Every method, in the order of the paper's comparison.
    pub const ALL: [Method; 4] =
        [Method::AngleBased, Method::Laplacian, Method::Cotangent, Method::EmbeddedPolygon];

    /// The short name used on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Method::EmbeddedPolygon => "ep",
            Method::Laplacian => "laplace",
            Method::Cotangent => "cotan",
            Method::AngleBased => "angle",
        }
    }
}

impl FromStr for Method {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        match s {
            "ep" | "embedded-polygon" => Ok(Method::EmbeddedPolygon),
            "laplace" | "laplacian" => Ok(Method::Laplacian),
            "cotan" | "cotangent" => Ok(Method::Cotangent),
            "angle" | "angle-based" => Ok(Method::AngleBased),
            _ => Err(format!("unknown method '{s}' (expected ep, laplace, cotan or angle)")),
        }
    }
}

/// How boundary vertices are treated (Section 3.3). Corners and fixed vertices never move.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum BoundaryMode {
    /// Boundary vertices never move.
    Fixed,
    /// Approach 2: move along the original boundary polyline only.
    #[default]
    Slide,
    /// Approach 1: rotate to bisect, then project back onto the original boundary between the
    /// vertex's two boundary neighbours.
    Snap,
}

impl BoundaryMode {
    /// Every mode.
    pub const ALL: [BoundaryMode; 3] = [BoundaryMode::Fixed, BoundaryMode::Slide, BoundaryMode::Snap];

    /// The short name used on the command line.
    pub fn name(self) -> &'static str {
        match self {
            BoundaryMode::Fixed => "fixed",
            BoundaryMode::Slide => "slide",
            BoundaryMode::Snap => "snap",
        }
    }
}

impl FromStr for BoundaryMode {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        match s {
            "fixed" => Ok(BoundaryMode::Fixed),
            "slide" => Ok(BoundaryMode::Slide),
            "snap" => Ok(BoundaryMode::Snap),
            _ => Err(format!("unknown boundary mode '{s}' (expected fixed, slide or snap)")),
        }
    }
}

/// Optimization options. The defaults reproduce the paper (lambda = 1, tau = 1e-4, feature
/// angle 45 degrees, boundary Approach 2).
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    /// Interior smoothing method.
    pub method: Method,
    /// Boundary treatment.
    pub boundary: BoundaryMode,
    /// Step factor of Eq. 8, in (0, 1].
    pub lambda: f64,
    /// Stop when the collective energy changes by less than this between sweeps (>= 0).
    pub tau: f64,
    /// Iteration cap (>= 1).
    pub max_iterations: usize,
    /// A boundary vertex whose turning angle differs from 180 degrees by more than this is a
    /// corner and never moves, in degrees within [0, 180].
    pub feature_angle_deg: f64,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            method: Method::EmbeddedPolygon,
            boundary: BoundaryMode::Slide,
            lambda: 1.0,
            tau: 1e-4,
            max_iterations: 1000,
            feature_angle_deg: 45.0,
        }
    }
}

impl Options {
    /// Checks every option's range, naming the first bad one.
    pub fn validate(&self) -> Result<()> {
        let bad = |name, reason: &str| Err(Error::InvalidOption { name, reason: reason.to_string() });
        if !(self.lambda > 0.0 && self.lambda <= 1.0) {
            return bad("lambda", &format!("{} is not in (0, 1]", self.lambda));
        }
        if !(self.tau >= 0.0 && self.tau.is_finite()) {
            return bad("tau", &format!("{} is not a finite number >= 0", self.tau));
        }
        if self.max_iterations == 0 {
            return bad("max_iterations", "must be at least 1");
        }
        if !(0.0..=180.0).contains(&self.feature_angle_deg) {
            return bad("feature_angle_deg", &format!("{} is not in [0, 180]", self.feature_angle_deg));
        }
        Ok(())
    }
}

/// Progress of a run, passed to the progress callback after every sweep.
#[derive(Clone, Copy, Debug)]
pub struct Progress {
    /// Sweeps done so far.
    pub iteration: usize,
    /// The iteration cap.
    pub max_iterations: usize,
    /// Collective energy before the last sweep.
    pub energy: f64,
    /// |E_new - E_old| of the last sweep.
    pub energy_change: f64,
}

/// What a run did.
#[derive(Clone, Debug, PartialEq)]
pub struct Report {
    /// Quality before.
    pub input: QualityStats,
    /// Quality after.
    pub output: QualityStats,
    /// Sweeps performed.
    pub iterations: usize,
    /// Whether the energy criterion was met (false: iteration cap or cancelled).
    pub converged: bool,
    /// Whether the progress callback cancelled the run.
    pub cancelled: bool,
    /// Collective energy of the input.
    pub initial_energy: f64,
    /// Collective energy of the output.
    pub final_energy: f64,
    /// Wall-clock seconds.
    pub seconds: f64,
    /// Quads that were reversed to make the orientation consistent.
    pub reoriented_quads: usize,
    /// Boundary vertices detected as corners (never moved).
    pub corners: usize,
    /// Vertices the optimizer was allowed to move.
    pub movable: usize,
}

/// Optimizes `mesh` in place with `options`. Builds the topology; to optimize many meshes
/// with the same connectivity, build an [`Optimizer`] once instead.
pub fn optimize(mesh: &mut QuadMesh, options: &Options) -> Result<Report> {
    Optimizer::new(mesh).run(mesh, options, None)
}

/// A reusable optimizer: the topology of one connectivity, built once.
#[derive(Clone, Debug)]
pub struct Optimizer {
    topology: Topology,
}

/// Per-vertex result of a sweep.
#[derive(Clone, Copy, Debug, Default)]
struct Update {
    position: DVec2,
    /// Boundary arclength parameter (unused for interior vertices).
    param: f64,
    /// Torsion energy of the vertex at the old positions.
    energy: f64,
}

impl Optimizer {
    /// Builds the topology of `mesh`.
    pub fn new(mesh: &QuadMesh) -> Optimizer {
        Optimizer { topology: Topology::new(mesh) }
    }

    /// The topology this optimizer works on.
    pub fn topology(&self) -> &Topology {
        &self.topology
    }

    /// Optimizes `mesh` (which must have the connectivity this optimizer was built for). The
    /// optional `progress` callback runs after every sweep; returning `false` cancels, keeping
    /// the positions reached so far.
    pub fn run(
        &self,
        mesh: &mut QuadMesh,
        options: &Options,
        mut progress: Option<&mut dyn FnMut(&Progress) -> bool>,
    ) -> Result<Report> {
        options.validate()?;
        if mesh.points().len() != self.topology.vertex_count() {
            return Err(Error::VertexCountMismatch {
                expected: self.topology.vertex_count(),
                got: mesh.points().len(),
            });
        }
        let start = Instant::now();
        let input = mesh.quality();
        let topo = &self.topology;
        let features = Features::new(mesh, topo, options.feature_angle_deg, options.boundary);
        let geometry = BoundaryGeometry::new(mesh.points(), topo, &features);
        let movable = features.movable_vertices();
        // Arclength of every boundary loop slot on the original polyline.
        let mut params = geometry.initial_params();
        let mut updates = vec![Update::default(); movable.len()];
        let sweep_ctx = Sweep { topo, features: &features, geometry: &geometry, options };

        let mut energy_old = f64::NAN;
        let mut initial_energy = f64::NAN;
        let (mut iterations, mut converged, mut cancelled) = (0, false, false);
        while iterations < options.max_iterations {
            {
                let (points, params) = (mesh.points(), &params);
                updates.par_iter_mut().zip(movable.par_iter()).for_each(|(u, &v)| {
                    *u = sweep_ctx.update(points, params, v as usize);
                });
            }
            // Sequential sum: the same energy whatever the thread count.
            let energy: f64 = updates.iter().map(|u| u.energy).sum();
            if iterations == 0 {
                initial_energy = energy;
            }
            let change = (energy - energy_old).abs();
            if change < options.tau {
                // The positions the energy was measured at are final.
                converged = true;
                energy_old = energy;
                break;
            }
            let points = mesh.points_mut();
            for (u, &v) in updates.iter().zip(&movable) {
                points[v as usize] = u.position;
                if let Some(slot) = geometry.slot(v as usize) {
                    params[slot] = u.param;
                }
            }
            iterations += 1;
            energy_old = energy;
            if let Some(cb) = progress.as_mut() {
                let p = Progress {
                    iteration: iterations,
                    max_iterations: options.max_iterations,
                    energy,
                    energy_change: change,
                };
                if !cb(&p) {
                    cancelled = true;
                    break;
                }
            }
        }
        let final_energy = if converged {
            energy_old
        } else {
            let points = mesh.points();
            movable.iter().map(|&v| sweep_ctx.update(points, &params, v as usize).energy).sum()
        };
        Ok(Report {
            input,
            output: mesh.quality(),
            iterations,
            converged,
            cancelled,
            initial_energy: if initial_energy.is_nan() { final_energy } else { initial_energy },
            final_energy,
            seconds: start.elapsed().as_secs_f64(),
            reoriented_quads: mesh.reoriented().len(),
            corners: features.corner_count(),
            movable: movable.len(),
        })
    }
}

/// Everything one vertex update reads besides the positions.
struct Sweep<'a> {
    topo: &'a Topology,
    features: &'a Features,
    geometry: &'a BoundaryGeometry,
    options: &'a Options,
}

impl Sweep<'_> {
    fn update(&self, points: &[DVec2], params: &[f64], v: usize) -> Update {
        if self.features.is_boundary(v) {
            let (position, param, energy) = boundary::update(
                points,
                self.topo,
                self.geometry,
                params,
                v,
                self.options.boundary,
                self.options.lambda,
            );
            return Update { position, param, energy };
        }
        let ring = self.topo.ring(v);
        let (target, energy) = match self.options.method {
            Method::EmbeddedPolygon => embedded_polygon::target(points, v, ring),
            Method::Laplacian => {
                (laplacian::uniform_target(points, ring), energy::vertex_energy(points, v, ring))
            }
            Method::Cotangent => {
                (laplacian::cotangent_target(points, v, ring), energy::vertex_energy(points, v, ring))
            }
            Method::AngleBased => (
                angle_based::target(points, v, self.topo.full_ring(v)),
                energy::vertex_energy(points, v, ring),
            ),
        };
        let p = points[v];
        Update { position: p + self.options.lambda * (target - p), param: 0.0, energy }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    pub(crate) fn grid(nx: u32, ny: u32) -> QuadMesh {
        let mut p = Vec::new();
        for j in 0..=ny {
            for i in 0..=nx {
                p.push(DVec2::new(i as f64, j as f64));
            }
        }
        let mut q = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                let a = j * (nx + 1) + i;
                q.push([a, a + 1, a + nx + 2, a + nx + 1]);
            }
        }
        QuadMesh::new(p, q, None).unwrap()
    }

    #[test]
    fn perfect_grid_is_a_fixed_point_of_every_method_and_mode() {
        for method in Method::ALL {
            for boundary in BoundaryMode::ALL {
                let mut m = grid(4, 3);
                let before = m.points().to_vec();
                let r = optimize(&mut m, &Options { method, boundary, ..Options::default() }).unwrap();
                for (a, b) in before.iter().zip(m.points()) {
                    assert!((*a - *b).length() < 1e-12, "{method:?} {boundary:?} moved {a} to {b}");
                }
                assert_eq!(r.output.min, 1.0);
            }
        }
    }
}
