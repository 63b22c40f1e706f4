//! `quadopt`: improve the quality of 2D quad meshes from the command line.
//!
//! - `quadopt` with no arguments optimizes every mesh in the bundled `data/` directory and
//!   prints a report like the paper's Table 1.
//! - `quadopt optimize IN -o OUT`, `quadopt quality IN`, `quadopt compare IN...`,
//!   `quadopt draw IN -o OUT.svg`: see `quadopt help`.
//!
//! Errors are one line on stderr; the exit code is 2 for usage errors, 1 for anything else.
//! Output files are written atomically, so a failed run never leaves one half-written.

mod svg;

/// `print!` that ends the program quietly when stdout is closed (`quadopt compare ... | head`)
/// instead of panicking with "failed printing to stdout".
macro_rules! out {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        if write!(std::io::stdout(), $($arg)*).is_err() {
            std::process::exit(0);
        }
    }};
}

/// `println!` with the behaviour of [`out!`].
macro_rules! outln {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        if writeln!(std::io::stdout(), $($arg)*).is_err() {
            std::process::exit(0);
        }
    }};
}

use clap::{Args, Parser, Subcommand};
use quadopt::io::{self, Format, MeshData, PlanarMesh};
use quadopt::synthetic::Synthetic;
use quadopt::{BoundaryMode, Method, Optimizer, Options, Progress, QuadMesh, QualityStats, Report};
use serde_json::{Value, json};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

