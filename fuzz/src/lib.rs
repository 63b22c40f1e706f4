//! Shared checks of the quadopt fuzz targets (see `fuzz_targets/`).
//!
//! Each reader target feeds arbitrary bytes to one reader and, when the file parses, checks the
//! whole path the command-line tool takes: write then read back bit-identical, map to the 2D
//! mesh, optimize a few sweeps, write the result back. The optimizer target builds a mesh from
//! arbitrary arrays and options. Every check is an assertion, so a violated guarantee is a
//! crash that libFuzzer reports and minimizes, just like a panic.

use quadopt::io::{self, Format, MeshData, PlanarMesh};
use quadopt::{BoundaryMode, DVec2, Error, Method, Options, Mesh, StopRule, optimize};

/// Largest mesh (vertices) the targets optimize: the optimizer is too slow on large random
/// arrays for a useful number of executions per second.
pub const MAX_VERTICES: usize = 200;

/// Largest iteration cap the targets use.
pub const MAX_ITERATIONS: usize = 50;

/// Bitwise equality, with every NaN equal to every other (text formats keep no NaN payload).
fn same(a: f64, b: f64) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

/// Reads `bytes` as `format`; on success checks the round trip and runs the optimizer.
/// A leading UTF-8 byte-order mark changes nothing: `bytes` read with and without one give the
/// same mesh or both fail. Compared through `Debug`, where a NaN coordinate (which readers
/// accept; the planar frame rejects it) equals itself.
pub fn check_bom(bytes: &[u8], format: Format) {
    const BOM: &[u8] = b"\xef\xbb\xbf";
    if bytes.starts_with(BOM) {
        return;
    }
    let with_bom = [BOM, bytes].concat();
    let plain = io::read_mesh_bytes(bytes, format).ok();
    let marked = io::read_mesh_bytes(&with_bom, format).ok();
    assert_eq!(format!("{plain:?}"), format!("{marked:?}"));
}

pub fn check_reader(bytes: &[u8], format: Format) {
    let Ok(data) = io::read_mesh_bytes(bytes, format) else { return };
    data.check().expect("a mesh that was read passes its own check");
    let bytes = io::write_mesh_bytes(format, &data).expect("a mesh that was read can be written");
    let back = io::read_mesh_bytes(&bytes, format).expect("a written mesh reads back");
    assert_eq!(back.points.len(), data.points.len());
    for (p, q) in back.points.iter().zip(&data.points) {
        assert!((0..3).all(|k| same(p[k], q[k])), "point {p:?} came back as {q:?}");
    }
    assert_eq!(back.quads, data.quads);
    if matches!(format, Format::Vtk | Format::Vtu | Format::Msh) {
        assert_eq!(back.fixed, data.fixed);
    }
    optimize_file_mesh(data, format);
}

/// The command-line tool's path: planar mapping, a short optimization, write back.
fn optimize_file_mesh(mut data: MeshData, format: Format) {
    if data.points.len() > MAX_VERTICES {
        return;
    }
    let Ok(mut planar) = PlanarMesh::new(&data) else { return };
    let options = Options::default().with_max_iterations(5);
    let report = optimize(&mut planar.mesh, &options).expect("default options are valid");
    assert!(planar.mesh.points().iter().all(|p| p.is_finite()));
    assert!(report.output.inverted <= report.input.inverted);
    assert!(report.output.min >= report.input.min || report.input.min.is_nan());
    planar.write_back(&mut data);
    io::write_mesh_bytes(format, &data).expect("an optimized mesh can be written");
}

/// Options from raw values; may be invalid (then the optimizer must say so).
#[derive(Clone, Debug, arbitrary::Arbitrary)]
pub struct RawOptions {
    method: u8,
    boundary: u8,
    lambda: f64,
    tau: f64,
    tau_absolute: bool,
    max_iterations: u8,
    feature_angle_deg: f64,
    guard: bool,
    guard_floor: f64,
    untangle: bool,
    keep_best: bool,
    max_boundary_deviation: Option<f64>,
    max_min: bool,
    /// The quality stopping rule instead of the energy rule.
    quality_stop: bool,
    /// Use the defaults for the real-valued fields (arbitrary floats are mostly invalid).
    default_reals: bool,
}

impl RawOptions {
    /// The options, with the iteration cap limited to [`MAX_ITERATIONS`].
    pub fn options(&self) -> Options {
        let d = Options::default();
        let reals = !self.default_reals;
        Options::DEFAULT
            .with_method(Method::ALL[self.method as usize % 4])
            .with_boundary(BoundaryMode::ALL[self.boundary as usize % 4])
            .with_lambda(if reals { self.lambda } else { d.lambda })
            .with_tau(if reals { self.tau } else { d.tau })
            .with_tau_absolute(self.tau_absolute)
            .with_max_iterations(self.max_iterations as usize % (MAX_ITERATIONS + 1))
            .with_feature_angle_deg(if reals { self.feature_angle_deg } else { d.feature_angle_deg })
            .with_guard(self.guard)
            .with_guard_floor(if reals { self.guard_floor } else { d.guard_floor })
            .with_untangle(self.untangle)
            .with_keep_best(self.keep_best)
            .with_max_boundary_deviation(if reals { self.max_boundary_deviation } else { None })
            .with_max_min(self.max_min)
            .with_stop(if self.quality_stop { StopRule::Quality } else { StopRule::Energy })
    }
}

