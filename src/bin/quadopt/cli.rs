//! The command line: clap's definitions of the subcommands and their options, the value
//! parsers, and the translation of the optimizing options into [`Options`].

use crate::fail::Fail;
use crate::openmesh_io;
use clap::{Args, Parser, Subcommand};
use quadopt::io::{self, Format, MeshData};
use quadopt::synthetic::Synthetic;
use quadopt::{BoundaryMode, Effort, Method, Options, StopRule};
use std::path::PathBuf;

#[derive(Parser)]
#[command(
    name = "quadopt",
    version = openmesh_io::VERSION,
    about = "Quality optimizer for quad and quad-dominant meshes, planar or on curved surfaces (embedded polygon method)"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
    /// Number of threads (default: one per core); results are identical on any number. At most
    /// four per core or 16, whichever is more (a larger N gets that many).
    #[arg(long, global = true, value_name = "N", value_parser = parse_threads)]
    pub threads: Option<usize>,
    /// Reader for .obj and .off: auto (quadopt's) or openmesh (.ply and .om always use OpenMesh).
    // Hidden in a build without OpenMesh, which refuses `--reader openmesh` with a message.
    #[arg(long, global = true, value_enum, default_value_t, hide = !openmesh_io::ENABLED)]
    pub reader: openmesh_io::Reader,
}

fn parse_threads(s: &str) -> Result<usize, String> {
    match s.parse::<usize>() {
        Ok(n) if n >= 1 => Ok(n),
        _ => Err(format!("'{s}' is not a number of threads (a whole number >= 1)")),
    }
}

/// A mesh format named on the command line (`--format`).
fn parse_format(s: &str) -> Result<Format, String> {
    Format::ALL
        .into_iter()
        .find(|f| f.extension().eq_ignore_ascii_case(s))
        .ok_or_else(|| format!("unknown mesh format '{s}' (expected obj, off, vtk, msh or vtu)"))
}

/// How the output file stores its data (VTU and MSH); by default as the input did.
#[derive(Args)]
pub struct EncodingArgs {
    /// Output encoding: ascii; binary (MSH binary, VTU inline base64); appended (VTU appended
    /// raw data, ParaView's default). Other formats are always text.
    #[arg(long, value_parser = parse_encoding)]
    encoding: Option<io::Encoding>,
    /// Compress VTU binary or appended data with zlib (ParaView's default).
    #[arg(long)]
    zlib: bool,
}

impl EncodingArgs {
    pub fn apply(&self, data: &mut MeshData) {
        if let Some(e) = self.encoding {
            data.encoding = e;
        }
        data.compressed |= self.zlib;
    }
}

fn parse_encoding(s: &str) -> Result<io::Encoding, String> {
    match s.to_ascii_lowercase().as_str() {
        "ascii" => Ok(io::Encoding::Ascii),
        "binary" => Ok(io::Encoding::Binary),
        "appended" => Ok(io::Encoding::Appended),
        _ => Err(format!("unknown encoding '{s}' (expected ascii, binary or appended)")),
    }
}

