//! `quadopt`: improve the quality of 2D quad meshes from the command line.
//!
//! - `quadopt` with no arguments optimizes every mesh in the bundled `data/` directory and
//!   prints a report like the paper's Table 1.
//! - `quadopt optimize IN -o OUT`, `quadopt quality IN`, `quadopt compare IN...`,
//!   `quadopt draw IN -o OUT.png` (or `.svg`): see `quadopt help`.
//!
//! Errors are one line on stderr, `quadopt: error: ...`; the exit code is 2 for usage errors,
//! 1 for anything else. Output files are written as [`quadopt::io::output`] describes (a
//! regular file is replaced atomically, a device or FIFO written in place); `-o -` writes to
//! stdout, and the report then goes to stderr.

mod openmesh_io;
mod picture;

/// Whether the report goes to stderr because stdout carries the output mesh (`-o -`).
static REPORT_ON_STDERR: AtomicBool = AtomicBool::new(false);

/// `print!` of the report: to stdout (or stderr with `-o -`), ending the program quietly when
/// stdout is closed (`quadopt compare ... | head`) instead of panicking with "failed printing
/// to stdout".
macro_rules! out {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let written = if REPORT_ON_STDERR.load(Ordering::Relaxed) {
            write!(std::io::stderr(), $($arg)*)
        } else {
            write!(std::io::stdout(), $($arg)*)
        };
        if written.is_err() {
            std::process::exit(0);
        }
    }};
}

/// `println!` with the behaviour of [`out!`].
macro_rules! outln {
    () => { out!("\n") };
    ($($arg:tt)*) => {{
        out!($($arg)*);
        out!("\n");
    }};
}

use clap::error::ErrorKind;
use clap::{Args, Parser, Subcommand};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use quadopt::io::{self, Format, MeshData, PlanarMesh};
use quadopt::synthetic::Synthetic;
use quadopt::{BoundaryMode, Method, Optimizer, Options, Progress, QuadMesh, QualityStats, Report, StopRule};
use serde_json::{Value, json};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

#[derive(Parser)]
#[command(
    name = "quadopt",
    version = openmesh_io::VERSION,
    about = "Quality optimizer for 2D quad meshes (embedded polygon method)"
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    /// Number of threads (default: one per core); results are identical on any number.
    #[arg(long, global = true, value_name = "N", value_parser = parse_threads)]
    threads: Option<usize>,
    /// Reader for .obj and .off: auto (quadopt's) or openmesh (.ply and .om always use OpenMesh).
    #[arg(long, global = true, value_enum, default_value_t)]
    reader: openmesh_io::Reader,
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
struct EncodingArgs {
    /// Output encoding: ascii; binary (MSH binary, VTU inline base64); appended (VTU appended
    /// raw data, ParaView's default). Other formats are always text.
    #[arg(long, value_parser = parse_encoding)]
    encoding: Option<io::Encoding>,
    /// Compress VTU binary or appended data with zlib (ParaView's default).
    #[arg(long)]
    zlib: bool,
}

