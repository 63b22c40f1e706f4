//! The README and the user guide (`docs/guide/*.md`) say what they show: every code block is
//! either checked or marked as an illustration (docs/guide/README.md, "How the examples are
//! checked"), and this test checks the kinds that are this crate's to check:
//!
//! - ```` ```console ```` transcripts: each `$ ` line is run by `sh` in a scratch directory
//!   holding the repository's `data/` and `cpp_tests/data/`, with this build's `quadopt` first
//!   on the `PATH`; its output (stdout, then stderr, then `[exit status N]` if it failed, paths
//!   into the repository made relative to it) must be the block's, after masking durations (see
//!   `normalise`);
//! - numbers followed by `<!-- from: SUBCOMMAND FILE [OPTION=VALUE ...] : KEY.PATH -->`: the
//!   value at KEY.PATH of the JSON output of `quadopt SUBCOMMAND FILE --OPTION VALUE ... --json`,
//!   printed with the digits the page shows;
//! - ```` ```c ````, ```` ```cpp ```` and other blocks after `<!-- example: FILE#PART -->`: the
//!   part of FILE between `doc:begin PART` and `doc:end`, character for character (cpp_tests/
//!   builds and runs those files);
//! - ```` ```rust ```` blocks: their page is one of the doc-test pages `src/lib.rs` includes;
//! - ```` ```python ```` blocks are run by python/tests/test_docs_and_examples.py;
//! - any other block must follow an `<!-- illustration: why -->` line (or be ```` ```text ````
//!   after one): an unmarked block fails the test.
//!
//! A second test keeps docs/guide/troubleshooting.md complete: every message of the library's
//! errors (src/error.rs, src/io/mod.rs), every C status and its name, and the command-line
//! tool's own messages must appear in it. A third checks that the pages' links (and
//! ARCHITECTURE.md's) lead to a file and, with a `#`, to a heading there.
//!
//! After a change that changes a documented output,
//!
//! ```text
//! QUADOPT_BLESS=1 cargo test --release --test docs
//! ```
//!
//! rewrites the transcripts, the `from:` numbers and the example parts from a fresh run; review
//! the diff. Without `QUADOPT_BLESS` the test fails on any difference, naming the page and line.

use regex::Regex;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::LazyLock;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn bless() -> bool {
    std::env::var_os("QUADOPT_BLESS").is_some_and(|v| v == "1")
}

/// The pages checked: the README and every page of the guide.
fn pages() -> Vec<PathBuf> {
    let mut pages = vec![root().join("README.md")];
    let mut guide: Vec<PathBuf> = std::fs::read_dir(root().join("docs/guide"))
        .expect("docs/guide exists")
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    guide.sort();
    pages.extend(guide);
    pages
}

/// A fenced code block: its language, its body's byte range in the page, the line of its
/// opening fence (1-based), and the comment line right before it, if any.
#[derive(Debug)]
struct Block {
    lang: String,
    body: std::ops::Range<usize>,
    line: usize,
    marker: Option<String>,
}

fn blocks(text: &str) -> Vec<Block> {
    let mut out = Vec::new();
    let mut offset = 0;
    let mut open: Option<(String, usize, usize, Option<String>)> = None;
    let mut previous = "";
    for (i, line) in text.split_inclusive('\n').enumerate() {
        let trimmed = line.trim_end();
        match &open {
            None if trimmed.starts_with("```") => {
                let marker = previous.trim();
                let marker =
                    (marker.starts_with("<!--") && marker.ends_with("-->")).then(|| marker.to_string());
                open = Some((trimmed[3..].trim().to_string(), offset + line.len(), i + 1, marker));
            }
            Some((lang, start, at, marker)) if trimmed == "```" => {
                out.push(Block {
                    lang: lang.clone(),
                    body: *start..offset,
                    line: *at,
                    marker: marker.clone(),
                });
                open = None;
            }
            _ => {}
        }
        if !trimmed.is_empty() {
            previous = line;
        }
        offset += line.len();
    }
    assert!(open.is_none(), "a code block is not closed");
    out
}