#[derive(Subcommand)]
pub enum Command {
    /// Optimize a mesh and write the result.
    ///
    /// The mesh may have triangles besides its quads; the report then adds the statistics of
    /// each face kind, input and output (JSON: "faces", "triangles", "input_by_kind",
    /// "output_by_kind").
    Optimize {
        #[arg(help = openmesh_io::INPUT_HELP)]
        input: PathBuf,
        /// Output mesh (format from its extension); `-` writes to stdout, in the input's format.
        #[arg(short, long)]
        output: PathBuf,
        /// Output format, whatever the output's name: obj, off, vtk, msh or vtu.
        #[arg(long, value_parser = parse_format)]
        format: Option<Format>,
        #[command(flatten)]
        encoding: EncodingArgs,
        #[command(flatten)]
        opts: OptArgs,
        /// Also draw the input and the output side by side, with a histogram of both (.png
        /// or .svg, by extension).
        #[arg(long, value_name = "OUT.png")]
        picture: Option<PathBuf>,
        /// Print one JSON object instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Print the quality of a mesh, and of each face kind when it has triangles.
    ///
    /// For a mesh with triangles, the report adds the count, min, avg, max and inverted count
    /// of its quads and of its triangles (JSON: "faces", "triangles" and "by_kind"). A mesh on
    /// a curved surface (not planar) gets two measures: Verdict's 3D scaled Jacobian (JSON
    /// "verdict") and the value the optimizer ranks by, each corner signed against the
    /// surface's normal there (the main statistics, the histogram and -o's array; JSON
    /// "surface": true).
    Quality {
        /// Input mesh.
        input: PathBuf,
        /// For a mesh on a curved surface: measure it against the surface of REF, a mesh with
        /// the same faces (the input it was optimized from, by quadopt or another tool), and
        /// report the largest distances of its vertices from that surface and of its feature
        /// vertices from their curves (JSON "surface_fidelity").
        #[arg(long, value_name = "REF")]
        reference: Option<PathBuf>,
        /// Also write the mesh with its per-face scaled Jacobian as cell data and its fixed
        /// and corner flags as point data (VTK, MSH); `-` writes to stdout.
        #[arg(short, long)]
        output: Option<PathBuf>,
        /// Output format, whatever the output's name: obj, off, vtk, msh or vtu.
        #[arg(long, value_parser = parse_format, requires = "output")]
        format: Option<Format>,
        #[command(flatten)]
        encoding: EncodingArgs,
        /// Print one JSON object instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Compare every method (fixed boundary) and the boundary modes of ep, per mesh.
    ///
    /// A mesh with triangles gets a row for its quads and one for its triangles under its own
    /// (JSON: "input_by_kind", and "output_by_kind" in each result).
    Compare {
        /// Input meshes.
        #[arg(required = true)]
        inputs: Vec<PathBuf>,
        #[command(flatten)]
        tune: TuneArgs,
        /// Print one JSON object instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Draw a mesh as PNG or SVG (by extension), faces coloured by scaled Jacobian.
    ///
    /// Quads and triangles alike are filled with the colour of their scaled Jacobian; inverted
    /// faces are outlined and hatched.
    Draw {
        /// Input mesh.
        input: PathBuf,
        /// Output picture (.png or .svg); `-` writes SVG to stdout.
        #[arg(short, long)]
        output: PathBuf,
        /// Optimize first (with the options below) and draw the result.
        #[arg(long, conflicts_with = "before_after")]
        optimized: bool,
        /// Optimize (with the options below) and draw input and output side by side on one
        /// colour scale, each with its min, avg and inverted count, and a histogram of both.
        #[arg(long)]
        before_after: bool,
        #[command(flatten)]
        opts: OptArgs,
    },
    /// Write a synthetic benchmark mesh: a grid with circular holes and jittered interior
    /// vertices (quad-dominant with --triangles)
    Generate {
        /// Output mesh (format from its extension); `-` writes to stdout (needs --format).
        #[arg(short, long)]
        output: PathBuf,
        /// Output format, whatever the output's name: obj, off, vtk, msh or vtu.
        #[arg(long, value_parser = parse_format)]
        format: Option<Format>,
        /// Approximate number of quads of a square grid, before any split (overrides --nx and
        /// --ny).
        #[arg(long)]
        quads: Option<usize>,
        /// Cells along x.
        #[arg(long, default_value_t = Synthetic::default().nx)]
        nx: u32,
        /// Cells along y.
        #[arg(long, default_value_t = Synthetic::default().ny)]
        ny: u32,
        /// Number of circular holes, on a square lattice no finer than the grid (at most
        /// min(nx, ny)^2 holes).
        #[arg(long, default_value_t = Synthetic::default().holes)]
        holes: u32,
        /// Hole diameter as a fraction of the hole spacing, in [0, 1).
        #[arg(long, default_value_t = Synthetic::default().hole_size)]
        hole_size: f64,
        /// Largest interior vertex displacement per axis, in grid spacings (>= 0.25 may fold quads).
        #[arg(long, default_value_t = Synthetic::default().jitter)]
        jitter: f64,
        /// Seed of the perturbation.
        #[arg(long, default_value_t = Synthetic::default().seed)]
        seed: u64,
        /// Fraction of the quads split along a diagonal into two triangles, in [0, 1]: a
        /// quad-dominant mesh (the quads chosen by --seed; 0 keeps every quad).
        #[arg(long, value_name = "FRACTION", default_value_t = 0.0, allow_negative_numbers = true)]
        triangles: f64,
    },
}

/// Method and boundary mode.
#[derive(Args, Clone)]
pub struct OptArgs {
    /// Interior smoothing method: ep, laplace, cotan or angle.
    #[arg(long, default_value = "ep")]
    method: Method,
    /// Boundary treatment: fixed, slide, snap or auto (the better of slide and snap).
    #[arg(long, default_value = "auto")]
    boundary: BoundaryMode,
    /// Keep every node of the Gmsh physical curve or point NAME fixed (MSH input;
    /// repeatable).
    #[arg(long = "fix-physical", value_name = "NAME")]
    pub fix_physical: Vec<String>,
    /// Mark more feature edges of a mesh on a curved surface: FILE holds two 0-based vertex
    /// numbers per line (`#` starts a comment). Vertices on feature edges only slide along them.
    #[arg(long = "feature-edges", value_name = "FILE")]
    pub feature_edges: Option<PathBuf>,
    /// Mark every edge between two nodes of the Gmsh physical curve NAME as a feature edge
    /// (MSH input on a curved surface; repeatable).
    #[arg(long = "feature-physical", value_name = "NAME")]
    pub feature_physical: Vec<String>,
    #[command(flatten)]
    tune: TuneArgs,
}

/// Numeric options shared by every optimizing command.
#[derive(Args, Clone)]
pub struct TuneArgs {
    /// How much work to spend on quality: fast (a few guarded sweeps, no max-min stage: for
    /// meshers that smooth in their own loop), balanced (the default) or best (the highest
    /// quality, at more time). The options below apply on top of the preset.
    #[arg(long, default_value_t = Effort::Balanced)]
    effort: Effort,
    /// Stop when the collective energy changes by less than this per movable vertex
    /// (absolute change with --absolute-tau); implies --stop energy.
    #[arg(long, allow_negative_numbers = true)]
    tau: Option<f64>,
    /// Compare --tau with the absolute energy change, as the paper does (size-dependent);
    /// implies --stop energy.
    #[arg(long)]
    absolute_tau: bool,
    /// The paper's plain method: no guard, no untangling, no max-min stage, the energy rule
    /// with absolute tau = 1e-4 (the boundary mode still comes from --boundary).
    #[arg(long)]
    paper: bool,
    /// Turn off guarded moves (which never let a valid star's minimum drop below the floor).
    #[arg(long)]
    no_guard: bool,
    /// Floor of the guarded moves, in (0, 1].
    #[arg(long, default_value_t = Options::default().guard_floor, allow_negative_numbers = true)]
    guard_floor: f64,
    /// Do not untangle inverted faces before smoothing.
    #[arg(long)]
    no_untangle: bool,
    /// Skip the max-min stage (which raises the worst face after the sweeps).
    #[arg(long)]
    no_maxmin: bool,
    /// Stopping rule: quality (the default: stop once the inverted count, minimum and average
    /// of the result stop improving) or energy (the energy change per movable vertex below
    /// --tau; more sweeps).
    #[arg(long)]
    stop: Option<StopRule>,
    /// Largest distance of a new boundary edge from the original boundary, relative to the
    /// edge's length (default: unlimited).
    #[arg(long, allow_negative_numbers = true)]
    max_boundary_deviation: Option<f64>,
    /// Step factor, in (0, 1].
    #[arg(long, default_value_t = Options::default().lambda, allow_negative_numbers = true)]
    lambda: f64,
    /// Sweep cap (every preset; fast stops at 6 sweeps by itself).
    #[arg(long = "max-iter", default_value_t = Options::default().max_iterations)]
    max_iter: usize,
    /// Boundary vertices turning by more than this many degrees are corners; on a curved
    /// surface also the dihedral angle beyond which an edge is sharp (a feature edge).
    #[arg(long = "feature-angle", default_value_t = Options::default().feature_angle_deg, allow_negative_numbers = true)]
    feature_angle: f64,
}

impl TuneArgs {
    pub fn options(&self, method: Method, boundary: BoundaryMode) -> Result<Options, Fail> {
        let base = if self.paper { Options::paper() } else { Options::default() };
        let o = base
            .clone()
            .with_effort(self.effort)
            .with_method(method)
            .with_boundary(boundary)
            .with_lambda(self.lambda)
            .with_tau(self.tau.unwrap_or(base.tau))
            .with_tau_absolute(base.tau_absolute || self.absolute_tau)
            .with_max_iterations(self.max_iter)
            .with_feature_angle_deg(self.feature_angle)
            .with_guard(base.guard && !self.no_guard)
            .with_guard_floor(self.guard_floor)
            .with_untangle(base.untangle && !self.no_untangle)
            .with_max_boundary_deviation(self.max_boundary_deviation)
            .with_max_min(base.max_min && !self.no_maxmin)
            // A threshold on the energy asks for the energy rule.
            .with_stop(self.stop.unwrap_or(if self.tau.is_some() || self.absolute_tau {
                StopRule::Energy
            } else {
                base.stop
            }));
        o.validate().map_err(|e| Fail::Usage(e.to_string()))?;
        Ok(o)
    }
}

impl OptArgs {
    pub fn options(&self) -> Result<Options, Fail> {
        self.tune.options(self.method, self.boundary)
    }

    /// Refuses the surface-only options for a planar mesh, whose boundary is its only feature.
    pub fn check_planar(&self) -> Result<(), Fail> {
        if self.feature_edges.is_some() || !self.feature_physical.is_empty() {
            return Err(Fail::Usage(
                "--feature-edges and --feature-physical apply to meshes on curved surfaces; this mesh is planar \
                 (its corners come from --feature-angle)"
                    .into(),
            ));
        }
        Ok(())
    }
}
