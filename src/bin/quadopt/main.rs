//! `quadopt`: improve the quality of 2D quad and quad-dominant (quads and triangles) meshes
//! from the command line.
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

// First: `out!` and `outln!` are in scope in the modules declared after it.
#[macro_use]
mod stdout;

mod annotation;
mod cli;
mod commands;
mod fail;
mod json;
mod mesh_files;
mod openmesh_io;
mod picture;
mod picture_files;
mod plural;
mod progress;
mod surface_report;

use clap::Parser;
use cli::{Cli, Command};
use commands::Drawn;
use fail::{Fail, usage_error};
use quadopt::synthetic::Synthetic;
use std::process::ExitCode;

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => return usage_error(&e),
    };
    if let Err(m) = openmesh_io::set_reader(cli.reader) {
        return Fail::Usage(m).exit();
    }
    #[cfg(unix)]
    remove_temporary_files_on_signal();
    cap_global_pool();
    let result = match cli.threads {
        // Capped as quadopt's own pool is: thousands of threads only exhaust the address space.
        Some(n) => match rayon::ThreadPoolBuilder::new().num_threads(n.min(quadopt::max_threads())).build() {
            Ok(pool) => pool.install(|| dispatch(cli.command)),
            Err(e) => Err(Fail::Other(format!("cannot start {n} threads: {e}"))),
        },
        None => dispatch(cli.command),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(fail) => fail.exit(),
    }
}

/// rayon's global pool, which a few measures use on large meshes outside a run, reads
/// `RAYON_NUM_THREADS` as quadopt's pool does: a count above [`quadopt::max_threads`] is capped
/// there too, so that an absurd one never starts thousands of threads.
fn cap_global_pool() {
    let requested = std::env::var("RAYON_NUM_THREADS").ok().and_then(|s| s.trim().parse::<usize>().ok());
    if requested.is_some_and(|n| n > quadopt::max_threads()) {
        // An error means the global pool exists already: nothing to cap then.
        let _ = rayon::ThreadPoolBuilder::new().num_threads(quadopt::max_threads()).build_global();
    }
}

fn dispatch(command: Option<Command>) -> Result<(), Fail> {
    match command {
        None => commands::run_data_dir(),
        Some(Command::Optimize { input, output, format, encoding, opts, picture, json }) => {
            commands::optimize(&input, &output, format, &encoding, &opts, picture.as_deref(), json)
        }
        Some(Command::Quality { input, reference, output, format, encoding, json }) => {
            commands::quality(&input, reference.as_deref(), output.as_deref(), format, &encoding, json)
        }
        Some(Command::Compare { inputs, tune, json }) => commands::compare(&inputs, &tune, json),
        Some(Command::Draw { input, output, optimized, before_after, opts }) => {
            let what = match (optimized, before_after) {
                (_, true) => Drawn::BeforeAfter,
                (true, _) => Drawn::Optimized,
                _ => Drawn::Input,
            };
            commands::draw(&input, &output, what, &opts)
        }
        Some(Command::Generate {
            output,
            format,
            quads,
            nx,
            ny,
            holes,
            hole_size,
            jitter,
            seed,
            triangles,
        }) => {
            let spec = match quads {
                Some(n) => Synthetic { holes, hole_size, jitter, seed, ..Synthetic::with_quads(n) },
                None => Synthetic { nx, ny, holes, hole_size, jitter, seed },
            };
            commands::generate(&output, format, &spec, triangles)
        }
    }
}

/// On SIGINT or SIGTERM, removes the temporary output file being written, then ends the
/// process as the signal would have.
#[cfg(unix)]
fn remove_temporary_files_on_signal() {
    use signal_hook::consts::{SIGINT, SIGTERM};
    let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM]) else { return };
    std::thread::spawn(move || {
        if let Some(signal) = signals.forever().next() {
            quadopt::io::remove_pending_temporary_files();
            let _ = signal_hook::low_level::emulate_default_handler(signal);
            std::process::exit(128 + signal);
        }
    });
}