/// Durations change from run to run: `0.013 s`, `2.1 ms`, `"seconds":0.01`, the sample
/// report's time column. Both sides are compared with them masked.
fn normalise(text: &str) -> String {
    static DURATION: LazyLock<Regex> =
        LazyLock::new(|| Regex::new(r"\b\d+(\.\d+)?(e-?\d+)? (s|ms)\b").unwrap());
    static JSON_SECONDS: LazyLock<Regex> =
        LazyLock::new(|| Regex::new(r#""(\w*seconds)":\s*[-+0-9.e]+"#).unwrap());
    static TIME_COLUMN: LazyLock<Regex> =
        LazyLock::new(|| Regex::new(r"(?m)(\d+->\d+ +\d+ +)\d+\.\d+$").unwrap());
    let text = DURATION.replace_all(text, "<time> $3");
    let text = JSON_SECONDS.replace_all(&text, "\"$1\":<time>");
    TIME_COLUMN.replace_all(&text, "$1<time>").into_owned()
}

/// The scratch directory the commands of one page run in, with the repository's sample meshes.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("docs-check").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("cpp_tests")).unwrap();
    std::os::unix::fs::symlink(root().join("data"), dir.join("data")).unwrap();
    std::os::unix::fs::symlink(root().join("cpp_tests/data"), dir.join("cpp_tests/data")).unwrap();
    dir
}

/// Runs one command line in `dir` as a user would type it, `quadopt` being this build's.
fn run(command: &str, dir: &Path) -> String {
    let bin = Path::new(env!("CARGO_BIN_EXE_quadopt")).parent().unwrap().to_owned();
    let path = std::env::join_paths(
        std::iter::once(bin).chain(std::env::split_paths(&std::env::var_os("PATH").unwrap_or_default())),
    )
    .unwrap();
    let out = Command::new("sh")
        .arg("-c")
        .arg(command)
        .current_dir(dir)
        .env("PATH", path)
        .env_remove("RAYON_NUM_THREADS")
        .env_remove("QUADOPT_BLESS")
        .output()
        .expect("sh runs");
    let mut text = String::from_utf8_lossy(&out.stdout).into_owned();
    text.push_str(&String::from_utf8_lossy(&out.stderr));
    if !out.status.success() {
        text.push_str(&format!("[exit status {}]\n", out.status.code().unwrap_or(-1)));
    }
    // Paths into the repository are shown relative to it (the sample report names its
    // directory), so the docs read the same on every checkout.
    text.replace(&format!("{}/", root().display()), "")
}

/// Runs a transcript's commands and returns what the block should say.
fn transcript(body: &str, dir: &Path) -> String {
    let mut expected = String::new();
    let mut lines = body.lines().peekable();
    while let Some(line) = lines.next() {
        let Some(mut command) = line.strip_prefix("$ ").map(str::to_string) else {
            continue;
        };
        expected.push_str(line);
        expected.push('\n');
        while command.ends_with('\\') {
            let next = lines.next().expect("a continued command line");
            expected.push_str(next);
            expected.push('\n');
            command.pop();
            command.push('\n');
            command.push_str(next);
        }
        while lines.peek().is_some_and(|l| !l.starts_with("$ ")) {
            lines.next();
        }
        expected.push_str(&run(&command, dir));
    }
    expected
}

/// The `doc:begin PART` ... `doc:end` part of an example file, dedented.
fn example_part(spec: &str) -> String {
    let (file, part) = spec.split_once('#').unwrap_or((spec, ""));
    let text = std::fs::read_to_string(root().join(file)).unwrap_or_else(|e| panic!("{file}: {e}"));
    if part.is_empty() {
        return text;
    }
    let begin = format!("doc:begin {part}");
    let lines: Vec<&str> = text.lines().collect();
    let start = lines
        .iter()
        .position(|l| {
            l.contains(&begin)
                && l.split(&begin)
                    .nth(1)
                    .is_some_and(|r| !r.starts_with(|c: char| c.is_alphanumeric() || c == '_'))
        })
        .unwrap_or_else(|| panic!("{file} has no '{begin}'"));
    let end = start + lines[start..].iter().position(|l| l.contains("doc:end")).expect("doc:end");
    let body = &lines[start + 1..end];
    let indent = body
        .iter()
        .filter(|l| !l.trim().is_empty())
        .map(|l| l.len() - l.trim_start().len())
        .min()
        .unwrap_or(0);
    body.iter().map(|l| format!("{}\n", l.get(indent..).unwrap_or("").trim_end())).collect()
}

/// The value at a dotted path of a JSON document, printed with the digits of `shown`.
fn json_number(json: &serde_json::Value, path: &str, shown: &str) -> String {
    let mut v = json;
    for key in path.split('.') {
        v = match key.parse::<usize>() {
            Ok(i) if v.is_array() => &v[i],
            _ => &v[key],
        };
    }
    let x = v.as_f64().unwrap_or_else(|| panic!("{path} is not a number in {json}"));
    match shown.split_once('.') {
        Some((_, decimals)) => format!("{x:.*}", decimals.len()),
        None => format!("{}", x.round() as i64),
    }
}

#[derive(Default)]
struct Findings {
    failures: Vec<String>,
}

impl Findings {
    fn fail(&mut self, page: &Path, line: usize, what: String) {
        let page = page.strip_prefix(root()).unwrap_or(page).display();
        self.failures.push(format!("{page}:{line}: {what}"));
    }
}

fn line_of(text: &str, offset: usize) -> usize {
    text[..offset].matches('\n').count() + 1
}

/// Pages with Rust blocks must be doc tests: `src/lib.rs` includes them.
fn doctest_pages() -> String {
    std::fs::read_to_string(root().join("src/lib.rs")).unwrap()
}

fn first_difference(expected: &str, actual: &str) -> String {
    for (i, (e, a)) in expected.lines().zip(actual.lines()).enumerate() {
        if normalise(e) != normalise(a) {
            return format!("line {} of the block:\n  documented: {e}\n  now:        {a}", i + 1);
        }
    }
    format!(
        "the block has {} lines, the run {}:\n--- documented\n{expected}--- now\n{actual}",
        expected.lines().count(),
        actual.lines().count()
    )
}

/// Checks one page, returning its text as blessing would rewrite it.
fn check_page(
    page: &Path,
    findings: &mut Findings,
    json_cache: &mut HashMap<String, serde_json::Value>,
) -> String {
    let text = std::fs::read_to_string(page).unwrap();
    let name = page.file_stem().unwrap().to_string_lossy().into_owned();
    let dir =
        scratch(if page.ends_with("README.md") && page.parent() == Some(&root()) { "README" } else { &name });
    let lib = doctest_pages();
    let relative = page.strip_prefix(root()).unwrap().to_string_lossy().into_owned();
    let mut replacements: Vec<(std::ops::Range<usize>, String)> = Vec::new();

    for block in blocks(&text) {
        let body = &text[block.body.clone()];
        let marker = block.marker.as_deref().unwrap_or("");
        let example = marker.strip_prefix("<!-- example:").and_then(|m| m.strip_suffix("-->")).map(str::trim);
        let illustration = marker.starts_with("<!-- illustration");
        if let Some(spec) = example {
            let part = example_part(spec);
            if part != body {
                findings.fail(
                    page,
                    block.line,
                    format!("the block is not {spec}: {}", first_difference(&part, body)),
                );
                replacements.push((block.body.clone(), part));
            }
            continue;
        }
        match block.lang.as_str() {
            "console" => {
                let actual = transcript(body, &dir);
                if normalise(&actual) != normalise(body) {
                    findings.fail(page, block.line, format!("the transcript changed: {}", first_difference(body, &actual)));
                    replacements.push((block.body.clone(), actual));
                }
            }
            "rust" => {
                if !lib.contains(&format!("include_str!(\"../{relative}\")")) {
                    findings.fail(page, block.line, format!("a Rust block, but src/lib.rs does not include {relative} as doc tests"));
                }
            }
            "python" if !illustration => {} // python/tests/test_docs_and_examples.py runs it
            _ if illustration => {}
            lang => findings.fail(
                page,
                block.line,
                format!("a ```{lang} block that nothing checks: mark it <!-- illustration: why --> or <!-- example: FILE#PART -->"),
            ),
        }
    }

    // Numbers from a command's JSON output: `<!-- from: SUBCOMMAND FILE [OPTION=VALUE ...] :
    // KEY.PATH -->` runs `quadopt SUBCOMMAND FILE [--OPTION VALUE ...] --json` (`optimize` with
    // `-o` to a scratch file). No `--` inside: GitHub would not read the comment as one.
    static FROM: LazyLock<Regex> =
        LazyLock::new(|| Regex::new(r"(-?\d+(?:\.\d+)?)(\**`?)<!-- from: (.+?) : ([\w.]+) -->").unwrap());
    for m in FROM.captures_iter(&text) {
        let (number, spec, path) = (m.get(1).unwrap(), &m[3], &m[4]);
        let mut words = spec.split_whitespace();
        let (sub, file) = (words.next().unwrap(), words.next().expect("a file"));
        let mut command = format!("quadopt {sub} {file}");
        for word in words {
            let (key, value) =
                word.split_once('=').unwrap_or_else(|| panic!("{spec}: '{word}' is not OPTION=VALUE"));
            command.push_str(&format!(" --{key} {value}"));
        }
        if sub == "optimize" {
            let ext = Path::new(file).extension().unwrap().to_string_lossy();
            command.push_str(&format!(" -o from-output.{ext}"));
        }
        command.push_str(" --json");
        let json = json_cache.entry(command.clone()).or_insert_with(|| {
            let out = run(&command, &dir);
            serde_json::from_str(&out).unwrap_or_else(|e| panic!("{command}: not JSON ({e}): {out}"))
        });
        let now = json_number(json, path, number.as_str());
        if now != number.as_str() {
            findings.fail(
                page,
                line_of(&text, number.start()),
                format!("{} is now {now} ({command}: {path})", number.as_str()),
            );
            replacements.push((number.range(), now));
        }
    }
    // Every marker must be an HTML comment to GitHub too.
    static COMMENT: LazyLock<Regex> = LazyLock::new(|| Regex::new(r"<!--(.*?)-->").unwrap());
    for c in COMMENT.captures_iter(&text) {
        if c[1].contains("--") {
            let at = line_of(&text, c.get(0).unwrap().start());
            findings.fail(page, at, format!("'--' inside a comment ends it on GitHub: <!--{}-->", &c[1]));
        }
    }

    replacements.sort_by_key(|(r, _)| std::cmp::Reverse(r.start));
    let mut blessed = text.clone();
    for (range, with) in replacements {
        blessed.replace_range(range, &with);
    }
    blessed
}

#[test]
fn documented_outputs_are_what_the_code_prints() {
    let mut findings = Findings::default();
    let mut json_cache = HashMap::new();
    for page in pages() {
        let blessed = check_page(&page, &mut findings, &mut json_cache);
        if bless() && blessed != std::fs::read_to_string(&page).unwrap() {
            std::fs::write(&page, blessed).unwrap();
            eprintln!("blessed {}", page.display());
        }
    }
    let unfixable: Vec<_> = findings
        .failures
        .iter()
        .filter(|f| {
            f.contains("nothing checks") || f.contains("src/lib.rs") || f.contains("inside a comment")
        })
        .collect();
    if bless() {
        assert!(
            unfixable.is_empty(),
            "blessing cannot fix:\n{}",
            unfixable.iter().map(|s| s.as_str()).collect::<Vec<_>>().join("\n")
        );
        return;
    }
    assert!(
        findings.failures.is_empty(),
        "{} differences between the docs and the code (QUADOPT_BLESS=1 cargo test --release --test docs rewrites \
         the docs from a fresh run; review the diff):\n\n{}",
        findings.failures.len(),
        findings.failures.join("\n\n")
    );
}

/// The literal parts of a Rust format string (between `{...}` placeholders), longest first.
fn fragments(format: &str) -> Vec<String> {
    static PLACEHOLDER: LazyLock<Regex> = LazyLock::new(|| Regex::new(r"\{[^{}]*\}").unwrap());
    let mut parts: Vec<String> =
        PLACEHOLDER.split(format).map(|s| s.trim().to_string()).filter(|s| s.len() >= 6).collect();
    parts.sort_by_key(|s| std::cmp::Reverse(s.len()));
    parts
}

/// The string literals of `#[error("...")]` attributes and of the given call sites, joined
/// where Rust continues a literal with `\` at a line's end.
fn messages(source: &str, starts: &[&str]) -> Vec<String> {
    static LITERAL: LazyLock<Regex> = LazyLock::new(|| Regex::new(r#""((?:[^"\\]|\\.)*)""#).unwrap());
    static CONTINUATION: LazyLock<Regex> = LazyLock::new(|| Regex::new(r"\\\n\s*").unwrap());
    let mut out = Vec::new();
    for start in starts {
        for (at, _) in source.match_indices(start) {
            let rest = &source[at + start.len()..];
            if let Some(m) = LITERAL.captures(&rest[..rest.len().min(400)]) {
                // Only a literal that opens the call, not one further on.
                if rest[..m.get(0).unwrap().start()].trim().trim_start_matches("format!(").trim().is_empty() {
                    out.push(CONTINUATION.replace_all(&m[1], "").replace("\\\"", "\""));
                }
            }
        }
    }
    out
}

#[test]
fn troubleshooting_lists_every_message() {
    let page = std::fs::read_to_string(root().join("docs/guide/troubleshooting.md")).unwrap();
    let read = |p: &str| std::fs::read_to_string(root().join(p)).unwrap();
    let mut missing = Vec::new();
    let mut check = |origin: &str, message: &str| {
        let parts = fragments(message);
        if let Some(longest) = parts.first() {
            if !page.contains(longest.as_str()) {
                missing.push(format!("{origin}: \"{longest}\" (from \"{message}\")"));
            }
        }
    };
    // The library's errors and the file readers' and writers'.
    for file in ["src/error.rs", "src/io/mod.rs"] {
        let source = read(file);
        let found = messages(&source, &["#[error(", "format!("]);
        assert!(
            found.len() >= 10 || file != "src/error.rs",
            "{file}: too few messages found ({})",
            found.len()
        );
        for m in found {
            check(file, &m);
        }
    }
    // The command-line tool's own messages.
    let mut cli_files = vec![];
    for dir in ["src/bin/quadopt", "src/bin/quadopt/commands"] {
        for e in std::fs::read_dir(root().join(dir)).unwrap() {
            let p = e.unwrap().path();
            if p.extension().is_some_and(|e| e == "rs") {
                cli_files.push(p);
            }
        }
    }
    let mut cli_count = 0;
    for file in cli_files {
        let source = std::fs::read_to_string(&file).unwrap();
        for m in messages(&source, &["Fail::Usage(", "Fail::Other("]) {
            cli_count += 1;
            check(&file.strip_prefix(root()).unwrap().display().to_string(), &m);
        }
    }
    assert!(cli_count >= 15, "only {cli_count} CLI messages found: has the CLI's error type changed?");
    // Every C status, by its enumerator and by the name quadopt_status_string() gives.
    let header = read("include/quadopt.h");
    let statuses: Vec<&str> = Regex::new(r"\b(QUADOPT_STATUS_[A-Z_]+) = \d+")
        .unwrap()
        .captures_iter(&header)
        .map(|c| c.get(1).unwrap().as_str())
        .collect();
    assert!(statuses.len() >= 16, "{statuses:?}");
    for s in statuses {
        if !page.contains(s) {
            missing.push(format!("include/quadopt.h: {s}"));
        }
    }
    let status = read("src/ffi/status.rs");
    for c in Regex::new(r#"\d+ => c"([^"]+)""#).unwrap().captures_iter(&status) {
        if !page.contains(&format!("\"{}\"", &c[1])) {
            missing.push(format!("src/ffi/status.rs: the status name \"{}\"", &c[1]));
        }
    }
    // The Python package's and the C++ layer's exception types.
    for name in
        ["MeshError", "CancelledError", "UnsupportedFace", "NotPlanar", "quadopt::Error", "MLException"]
    {
        if !page.contains(name) {
            missing.push(format!("the exception {name}"));
        }
    }
    assert!(missing.is_empty(), "docs/guide/troubleshooting.md does not mention:\n{}", missing.join("\n"));
}

/// GitHub's anchor of a heading: lower case, punctuation dropped, spaces as hyphens.
fn anchor(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter(|c| c.is_alphanumeric() || *c == '-' || *c == '_' || *c == ' ')
        .map(|c| if c == ' ' { '-' } else { c })
        .collect()
}

#[test]
fn links_between_the_pages_lead_somewhere() {
    static LINK: LazyLock<Regex> = LazyLock::new(|| Regex::new(r"\]\(([^)\s]+)\)").unwrap());
    static HEADING: LazyLock<Regex> = LazyLock::new(|| Regex::new(r"(?m)^#+ (.*)$").unwrap());
    let mut broken = Vec::new();
    for page in pages().into_iter().chain([root().join("ARCHITECTURE.md")]) {
        let text = std::fs::read_to_string(&page).unwrap();
        let mut prose = text.clone();
        for block in blocks(&text).iter().rev() {
            prose.replace_range(block.body.clone(), "");
        }
        for m in LINK.captures_iter(&prose) {
            let link = &m[1];
            if link.starts_with("http://") || link.starts_with("https://") {
                continue;
            }
            let (path, fragment) = link.split_once('#').unwrap_or((link, ""));
            let target = if path.is_empty() { page.clone() } else { page.parent().unwrap().join(path) };
            let shown = page.strip_prefix(root()).unwrap().display().to_string();
            if !target.exists() {
                broken.push(format!("{shown}: {link}: no such file"));
            } else if !fragment.is_empty() && target.extension().is_some_and(|e| e == "md") {
                let target_text = std::fs::read_to_string(&target).unwrap();
                if !HEADING.captures_iter(&target_text).any(|h| anchor(&h[1]) == fragment) {
                    broken.push(format!("{shown}: {link}: no such heading"));
                }
            }
        }
    }
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}