#[derive(Parser)]
#[command(
    name = "quadopt",
    version,
    about = "Quality optimizer for 2D quad meshes (embedded polygon method)"
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Optimize a mesh and write the result.
    Optimize {
        /// Input mesh (.obj, .off, .vtk, .msh).
        input: PathBuf,
        /// Output mesh (format from its extension).
        #[arg(short, long)]
        output: PathBuf,
        #[command(flatten)]
        opts: OptArgs,
        /// Print one JSON object instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Print the quality of a mesh.
    Quality {
        /// Input mesh.
        input: PathBuf,
        /// Print one JSON object instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Compare every method (fixed boundary) and the boundary modes of ep, per mesh.
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
    /// Draw a mesh as SVG, quads coloured by scaled Jacobian.
    Draw {
        /// Input mesh.
        input: PathBuf,
        /// Output SVG file.
        #[arg(short, long)]
        output: PathBuf,
        /// Optimize first (with the options below) and draw the result.
        #[arg(long)]
        optimized: bool,
        #[command(flatten)]
        opts: OptArgs,
    },
    /// Write a synthetic benchmark mesh: a grid with circular holes and jittered interior vertices.
    Generate {
        /// Output mesh (format from its extension).
        #[arg(short, long)]
        output: PathBuf,
        /// Approximate number of quads of a square grid (overrides --nx and --ny).
        #[arg(long)]
        quads: Option<usize>,
        /// Cells along x.
        #[arg(long, default_value_t = Synthetic::default().nx)]
        nx: u32,
        /// Cells along y.
        #[arg(long, default_value_t = Synthetic::default().ny)]
        ny: u32,
        /// Number of circular holes.
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
    },
}

/// Method and boundary mode.
#[derive(Args, Clone)]
struct OptArgs {
    /// Interior smoothing method: ep, laplace, cotan or angle.
    #[arg(long, default_value = "ep")]
    method: Method,
    /// Boundary treatment: fixed, slide, snap or auto (the better of slide and snap).
    #[arg(long, default_value = "auto")]
    boundary: BoundaryMode,
    #[command(flatten)]
    tune: TuneArgs,
}

/// Numeric options shared by every optimizing command.
#[derive(Args, Clone)]
struct TuneArgs {
    /// Stop when the collective energy changes by less than this per movable vertex
    /// (absolute change with --absolute-tau).
    #[arg(long, allow_negative_numbers = true)]
    tau: Option<f64>,
    /// Compare --tau with the absolute energy change, as the paper does (size-dependent).
    #[arg(long)]
    absolute_tau: bool,
    /// The paper's plain method: no guard, no untangling, absolute tau = 1e-4 (the boundary
    /// mode still comes from --boundary).
    #[arg(long)]
    paper: bool,
    /// Turn off guarded moves (which never let a valid star's minimum drop below the floor).
    #[arg(long)]
    no_guard: bool,
    /// Floor of the guarded moves, in (0, 1].
    #[arg(long, default_value_t = Options::default().guard_floor, allow_negative_numbers = true)]
    guard_floor: f64,
    /// Do not untangle inverted quads before smoothing.
    #[arg(long)]
    no_untangle: bool,
    /// Largest distance of a new boundary edge from the original boundary, relative to the
    /// edge's length (default: unlimited).
    #[arg(long, allow_negative_numbers = true)]
    max_boundary_deviation: Option<f64>,
    /// Step factor, in (0, 1].
    #[arg(long, default_value_t = Options::default().lambda, allow_negative_numbers = true)]
    lambda: f64,
    /// Iteration cap.
    #[arg(long = "max-iter", default_value_t = Options::default().max_iterations)]
    max_iter: usize,
    /// Boundary vertices turning by more than this many degrees are corners.
    #[arg(long = "feature-angle", default_value_t = Options::default().feature_angle_deg, allow_negative_numbers = true)]
    feature_angle: f64,
}

impl TuneArgs {
    fn options(&self, method: Method, boundary: BoundaryMode) -> Result<Options, Fail> {
        let base = if self.paper { Options::paper() } else { Options::default() };
        let o = Options {
            method,
            boundary,
            lambda: self.lambda,
            tau: self.tau.unwrap_or(base.tau),
            tau_absolute: base.tau_absolute || self.absolute_tau,
            max_iterations: self.max_iter,
            feature_angle_deg: self.feature_angle,
            guard: base.guard && !self.no_guard,
            guard_floor: self.guard_floor,
            untangle: base.untangle && !self.no_untangle,
            max_boundary_deviation: self.max_boundary_deviation,
            ..base
        };
        o.validate().map_err(|e| Fail::Usage(e.to_string()))?;
        Ok(o)
    }
}

impl OptArgs {
    fn options(&self) -> Result<Options, Fail> {
        self.tune.options(self.method, self.boundary)
    }
}

/// A failure: a usage error (exit 2) or anything else (exit 1), with a one-line message.
enum Fail {
    Usage(String),
    Other(String),
}

impl<E: std::fmt::Display> From<E> for Fail {
    fn from(e: E) -> Self {
        Fail::Other(e.to_string())
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        None => run_data_dir(),
        Some(Command::Optimize { input, output, opts, json }) => cmd_optimize(&input, &output, &opts, json),
        Some(Command::Quality { input, json }) => cmd_quality(&input, json),
        Some(Command::Compare { inputs, tune, json }) => cmd_compare(&inputs, &tune, json),
        Some(Command::Draw { input, output, optimized, opts }) => cmd_draw(&input, &output, optimized, &opts),
        Some(Command::Generate { output, quads, nx, ny, holes, hole_size, jitter, seed }) => {
            let spec = match quads {
                Some(n) => Synthetic { holes, hole_size, jitter, seed, ..Synthetic::with_quads(n) },
                None => Synthetic { nx, ny, holes, hole_size, jitter, seed },
            };
            cmd_generate(&output, &spec)
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(fail) => {
            let (code, msg) = match fail {
                Fail::Usage(m) => (2, m),
                Fail::Other(m) => (1, m),
            };
            eprintln!("quadopt: error: {}", msg.replace('\n', " "));
            ExitCode::from(code)
        }
    }
}

/// A mesh read from a file and mapped to 2D.
struct Loaded {
    data: MeshData,
    planar: PlanarMesh,
}

fn load(path: &Path) -> Result<Loaded, Fail> {
    let data = io::read_mesh(path)?;
    let planar = PlanarMesh::new(&data).map_err(|e| Fail::Other(format!("{}: {e}", path.display())))?;
    Ok(Loaded { data, planar })
}

/// Runs the optimizer, showing progress on stderr when it is a terminal.
fn run(optimizer: &Optimizer, mesh: &mut QuadMesh, options: &Options) -> Result<Report, Fail> {
    if !std::io::stderr().is_terminal() {
        return Ok(optimizer.run(mesh, options, None)?);
    }
    let start = Instant::now();
    let mut last = 0.0;
    let mut shown = false;
    let mut cb = |p: &Progress| {
        let t = start.elapsed().as_secs_f64();
        if t - last > 0.2 {
            last = t;
            shown = true;
            eprint!(
                "\r  iteration {}/{}  energy {:.6e}  change {:.3e}   ",
                p.iteration, p.max_iterations, p.energy, p.energy_change
            );
        }
        true
    };
    let report = optimizer.run(mesh, options, Some(&mut cb));
    if shown {
        eprint!("\r{:60}\r", "");
    }
    Ok(report?)
}

fn stats_json(s: &QualityStats) -> Value {
    json!({ "min": s.min, "avg": s.avg, "max": s.max, "inverted": s.inverted })
}

/// The guarantees-related part of a report, shared by the JSON outputs.
fn report_json(r: &Report) -> Value {
    let f = &r.fidelity;
    json!({
        "converged": r.converged,
        "untangle_sweeps": r.untangle_sweeps,
        "loop_modes": r.loop_modes.iter().map(|m| m.name()).collect::<Vec<_>>(),
        "boundary_fidelity": {
            "max_deviation": f.max_deviation, "hausdorff": f.hausdorff,
            "max_deviation_relative": f.max_deviation_relative, "hausdorff_relative": f.hausdorff_relative,
        },
        "tangled": r.tangled.iter().map(|t| json!({ "quad": t.quad, "reason": t.reason.describe() })).collect::<Vec<_>>(),
    })
}

/// One line per quad still inverted, with the reason.
fn print_tangled(r: &Report) {
    for t in r.tangled.iter().take(20) {
        outln!("  quad {} still inverted: {}", t.quad, t.reason.describe());
    }
    if r.tangled.len() > 20 {
        outln!("  ... and {} more", r.tangled.len() - 20);
    }
}

fn cmd_optimize(input: &Path, output: &Path, opts: &OptArgs, as_json: bool) -> Result<(), Fail> {
    let options = opts.options()?;
    Format::from_path(output)?;
    let Loaded { mut data, mut planar } = load(input)?;
    let optimizer = Optimizer::new(&planar.mesh);
    let report = run(&optimizer, &mut planar.mesh, &options)?;
    planar.write_back(&mut data);
    io::write_mesh(output, &data)?;
    if as_json {
        let mut v = json!({
            "input": stats_json(&report.input),
            "output": stats_json(&report.output),
            "iterations": report.iterations,
            "seconds": report.seconds,
            "converged": report.converged,
            "corners": report.corners,
            "movable": report.movable,
            "moved": planar.moved().len(),
            "reoriented_quads": report.reoriented_quads,
            "method": options.method.name(),
            "boundary": options.boundary.name(),
            "vertices": data.points.len(),
            "quads": data.quads.len(),
            "input_file": input.display().to_string(),
            "output_file": output.display().to_string(),
        });
        if let (Value::Object(v), Value::Object(extra)) = (&mut v, report_json(&report)) {
            v.extend(extra);
        }
        outln!("{v}");
        return Ok(());
    }
    outln!("{}: {} vertices, {} quads", input.display(), data.points.len(), data.quads.len());
    outln!("method {}, boundary {}", options.method.name(), options.boundary.name());
    outln!("{:8} {:>9} {:>9} {:>9} {:>9}", "", "min", "avg", "max", "inverted");
    for (name, s) in [("input", &report.input), ("output", &report.output)] {
        outln!("{name:8} {:>9.4} {:>9.4} {:>9.4} {:>9}", s.min, s.avg, s.max, s.inverted);
    }
    outln!(
        "{} iterations ({}), {:.3} s; {} corners, {} movable vertices, {} moved, {} quads reoriented",
        report.iterations,
        if report.converged { "converged" } else { "iteration cap" },
        report.seconds,
        report.corners,
        report.movable,
        planar.moved().len(),
        report.reoriented_quads
    );
    let f = &report.fidelity;
    let modes: Vec<&str> = report.loop_modes.iter().map(|m| m.name()).collect();
    outln!(
        "boundary: modes per loop [{}]; largest deviation {:.3e} ({:.3e} of the mean edge), Hausdorff {:.3e} ({:.3e})",
        modes.join(", "),
        f.max_deviation,
        f.max_deviation_relative,
        f.hausdorff,
        f.hausdorff_relative
    );
    print_tangled(&report);
    outln!("wrote {}", output.display());
    Ok(())
}

/// Counts of quads with scaled Jacobian <= 0 and in ten bins of width 0.1 over (0, 1].
fn histogram(values: &[f64]) -> [usize; 11] {
    let mut h = [0usize; 11];
    for &v in values {
        let bin = if v <= 0.0 || v.is_nan() { 0 } else { ((v * 10.0).ceil() as usize).clamp(1, 10) };
        h[bin] += 1;
    }
    h
}

fn cmd_quality(input: &Path, as_json: bool) -> Result<(), Fail> {
    let Loaded { data, planar } = load(input)?;
    let values = planar.mesh.quality_values();
    let s = QualityStats::from_values(&values);
    let h = histogram(&values);
    if as_json {
        let mut v = stats_json(&s);
        v["file"] = json!(input.display().to_string());
        v["vertices"] = json!(data.points.len());
        v["quads"] = json!(data.quads.len());
        v["histogram"] = json!(h);
        outln!("{v}");
        return Ok(());
    }
    outln!("{}: {} vertices, {} quads", input.display(), data.points.len(), data.quads.len());
    outln!("scaled Jacobian: min {:.4}, avg {:.4}, max {:.4}; {} inverted", s.min, s.avg, s.max, s.inverted);
    let most = h.iter().copied().max().unwrap_or(1).max(1);
    for (i, &count) in h.iter().enumerate() {
        let label = if i == 0 {
            "    <= 0.0".to_string()
        } else {
            format!("({:.1}, {:.1}]", (i - 1) as f64 / 10.0, i as f64 / 10.0)
        };
        let bar = "#".repeat((count * 40).div_ceil(most));
        outln!("  {label:>10} {count:>7} {bar}");
    }
    Ok(())
}

/// The configurations of the paper's Table 2: every method with a fixed boundary, then the
/// embedded polygon method with each moving boundary mode.
const COMPARE: [(Method, BoundaryMode); 7] = [
    (Method::AngleBased, BoundaryMode::Fixed),
    (Method::Laplacian, BoundaryMode::Fixed),
    (Method::Cotangent, BoundaryMode::Fixed),
    (Method::EmbeddedPolygon, BoundaryMode::Fixed),
    (Method::EmbeddedPolygon, BoundaryMode::Slide),
    (Method::EmbeddedPolygon, BoundaryMode::Snap),
    (Method::EmbeddedPolygon, BoundaryMode::Auto),
];

fn cmd_compare(inputs: &[PathBuf], tune: &TuneArgs, as_json: bool) -> Result<(), Fail> {
    let configs: Vec<Options> = COMPARE.iter().map(|&(m, b)| tune.options(m, b)).collect::<Result<_, _>>()?;
    let mut rows = Vec::new();
    for input in inputs {
        let Loaded { data, planar } = load(input)?;
        let optimizer = Optimizer::new(&planar.mesh);
        let mut results = Vec::new();
        for options in &configs {
            let mut mesh = planar.mesh.clone();
            results.push(run(&optimizer, &mut mesh, options)?);
        }
        rows.push((input, data.points.len(), data.quads.len(), planar.mesh.quality(), results));
    }
    if as_json {
        let meshes: Vec<Value> = rows
            .iter()
            .map(|(input, nv, nq, q, results)| {
                let runs: Vec<Value> = results
                    .iter()
                    .zip(&configs)
                    .map(|(r, o)| {
                        json!({
                            "method": o.method.name(), "boundary": o.boundary.name(),
                            "output": stats_json(&r.output), "iterations": r.iterations,
                            "seconds": r.seconds, "converged": r.converged,
                        })
                    })
                    .collect();
                json!({ "file": input.display().to_string(), "vertices": nv, "quads": nq,
                        "input": stats_json(q), "results": runs })
            })
            .collect();
        outln!("{}", json!({ "meshes": meshes }));
        return Ok(());
    }
    out!("{:24} {:>15}", "mesh (min/avg)", "input");
    for o in &configs {
        out!(" {:>15}", format!("{}/{}", o.method.name(), o.boundary.name()));
    }
    outln!();
    for (input, _, _, q, results) in &rows {
        let name = input.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        out!("{name:24} {:>15}", format!("{:.3}/{:.3}", q.min, q.avg));
        for r in results {
            out!(" {:>15}", format!("{:.3}/{:.3}", r.output.min, r.output.avg));
        }
        outln!();
    }
    Ok(())
}

fn cmd_draw(input: &Path, output: &Path, optimized: bool, opts: &OptArgs) -> Result<(), Fail> {
    let options = opts.options()?;
    let Loaded { mut planar, .. } = load(input)?;
    let name = input.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let title = if optimized {
        let report = run(&Optimizer::new(&planar.mesh), &mut planar.mesh, &options)?;
        format!(
            "{name} optimized ({}, {}): min {:.3}, avg {:.3}, {} inverted",
            options.method.name(),
            options.boundary.name(),
            report.output.min,
            report.output.avg,
            report.output.inverted
        )
    } else {
        let q = planar.mesh.quality();
        format!("{name}: min {:.3}, avg {:.3}, {} inverted", q.min, q.avg, q.inverted)
    };
    write_atomic(output, svg::render(&planar.mesh, &title).as_bytes())?;
    Ok(())
}

fn cmd_generate(output: &Path, spec: &Synthetic) -> Result<(), Fail> {
    Format::from_path(output)?;
    if !(0.0..1.0).contains(&spec.hole_size) {
        return Err(Fail::Usage(format!("--hole-size {} is not in [0, 1)", spec.hole_size)));
    }
    if !(spec.jitter >= 0.0 && spec.jitter.is_finite()) {
        return Err(Fail::Usage(format!("--jitter {} is not a finite number >= 0", spec.jitter)));
    }
    if spec.nx == 0 || spec.ny == 0 {
        return Err(Fail::Usage("--nx and --ny must be at least 1".into()));
    }
    let mesh = spec.try_generate()?;
    let points = mesh.points().iter().map(|p| [p.x, p.y, 0.0]).collect();
    io::write_mesh(output, &MeshData::new(points, mesh.quads_as_given()))?;
    let q = mesh.quality();
    outln!(
        "wrote {}: {} vertices, {} quads; scaled Jacobian min {:.4}, avg {:.4}, {} inverted",
        output.display(),
        mesh.points().len(),
        mesh.quads().len(),
        q.min,
        q.avg,
        q.inverted
    );
    Ok(())
}

/// Writes a file through a temporary file in the same directory and a rename.
fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), Fail> {
    let dir = path.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let tmp = dir.join(format!(".{name}.{}.tmp", std::process::id()));
    let result = std::fs::write(&tmp, bytes).and_then(|()| std::fs::rename(&tmp, path));
    if let Err(e) = result {
        let _ = std::fs::remove_file(&tmp);
        return Err(Fail::Other(format!("cannot write {}: {e}", path.display())));
    }
    Ok(())
}

/// The bundled sample meshes: `data/` of the crate, else `./data`.
fn data_dir() -> PathBuf {
    let bundled = Path::new(env!("CARGO_MANIFEST_DIR")).join("data");
    if bundled.is_dir() { bundled } else { PathBuf::from("data") }
}

fn run_data_dir() -> Result<(), Fail> {
    let dir = data_dir();
    let mut files: Vec<PathBuf> = match std::fs::read_dir(&dir) {
        Ok(entries) => entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.is_file() && Format::from_path(p).is_ok())
            .collect(),
        Err(e) => {
            return Err(Fail::Other(format!(
                "no sample meshes: cannot read the data directory {}: {e} (run `quadopt --help` for the commands)",
                dir.display()
            )));
        }
    };
    if files.is_empty() {
        return Err(Fail::Other(format!(
            "no sample meshes (.obj, .off, .vtk, .msh) in {} (run `quadopt --help` for the commands)",
            dir.display()
        )));
    }
    files.sort();
    let options = Options::default();
    outln!(
        "quadopt: {} meshes in {}, method {}, boundary {}",
        files.len(),
        dir.display(),
        options.method.name(),
        options.boundary.name()
    );
    outln!(
        "{:28} {:>7} {:>7}  {:>23}  {:>23}  {:>9} {:>6} {:>8}",
        "model",
        "#V",
        "#F",
        "input min/avg/max",
        "output min/avg/max",
        "inverted",
        "iters",
        "time (s)"
    );
    let mut failed = 0;
    for path in &files {
        let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        let result = load(path).and_then(|Loaded { data, mut planar }| {
            let report = run(&Optimizer::new(&planar.mesh), &mut planar.mesh, &options)?;
            Ok((data, report))
        });
        match result {
            Ok((data, r)) => {
                let (i, o) = (&r.input, &r.output);
                outln!(
                    "{name:28} {:>7} {:>7}  {:>7.3} {:>7.3} {:>7.3}  {:>7.3} {:>7.3} {:>7.3}  {:>4}->{:<4} {:>6} {:>8.3}",
                    data.points.len(),
                    data.quads.len(),
                    i.min,
                    i.avg,
                    i.max,
                    o.min,
                    o.avg,
                    o.max,
                    i.inverted,
                    o.inverted,
                    r.iterations,
                    r.seconds
                );
            }
            Err(Fail::Usage(m) | Fail::Other(m)) => {
                failed += 1;
                outln!("{name:28} error: {m}");
            }
        }
    }
    if failed > 0 {
        return Err(Fail::Other(format!("{failed} of {} meshes could not be optimized", files.len())));
    }
    Ok(())
}
