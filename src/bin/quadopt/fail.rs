//! How `quadopt` fails: one line on stderr, `quadopt: error: ...`, and the exit code 2 for
//! usage errors, 1 for anything else.

use clap::error::ErrorKind;
use std::process::ExitCode;

/// A failure: a usage error (exit 2) or anything else (exit 1), with a one-line message.
pub enum Fail {
    Usage(String),
    Other(String),
}

impl<E: std::fmt::Display> From<E> for Fail {
    fn from(e: E) -> Self {
        Fail::Other(e.to_string())
    }
}

impl Fail {
    /// Prints the message (on one line) and returns the exit code.
    pub fn exit(self) -> ExitCode {
        let (code, msg) = match self {
            Fail::Usage(m) => (2, m),
            Fail::Other(m) => (1, m),
        };
        eprintln!("quadopt: error: {}", msg.replace('\n', " "));
        ExitCode::from(code)
    }
}

/// Prints help and version as clap does; any other parse error as one line
/// `quadopt: error: ...` (clap's message, its indented lines and tip joined), exit code 2.
pub fn usage_error(e: &clap::Error) -> ExitCode {
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
    eprintln!("quadopt: error: {msg} (see '{} --help')", command_of(&rendered));
    ExitCode::from(2)
}

/// The (sub)command a clap error is about, from its usage line (`Usage: quadopt optimize
/// [OPTIONS] ...` gives `quadopt optimize`), so that the hint points at that command's help.
fn command_of(rendered: &str) -> String {
    let usage = rendered.lines().find_map(|l| l.trim().strip_prefix("Usage:"));
    let words: Vec<&str> = usage
        .map(|u| u.split_whitespace().take_while(|w| !w.starts_with(['[', '<', '-'])).collect())
        .unwrap_or_default();
    if words.is_empty() { "quadopt".into() } else { words.join(" ") }
}
