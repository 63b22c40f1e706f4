//! Stdout is shared by the report and, with `-o -`, the output itself: then the report goes
//! to stderr. The report is printed with [`out!`] and [`outln!`], which know where it goes.

use crate::fail::Fail;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

/// Whether the report goes to stderr because stdout carries the output (`-o -`).
pub static REPORT_ON_STDERR: AtomicBool = AtomicBool::new(false);

/// `print!` of the report: to stdout (or stderr with `-o -`), ending the program quietly when
/// stdout is closed (`quadopt compare ... | head`) instead of panicking with "failed printing
/// to stdout".
macro_rules! out {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let written = if $crate::stdout::REPORT_ON_STDERR.load(std::sync::atomic::Ordering::Relaxed) {
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

/// Whether `-o` names stdout.
pub fn is_stdout(path: &Path) -> bool {
    path.as_os_str() == "-"
}

/// Sends the rest of the report to stderr if the output just written went to stdout.
pub fn report_on_stderr_if_written_to_stdout(output: &Path) {
    REPORT_ON_STDERR.store(is_stdout(output), Ordering::Relaxed);
}

/// The failure of writing the output to stdout (a closed pipe, a full disk).
pub fn stdout_write_error(e: std::io::Error) -> Fail {
    Fail::Other(format!("cannot write to stdout: {e}"))
}