/// How the quads are given.
#[derive(Clone, Debug, arbitrary::Arbitrary)]
pub enum Connectivity {
    /// Arbitrary quads (indices taken modulo the vertex count plus 2, so some are out of range).
    Raw(Vec<[u16; 4]>),
    /// An `nx` by `ny` grid (at most 12 by 12) without the cells whose flag is set; the vertex
    /// array is the grid's.
    Grid { nx: u8, ny: u8, removed: Vec<bool> },
}

/// A mesh from arbitrary arrays.
#[derive(Clone, Debug, arbitrary::Arbitrary)]
pub struct RawMesh {
    /// Coordinates in units of 2^-shift (grid meshes: added to the grid positions).
    coords: Vec<(i16, i16)>,
    shift: u8,
    /// Raw coordinate overrides (vertex index modulo the count): NaN, infinities, huge values.
    overrides: Vec<(u16, f64, f64)>,
    connectivity: Connectivity,
    /// Fixed flags (missing entries are false), or none.
    fixed: Option<Vec<bool>>,
    /// Give the fixed array one entry too many.
    bad_fixed_length: bool,
}

impl RawMesh {
    /// The arrays (vertex count capped at [`MAX_VERTICES`]).
    pub fn arrays(&self) -> (Vec<DVec2>, Vec<[u32; 4]>, Option<Vec<bool>>) {
        let scale = 0.5f64.powi((self.shift % 24) as i32);
        let c = |i: usize| {
            self.coords.get(i).map_or(DVec2::ZERO, |&(x, y)| DVec2::new(x as f64, y as f64) * scale)
        };
        let (mut points, quads) = match &self.connectivity {
            Connectivity::Raw(q) => {
                let n = self.coords.len().min(MAX_VERTICES);
                let points: Vec<DVec2> = (0..n).map(c).collect();
                let m = n as u32 + 2;
                let quads = q.iter().take(2 * MAX_VERTICES).map(|q| q.map(|v| v as u32 % m)).collect();
                (points, quads)
            }
            Connectivity::Grid { nx, ny, removed } => {
                let (nx, ny) = (*nx as usize % 12 + 1, *ny as usize % 12 + 1);
                let mut points = Vec::new();
                for j in 0..=ny {
                    for i in 0..=nx {
                        let k = points.len();
                        points.push(DVec2::new(i as f64, j as f64) + c(k) * (1.0 / 32768.0));
                    }
                }
                let mut quads = Vec::new();
                for j in 0..ny {
                    for i in 0..nx {
                        if removed.get(j * nx + i).copied().unwrap_or(false) {
                            continue;
                        }
                        let a = (j * (nx + 1) + i) as u32;
                        quads.push([a, a + 1, a + nx as u32 + 2, a + nx as u32 + 1]);
                    }
                }
                (points, quads)
            }
        };
        let n = points.len();
        if n > 0 {
            for &(v, x, y) in &self.overrides {
                points[v as usize % n] = DVec2::new(x, y);
            }
        }
        let fixed = self.fixed.as_ref().map(|f| {
            let len = n + usize::from(self.bad_fixed_length);
            (0..len).map(|i| f.get(i).copied().unwrap_or(false)).collect()
        });
        (points, quads, fixed)
    }
}

/// Builds the mesh and optimizes it; checks every guarantee the optimizer makes.
pub fn check_optimize(mesh: &RawMesh, options: &RawOptions) {
    let (points, quads, fixed) = mesh.arrays();
    let mesh = match Mesh::new(points, quads, fixed) {
        Ok(m) => m,
        Err(e) => {
            assert!(!matches!(e, Error::InvalidOption { .. } | Error::VertexCountMismatch { .. }), "{e:?}");
            return;
        }
    };
    let options = options.options();
    let mut out = mesh.clone();
    let result = optimize(&mut out, &options);
    if let Err(e) = options.validate() {
        assert_eq!(result, Err(e));
        return;
    }
    let report = result.expect("valid options on a valid mesh");
    assert_eq!(out.quads(), mesh.quads(), "connectivity changed");
    assert!(out.points().iter().all(|p| p.is_finite()), "non-finite output");
    let bits = |s: &quadopt::QualityStats| (s.min.to_bits(), s.avg.to_bits(), s.max.to_bits(), s.inverted);
    assert_eq!(bits(&report.output), bits(&out.quality()), "the report's output quality is not the mesh's");
    for (v, (a, b)) in mesh.points().iter().zip(out.points()).enumerate() {
        if mesh.fixed()[v] {
            assert!(
                a.x.to_bits() == b.x.to_bits() && a.y.to_bits() == b.y.to_bits(),
                "fixed vertex {v} moved"
            );
        }
    }
    if options.keep_best {
        assert!(report.output.inverted <= report.input.inverted, "{report:?}");
        assert!(report.output.min >= report.input.min, "{report:?}");
    }
}