impl EncodingArgs {
    fn apply(&self, data: &mut MeshData) {
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
enum Command {
    /// Optimize a mesh and write the result.
    Optimize {
        /// Input mesh (.obj, .off, .vtk, .msh).
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
    /// Print the quality of a mesh.
    Quality {
        /// Input mesh.
        input: PathBuf,
        /// Also write the mesh with its per-quad scaled Jacobian as cell data and its fixed
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
    /// Draw a mesh as PNG or SVG (by extension), quads coloured by scaled Jacobian.
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
    /// Write a synthetic benchmark mesh: a grid with circular holes and jittered interior vertices.
    Generate {
        /// Output mesh (format from its extension); `-` writes to stdout (needs --format).
        #[arg(short, long)]
        output: PathBuf,
        /// Output format, whatever the output's name: obj, off, vtk, msh or vtu.
        #[arg(long, value_parser = parse_format)]
        format: Option<Format>,
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
    /// Keep every node of the Gmsh physical curve or point NAME fixed (MSH input;
    /// repeatable).
    #[arg(long = "fix-physical", value_name = "NAME")]
    fix_physical: Vec<String>,
    #[command(flatten)]
    tune: TuneArgs,
}

/// Numeric options shared by every optimizing command.
#[derive(Args, Clone)]
struct TuneArgs {
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
    /// Do not untangle inverted quads before smoothing.
    #[arg(long)]
    no_untangle: bool,
    /// Skip the max-min stage (which raises the worst quad after the sweeps).
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
            max_min: base.max_min && !self.no_maxmin,
            // A threshold on the energy asks for the energy rule.
            stop: self.stop.unwrap_or(if self.tau.is_some() || self.absolute_tau {
                StopRule::Energy
            } else {
                base.stop
            }),
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
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => return usage_error(&e),
    };
    if let Err(m) = openmesh_io::set_reader(cli.reader) {
        eprintln!("quadopt: error: {m}");
        return ExitCode::from(2);
    }
    #[cfg(unix)]
    remove_temporary_files_on_signal();
    let result = match cli.threads {
        Some(n) => match rayon::ThreadPoolBuilder::new().num_threads(n).build() {
            Ok(pool) => pool.install(|| dispatch(cli.command)),
            Err(e) => Err(Fail::Other(format!("cannot start {n} threads: {e}"))),
        },
        None => dispatch(cli.command),
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

fn dispatch(command: Option<Command>) -> Result<(), Fail> {
    match command {
        None => run_data_dir(),
        Some(Command::Optimize { input, output, format, encoding, opts, picture, json }) => {
            cmd_optimize(&input, &output, format, &encoding, &opts, picture.as_deref(), json)
        }
        Some(Command::Quality { input, output, format, encoding, json }) => {
            cmd_quality(&input, output.as_deref(), format, &encoding, json)
        }
        Some(Command::Compare { inputs, tune, json }) => cmd_compare(&inputs, &tune, json),
        Some(Command::Draw { input, output, optimized, before_after, opts }) => {
            let what = match (optimized, before_after) {
                (_, true) => Drawn::BeforeAfter,
                (true, _) => Drawn::Optimized,
                _ => Drawn::Input,
            };
            cmd_draw(&input, &output, what, &opts)
        }
        Some(Command::Generate { output, format, quads, nx, ny, holes, hole_size, jitter, seed }) => {
            let spec = match quads {
                Some(n) => Synthetic { holes, hole_size, jitter, seed, ..Synthetic::with_quads(n) },
                None => Synthetic { nx, ny, holes, hole_size, jitter, seed },
            };
            cmd_generate(&output, format, &spec)
        }
    }
}

/// Prints help and version as clap does; any other parse error as one line
/// `quadopt: error: ...` (clap's message, its indented lines and tip joined), exit code 2.
fn usage_error(e: &clap::Error) -> ExitCode {
    if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion) {
        let _ = e.print();
        return ExitCode::SUCCESS;
    }
    let rendered = e.render().to_string();
    let mut msg = String::new();
    for line in rendered.lines().map(str::trim) {
        if line.starts_with("Usage:") || line.starts_with("For more information") {
            break;
        }
        if line.is_empty() {
            continue;
        }
        if !msg.is_empty() {
            msg.push_str(if line.starts_with("tip:") { "; " } else { " " });
        }
        msg.push_str(line.strip_prefix("error:").map_or(line, str::trim_start));
    }
    if msg.is_empty() {
        msg = e.kind().to_string();
    }
    eprintln!("quadopt: error: {msg} (see 'quadopt --help')");
    ExitCode::from(2)
}

/// On SIGINT or SIGTERM, removes the temporary output file being written, then ends the
/// process as the signal would have.
#[cfg(unix)]
fn remove_temporary_files_on_signal() {
    use signal_hook::consts::{SIGINT, SIGTERM};
    let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM]) else { return };
    std::thread::spawn(move || {
        if let Some(signal) = signals.forever().next() {
            io::remove_pending_temporary_files();
            let _ = signal_hook::low_level::emulate_default_handler(signal);
            std::process::exit(128 + signal);
        }
    });
}

/// Whether `-o` names stdout.
fn is_stdout(path: &Path) -> bool {
    path.as_os_str() == "-"
}

/// The format to write: `--format`, else the output's extension, else (for stdout) `fallback`.
fn output_format(output: &Path, format: Option<Format>, fallback: Option<Format>) -> Result<Format, Fail> {
    match (format, is_stdout(output), fallback) {
        (Some(f), _, _) => Ok(f),
        (None, true, Some(f)) => Ok(f),
        (None, true, None) => Err(Fail::Usage("writing to stdout (-o -) needs --format".into())),
        (None, false, _) => Ok(Format::from_path(output)?),
    }
}

/// Writes a mesh to `output` (or stdout for `-`), every write checked.
fn write_mesh_output(output: &Path, format: Format, data: &MeshData) -> Result<(), Fail> {
    if !is_stdout(output) {
        return Ok(io::write_mesh_as(output, format, data)?);
    }
    io::write_mesh_to(&mut std::io::stdout().lock(), format, data).map_err(|e| match e {
        io::IoError::Stream(e) => Fail::Other(format!("cannot write to stdout: {e}")),
        e => Fail::Other(e.to_string()),
    })
}

/// A mesh read from a file and mapped to 2D.
struct Loaded {
    data: MeshData,
    planar: PlanarMesh,
}

/// Reads `path`; the nodes of the physical groups named in `fix` join the fixed flags.
fn load(path: &Path, fix: &[String]) -> Result<Loaded, Fail> {
    let mut data = openmesh_io::read_mesh(path)?;
    fix_physical(&mut data, fix).map_err(|e| Fail::Other(format!("{}: {e}", path.display())))?;
    let planar = PlanarMesh::new(&data).map_err(|e| Fail::Other(format!("{}: {e}", path.display())))?;
    Ok(Loaded { data, planar })
}

/// Pins every node of the physical points and curves named `names` (all groups of a name).
fn fix_physical(data: &mut MeshData, names: &[String]) -> Result<(), String> {
    let n = data.points.len();
    for name in names {
        let groups: Vec<&io::PhysicalGroup> =
            data.physical_groups.iter().filter(|g| &g.name == name).collect();
        if groups.is_empty() {
            let mut known: Vec<&str> =
                data.physical_groups.iter().map(|g| g.name.as_str()).filter(|s| !s.is_empty()).collect();
            known.dedup();
            let has = if known.is_empty() {
                "the file has none".to_string()
            } else {
                format!("the file has: {}", known.join(", "))
            };
            return Err(format!("--fix-physical {name}: no physical point or curve of that name ({has})"));
        }
        let nodes: Vec<u32> = groups.iter().flat_map(|g| g.nodes.iter().copied()).collect();
        let fixed = data.fixed.get_or_insert_with(|| vec![false; n]);
        for v in nodes {
            fixed[v as usize] = true;
        }
    }
    Ok(())
}

/// How long a run goes before the progress bar appears.
const PROGRESS_DELAY: Duration = Duration::from_millis(500);

/// Runs the optimizer. With `progress`, a run lasting more than [`PROGRESS_DELAY`] draws a
/// progress bar on stderr if stderr is a terminal (cleared at the end).
fn run(
    optimizer: &Optimizer,
    mesh: &mut QuadMesh,
    options: &Options,
    progress: bool,
) -> Result<Report, Fail> {
    if !progress || !std::io::stderr().is_terminal() {
        return Ok(optimizer.run(mesh, options, None)?);
    }
    let start = Instant::now();
    let mut bar: Option<ProgressBar> = None;
    let mut cb = |p: &Progress| {
        if bar.is_none() && start.elapsed() >= PROGRESS_DELAY {
            let b =
                ProgressBar::with_draw_target(Some(p.max_iterations as u64), ProgressDrawTarget::stderr());
            if let Ok(style) =
                ProgressStyle::with_template("{prefix} [{bar:30}] {pos}/{len} sweeps, {msg} ({elapsed})")
            {
                b.set_style(style.progress_chars("=> "));
            }
            bar = Some(b);
        }
        if let Some(b) = &bar {
            b.set_prefix(format!("pass {}/{}", p.pass, p.passes));
            b.set_length(p.max_iterations as u64);
            b.set_position(p.iteration as u64);
            b.set_message(format!("energy {:.6e}", p.energy));
        }
        true
    };
    let report = optimizer.run(mesh, options, Some(&mut cb));
    if let Some(b) = bar {
        b.finish_and_clear();
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
        "max_min": r.max_min.map(|g| json!({
            "before": stats_json(&g.before), "after": stats_json(&g.after),
            "rounds": g.rounds, "seconds": g.seconds,
        })),
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

fn cmd_optimize(
    input: &Path,
    output: &Path,
    format: Option<Format>,
    encoding: &EncodingArgs,
    opts: &OptArgs,
    picture: Option<&Path>,
    as_json: bool,
) -> Result<(), Fail> {
    let options = opts.options()?;
    if picture.is_some_and(is_stdout) {
        return Err(Fail::Usage("--picture needs a file name (- is where draw writes to stdout)".into()));
    }
    let picture_format = picture.map(PictureFormat::of).transpose()?;
    let format = if openmesh_io::handles_output(output) {
        openmesh_io::check_output(output)?;
        None
    } else {
        Some(output_format(output, format, Format::from_path(input).ok())?)
    };
    let Loaded { mut data, mut planar } = load(input, &opts.fix_physical)?;
    // Before the optimizer's topology exists, so that the run's peak memory is not raised.
    let corners = corner_flags(&planar.mesh, &options);
    // `write_back` puts the quads back: meanwhile the file's copy is 16 bytes a quad for
    // nothing, as is the topology once the run is over (the writers need memory too).
    data.quads = Vec::new();
    // The input as it was, for the picture only (a copy of the 2D mesh).
    let before =
        picture.map(|_| planar.mesh.try_clone()).transpose().map_err(|e| Fail::Other(e.to_string()))?;
    let optimizer = Optimizer::new(&planar.mesh);
    let report = run(&optimizer, &mut planar.mesh, &options, !as_json)?;
    drop(optimizer);
    if let (Some(path), Some(f), Some(before)) = (picture, picture_format, &before) {
        let title = input.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        let headings = [
            "input".to_string(),
            format!("optimized ({}, {})", options.method.name(), options.boundary.name()),
        ];
        let p = picture::layout::before_after(
            before,
            &planar.mesh,
            &title,
            headings.each_ref().map(String::as_str),
        );
        write_picture(path, f, &p)?;
    }
    drop(before);
    let moved = planar.write_back(&mut data);
    annotate(&mut data, &planar, corners);
    encoding.apply(&mut data);
    match format {
        Some(format) => write_mesh_output(output, format, &data)?,
        None => openmesh_io::write_mesh(output, &data)?,
    }
    REPORT_ON_STDERR.store(is_stdout(output), Ordering::Relaxed);
    if as_json {
        let mut v = json!({
            "input": stats_json(&report.input),
            "output": stats_json(&report.output),
            "iterations": report.iterations,
            "seconds": report.seconds,
            "converged": report.converged,
            "corners": report.corners,
            "movable": report.movable,
            "moved": moved,
            "reoriented_quads": report.reoriented_quads,
            "method": options.method.name(),
            "boundary": options.boundary.name(),
            "vertices": data.points.len(),
            "quads": data.quads.len(),
            "input_file": input.display().to_string(),
            "output_file": output.display().to_string(),
        });
        if let Some(path) = picture {
            v["picture_file"] = json!(path.display().to_string());
        }
        if let (Value::Object(v), Value::Object(extra)) = (&mut v, report_json(&report)) {
            v.extend(extra);
        }
        outln!("{v}");
        return Ok(());
    }
    outln!("{}: {} vertices, {} quads", input.display(), data.points.len(), data.quads.len());
    outln!("method {}, boundary {}", options.method.name(), options.boundary.name());
    outln!("{:8} {:>9} {:>9} {:>9} {:>9}", "", "min", "avg", "max", "inverted");
    let sweeps = report.max_min.map(|g| ("sweeps", g.before));
    for (name, s) in [("input", report.input)].into_iter().chain(sweeps).chain([("output", report.output)]) {
        outln!("{name:8} {:>9.4} {:>9.4} {:>9.4} {:>9}", s.min, s.avg, s.max, s.inverted);
    }
    outln!(
        "{} iterations ({}), {:.3} s; {} corners, {} movable vertices, {} moved, {} quads reoriented",
        report.iterations,
        if report.converged { "converged" } else { "iteration cap" },
        report.seconds,
        report.corners,
        report.movable,
        moved,
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
    if let Some(path) = picture {
        outln!("wrote the picture {}", path.display());
    }
    if is_stdout(output) {
        outln!("wrote the mesh to stdout");
    } else {
        outln!("wrote {}", output.display());
    }
    Ok(())
}

/// Per-vertex corner flags of `mesh` (the corners `options` keep in place).
fn corner_flags(mesh: &QuadMesh, options: &Options) -> Vec<bool> {
    let topo = quadopt::Topology::new(mesh);
    let features = quadopt::Features::new(
        mesh,
        &topo,
        options.feature_angle_deg,
        options.boundary != BoundaryMode::Fixed,
    );
    (0..mesh.points().len()).map(|v| features.is_corner(v)).collect()
}

/// Adds what viewers colour by to `data`: each quad's signed scaled Jacobian at the planar
/// mesh's positions, and the fixed and corner flags.
fn annotate(data: &mut MeshData, planar: &PlanarMesh, corners: Vec<bool>) {
    data.quality = Some(planar.mesh.quality_values());
    data.fixed = Some(planar.mesh.fixed().to_vec());
    data.corner = Some(corners);
}

fn cmd_quality(
    input: &Path,
    output: Option<&Path>,
    format: Option<Format>,
    encoding: &EncodingArgs,
    as_json: bool,
) -> Result<(), Fail> {
    let Loaded { mut data, planar } = load(input, &[])?;
    let values = planar.mesh.quality_values();
    if let Some(output) = output {
        let corners = corner_flags(&planar.mesh, &Options::default());
        annotate(&mut data, &planar, corners);
        encoding.apply(&mut data);
        if openmesh_io::handles_output(output) {
            openmesh_io::check_output(output)?;
            openmesh_io::write_mesh(output, &data)?;
        } else {
            let format = output_format(output, format, Format::from_path(input).ok())?;
            write_mesh_output(output, format, &data)?;
        }
        // The mesh went to stdout: the report goes to stderr.
        REPORT_ON_STDERR.store(is_stdout(output), Ordering::Relaxed);
    }
    let s = QualityStats::from_values(&values);
    let h = picture::histogram(&values);
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
        let Loaded { data, planar } = load(input, &[])?;
        let optimizer = Optimizer::new(&planar.mesh);
        let mut results = Vec::new();
        for options in &configs {
            let mut mesh = planar.mesh.clone();
            results.push(run(&optimizer, &mut mesh, options, !as_json)?);
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

/// What `draw` draws.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Drawn {
    Input,
    Optimized,
    BeforeAfter,
}

/// A picture file's format, from its name.
#[derive(Clone, Copy, PartialEq, Eq)]
enum PictureFormat {
    Svg,
    Png,
}

impl PictureFormat {
    /// `.png` or `.svg` (any case); `-` (stdout) is SVG.
    fn of(path: &Path) -> Result<PictureFormat, Fail> {
        if is_stdout(path) {
            return Ok(PictureFormat::Svg);
        }
        match path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref() {
            Some("svg") => Ok(PictureFormat::Svg),
            Some("png") => Ok(PictureFormat::Png),
            _ => Err(Fail::Other(format!(
                "{}: not a picture file name (expected the extension .png or .svg, or - for SVG on stdout)",
                path.display()
            ))),
        }
    }
}

/// Writes `picture` to `path` (or stdout for `-`) in `format`.
fn write_picture(path: &Path, format: PictureFormat, picture: &picture::Picture) -> Result<(), Fail> {
    let bytes = match format {
        PictureFormat::Svg => picture::svg::render(picture).into_bytes(),
        PictureFormat::Png => {
            picture::png::render(picture).map_err(|e| Fail::Other(format!("{}: {e}", path.display())))?
        }
    };
    if is_stdout(path) {
        use std::io::Write as _;
        let mut out = std::io::stdout().lock();
        out.write_all(&bytes)
            .and_then(|()| out.flush())
            .map_err(|e| Fail::Other(format!("cannot write to stdout: {e}")))?;
    } else {
        io::write_file(path, &bytes)?;
    }
    Ok(())
}

fn cmd_draw(input: &Path, output: &Path, what: Drawn, opts: &OptArgs) -> Result<(), Fail> {
    let options = opts.options()?;
    let format = PictureFormat::of(output)?;
    let Loaded { mut planar, .. } = load(input, &opts.fix_physical)?;
    let name = input.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let optimized = format!("optimized ({}, {})", options.method.name(), options.boundary.name());
    let picture = match what {
        Drawn::Input => {
            let q = planar.mesh.quality();
            picture::layout::single(
                &planar.mesh,
                &format!("{name}: min {:.3}, avg {:.3}, {} inverted", q.min, q.avg, q.inverted),
            )
        }
        Drawn::Optimized => {
            let report = run(&Optimizer::new(&planar.mesh), &mut planar.mesh, &options, true)?;
            let o = report.output;
            let title =
                format!("{name} {optimized}: min {:.3}, avg {:.3}, {} inverted", o.min, o.avg, o.inverted);
            picture::layout::single(&planar.mesh, &title)
        }
        Drawn::BeforeAfter => {
            let before = planar.mesh.try_clone().map_err(|e| Fail::Other(e.to_string()))?;
            run(&Optimizer::new(&planar.mesh), &mut planar.mesh, &options, true)?;
            picture::layout::before_after(&before, &planar.mesh, &name, ["input", &optimized])
        }
    };
    write_picture(output, format, &picture)
}

fn cmd_generate(output: &Path, format: Option<Format>, spec: &Synthetic) -> Result<(), Fail> {
    let format = if openmesh_io::handles_output(output) {
        openmesh_io::check_output(output)?;
        None
    } else {
        Some(output_format(output, format, None)?)
    };
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
    let data = MeshData::new(points, mesh.quads_as_given());
    match format {
        Some(format) => write_mesh_output(output, format, &data)?,
        None => openmesh_io::write_mesh(output, &data)?,
    }
    REPORT_ON_STDERR.store(is_stdout(output), Ordering::Relaxed);
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
            "no sample meshes (.obj, .off, .vtk, .msh, .vtu) in {} (run `quadopt --help` for the commands)",
            dir.display()
        )));
    }
    files.sort();
    let options = Options::default();
    // Relative to the working directory when inside it: what a user would type.
    let shown =
        std::env::current_dir().ok().and_then(|cwd| dir.strip_prefix(cwd).ok().map(Path::to_path_buf));
    outln!(
        "quadopt: {} meshes in {}, method {}, boundary {}",
        files.len(),
        shown.as_deref().unwrap_or(&dir).display(),
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
        let result = load(path, &[]).and_then(|Loaded { data, mut planar }| {
            let report = run(&Optimizer::new(&planar.mesh), &mut planar.mesh, &options, true)?;
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
