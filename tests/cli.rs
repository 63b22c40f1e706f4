//! The `quadopt` binary, run as a user would.

mod common;

use common::grids::{Grid, mesh_data_at_z};
use quadopt::DVec2;
use quadopt::io::{self, MeshData};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn quadopt(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_quadopt")).args(args).output().unwrap()
}

fn scratch(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("quadopt-cli-{}-{test}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// An n x n grid of unit squares in the plane z = -5 with its interior vertices jittered
/// (deterministically) by up to 0.35, and vertex (1, 1) dragged across its neighbours so that
/// quads fold.
fn jittered_grid(n: usize) -> MeshData {
    let grid = Grid::square(n);
    let (points, quads) = grid.placed(|i, j| {
        let (mut x, mut y) = (i as f64, j as f64);
        if grid.is_interior(i, j) {
            x += 0.35 * ((i * 12 + j * 7) as f64).sin();
            y += 0.35 * ((i * 5 + j * 13) as f64).cos();
        }
        if (i, j) == (1, 1) {
            (x, y) = (2.3, 2.2);
        }
        DVec2::new(x, y)
    });
    mesh_data_at_z(&points, quads, -5.0)
}

fn json_stdout(out: &Output) -> Value {
    assert!(out.status.success(), "stderr: {}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout.clone()).unwrap();
    assert_eq!(text.trim_end().lines().count(), 1, "exactly one JSON line: {text}");
    serde_json::from_str(&text).unwrap()
}

fn stats_keys(v: &Value) {
    for k in ["min", "avg", "max"] {
        assert!(v[k].is_f64(), "{k} in {v}");
    }
    assert!(v["inverted"].is_u64(), "{v}");
}

#[test]
fn optimize_json_improves_a_jittered_grid() {
    let dir = scratch("optimize");
    let input = dir.join("grid.obj");
    let mesh = jittered_grid(8);
    io::write_mesh(&input, &mesh).unwrap();
    let output = dir.join("out.off");
    let v =
        json_stdout(&quadopt(&["optimize", s(&input), "-o", s(&output), "--boundary", "fixed", "--json"]));
    stats_keys(&v["input"]);
    stats_keys(&v["output"]);
    assert!(v["iterations"].as_u64().unwrap() >= 1);
    assert!(v["seconds"].as_f64().unwrap() >= 0.0);
    assert_eq!((v["method"].as_str(), v["boundary"].as_str()), (Some("ep"), Some("fixed")));
    assert!(v["input"]["inverted"].as_u64().unwrap() > 0, "the jitter folds some quads: {v}");
    assert_eq!(v["output"]["inverted"].as_u64(), Some(0));
    assert!(v["output"]["avg"].as_f64().unwrap() > v["input"]["avg"].as_f64().unwrap() + 0.05, "{v}");
    assert!(v["output"]["min"].as_f64().unwrap() > 0.5, "{v}");
    // The output file holds the optimized mesh: same quads, boundary bit-identical, z kept,
    // and its measured quality is what was reported.
    let back = io::read_mesh(&output).unwrap();
    assert_eq!(back.quads, mesh.quads);
    for (i, (p, q)) in back.points.iter().zip(&mesh.points).enumerate() {
        let (x, y) = (i % 9, i / 9);
        if x == 0 || y == 0 || x == 8 || y == 8 {
            assert_eq!(p.map(f64::to_bits), q.map(f64::to_bits), "boundary vertex {i}");
        }
        assert_eq!(p[2], -5.0);
    }
    let q = json_stdout(&quadopt(&["quality", s(&output), "--json"]));
    assert_eq!(q["avg"], v["output"]["avg"]);
    assert_eq!(q["min"], v["output"]["min"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn vtk_fixed_vertices_and_unused_vertices_come_back_bit_identical() {
    let dir = scratch("fixed");
    let mut mesh = jittered_grid(6);
    // Fix the boundary and two interior vertices; add an unused vertex.
    let mut fixed: Vec<bool> =
        (0..mesh.points.len()).map(|i| i % 7 == 0 || i % 7 == 6 || !(7..42).contains(&i)).collect();
    fixed[8] = true;
    fixed[24] = true;
    mesh.points.push([0.1, 0.7, 3.0]);
    fixed.push(false);
    mesh.fixed = Some(fixed.clone());
    let input = dir.join("in.vtk");
    io::write_mesh(&input, &mesh).unwrap();
    let output = dir.join("out.vtk");
    let out = quadopt(&["optimize", s(&input), "-o", s(&output), "--boundary", "slide"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("input") && text.contains("output") && text.contains("iterations"), "{text}");
    let back = io::read_mesh(&output).unwrap();
    assert_eq!(back.fixed.as_ref(), Some(&fixed), "fixed flags written back");
    assert_eq!(back.quads, mesh.quads);
    let mut moved = 0;
    for (i, (p, q)) in back.points.iter().zip(&mesh.points).enumerate() {
        if fixed[i] || i == mesh.points.len() - 1 {
            assert_eq!(p.map(f64::to_bits), q.map(f64::to_bits), "vertex {i}");
        } else {
            moved += usize::from(p != q);
        }
    }
    assert!(moved > 20, "{moved} interior vertices moved");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Runs a failing command: exit code, one-line stderr, and no output file.
fn fails(args: &[&str], code: i32, needle: &str, output: Option<&Path>) {
    let out = quadopt(args);
    assert_eq!(out.status.code(), Some(code), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.contains(needle), "{args:?}: {err}");
    // Usage errors (clap's too) and every other error alike: one line with the prefix.
    assert_eq!(err.lines().count(), 1, "one line: {err}");
    assert!(err.starts_with("quadopt: error: "), "{err}");
    if let Some(o) = output {
        assert!(!o.exists(), "{} was created", o.display());
        let leftovers: Vec<_> = std::fs::read_dir(o.parent().unwrap())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .filter(|n| n.to_string_lossy().contains(".tmp"))
            .collect();
        assert!(leftovers.is_empty(), "{leftovers:?}");
    }
}

#[test]
fn errors_are_one_line_with_the_right_exit_code_and_no_output() {
    let dir = scratch("errors");
    let good = dir.join("good.obj");
    io::write_mesh(&good, &jittered_grid(3)).unwrap();
    let out = dir.join("out.vtk");
    let (g, o) = (s(&good), s(&out));
    fails(&["optimize", s(&dir.join("missing.obj")), "-o", o], 1, "missing.obj: No such file", Some(&out));
    fails(
        &["optimize", g, "-o", s(&dir.join("out.stl"))],
        1,
        "out.stl: unknown mesh format",
        Some(&dir.join("out.stl")),
    );
    let penta = dir.join("penta.off");
    std::fs::write(&penta, "OFF\n5 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 0 0\n4 0 1 2 3\n5 0 4 1 2 3\n")
        .unwrap();
    fails(
        &["optimize", s(&penta), "-o", o],
        1,
        "penta.off: line 9: cell 1 is a polygon with 5 vertices; only triangles and quads",
        Some(&out),
    );
    // On a curved surface too: three faces on one edge.
    let fin = dir.join("fin.obj");
    std::fs::write(
        &fin,
        "v 0 0 0\nv 1 0 0\nv 1 1 1\nv 0 1 0\nv 2 0 0\nv 2 1 0\nv 1 1 -1\nf 1 2 3 4\nf 2 5 6 3\nf 2 3 7\n",
    )
    .unwrap();
    fails(&["optimize", s(&fin), "-o", o], 1, "fin.obj: ", Some(&out));
    fails(
        &["optimize", g, "-o", o, "--feature-edges", s(&fin)],
        2,
        "apply to meshes on curved surfaces",
        Some(&out),
    );
    let trunc = dir.join("trunc.vtk");
    let text = io::write_mesh_string(io::Format::Vtk, &jittered_grid(3)).unwrap();
    std::fs::write(&trunc, &text[..text.len() / 2]).unwrap();
    fails(&["optimize", s(&trunc), "-o", o], 1, "unexpected end of file", Some(&out));
    let bowtie = dir.join("nonmanifold.obj");
    std::fs::write(&bowtie, "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\nv 1 2 0\nv 0 2 0\nf 1 2 3 4\nf 2 5 6 3\nf 2 3 7 8\n").unwrap();
    fails(&["optimize", s(&bowtie), "-o", o], 1, "non-manifold", Some(&out));
    // A closed mesh: a 6 x 6 grid whose quads wrap around (every vertex interior).
    let torus = dir.join("torus.obj");
    let mut text = String::new();
    for v in 0..36 {
        text += &format!("v {} {} 0\n", v % 6, v / 6);
    }
    for (i, j) in (0..36).map(|c| (c % 6, c / 6)) {
        let id = |i: usize, j: usize| (j % 6) * 6 + i % 6 + 1;
        text += &format!("f {} {} {} {}\n", id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
    }
    std::fs::write(&torus, text).unwrap();
    let closed = "torus.obj: the mesh is closed (it has no boundary edge): a closed surface cannot lie flat";
    fails(&["optimize", s(&torus), "-o", o], 1, closed, Some(&out));
    fails(&["quality", s(&torus)], 1, closed, None);
    fails(&["optimize", g, "-o", o, "--lambda", "2"], 2, "invalid option lambda", Some(&out));
    fails(&["optimize", g, "-o", o, "--tau", "-1"], 2, "invalid option tau", Some(&out));
    fails(&["optimize", g, "-o", o, "--method", "simplex"], 2, "unknown method 'simplex'", Some(&out));
    fails(&["optimize", g, "-o", o, "--boundary", "free"], 2, "unknown boundary mode 'free'", Some(&out));
    fails(&["optimize", g], 2, "--output", Some(&out));
    fails(&["quality", s(&dir.join("nope.msh"))], 1, "nope.msh", None);
    // An output in a missing directory fails after the work, leaving nothing.
    let deep = dir.join("no/such/out.obj");
    fails(&["optimize", g, "-o", s(&deep)], 1, &format!("cannot write {}: No such file", s(&deep)), None);
    let err = String::from_utf8(quadopt(&["optimize", g, "-o", s(&deep)]).stderr).unwrap();
    assert!(!err.contains(".quadopt-"), "the temporary file is named: {err}");
    // A directory, as input or output, is named as one (it has no known extension either).
    fails(
        &["optimize", s(&dir), "-o", o],
        1,
        &format!("cannot read {}: it is a directory", s(&dir)),
        Some(&out),
    );
    fails(&["quality", s(&dir)], 1, "it is a directory", None);
    fails(&["optimize", g, "-o", s(&dir)], 1, &format!("cannot write {}: it is a directory", s(&dir)), None);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn quality_text_has_a_histogram() {
    let dir = scratch("quality");
    let input = dir.join("grid.msh");
    io::write_mesh(&input, &jittered_grid(4)).unwrap();
    let out = quadopt(&["quality", s(&input)]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("16 quads") && text.contains("<= 0.0") && text.contains("(0.9, 1.0]"), "{text}");
    let v = json_stdout(&quadopt(&["quality", s(&input), "--json"]));
    stats_keys(&v);
    let h: u64 = v["histogram"].as_array().unwrap().iter().map(|x| x.as_u64().unwrap()).sum();
    assert_eq!(h, 16);
    assert_eq!(v["histogram"][0], v["inverted"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn compare_runs_every_method() {
    let dir = scratch("compare");
    let (a, b) = (dir.join("a.obj"), dir.join("b.vtk"));
    io::write_mesh(&a, &jittered_grid(4)).unwrap();
    io::write_mesh(&b, &jittered_grid(5)).unwrap();
    let v = json_stdout(&quadopt(&["compare", s(&a), s(&b), "--json"]));
    let meshes = v["meshes"].as_array().unwrap();
    assert_eq!(meshes.len(), 2);
    let runs: Vec<(String, String)> = meshes[1]["results"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| {
            stats_keys(&r["output"]);
            (r["method"].as_str().unwrap().into(), r["boundary"].as_str().unwrap().into())
        })
        .collect();
    let want = [
        ("angle", "fixed"),
        ("laplace", "fixed"),
        ("cotan", "fixed"),
        ("ep", "fixed"),
        ("ep", "slide"),
        ("ep", "snap"),
        ("ep", "auto"),
    ];
    assert_eq!(runs, want.map(|(m, b)| (m.to_string(), b.to_string())));
    assert_eq!(meshes[0]["quads"], 16);
    let text = String::from_utf8(quadopt(&["compare", s(&a), s(&b)]).stdout).unwrap();
    assert!(text.contains("ep/snap") && text.contains("a.obj") && text.contains("b.vtk"), "{text}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn draw_writes_a_coloured_svg() {
    let dir = scratch("draw");
    let input = dir.join("grid.obj");
    io::write_mesh(&input, &jittered_grid(4)).unwrap();
    let svg = dir.join("grid.svg");
    assert!(quadopt(&["draw", s(&input), "-o", s(&svg)]).status.success());
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.starts_with("<svg") && text.trim_end().ends_with("</svg>"));
    // One path per quad (the marks of inverted quads are paths of class "inverted").
    assert_eq!(text.matches("<path d=").count(), 16);
    assert!(text.contains("linearGradient") && text.contains(">scaled<") && text.contains(">Jacobian<"));
    // The quads' fills (not the legend's).
    let fills = |text: &str| -> Vec<String> {
        text.split("<path d=").skip(1).map(|p| p.split("fill=\"#").nth(1).unwrap()[..6].to_string()).collect()
    };
    // The jitter inverts quads: some fill is a dark red (green and blue 0, red below 255).
    assert!(fills(&text).iter().any(|t| &t[2..6] == "0000" && &t[..2] != "ff"), "no inverted quad drawn");
    let opt = dir.join("opt.svg");
    assert!(
        quadopt(&["draw", s(&input), "-o", s(&opt), "--optimized", "--boundary", "fixed"]).status.success()
    );
    let text = std::fs::read_to_string(&opt).unwrap();
    assert!(text.contains("optimized (ep, fixed)"));
    assert!(!fills(&text).iter().any(|t| &t[2..6] == "0000" && &t[..2] != "ff"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn no_arguments_reports_on_the_bundled_meshes() {
    let out = quadopt(&[]);
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("data");
    let has_meshes = std::fs::read_dir(&data)
        .map(|d| d.filter_map(|e| e.ok()).any(|e| io::Format::from_path(&e.path()).is_ok()))
        .unwrap_or(false);
    let stdout = String::from_utf8(out.stdout).unwrap();
    if has_meshes {
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        assert!(stdout.contains("model") && stdout.contains("output min/avg/max"), "{stdout}");
    } else {
        assert_eq!(out.status.code(), Some(1));
        assert!(String::from_utf8(out.stderr).unwrap().contains("no sample meshes"));
    }
}

#[test]
fn reports_name_paths_as_the_user_gave_them() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let run = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_quadopt")).args(args).current_dir(root).output().unwrap()
    };
    let absolute = root.to_str().unwrap();
    // The sample report run from the project's root (as the README shows it) names `data`.
    let out = run(&[]);
    let stdout = String::from_utf8(out.stdout).unwrap();
    assert!(stdout.starts_with("quadopt: 19 meshes in data, "), "{stdout}");
    assert!(!stdout.contains(absolute), "{stdout}");
    // Relative input and output paths stay relative in text and JSON reports.
    let target = std::env::temp_dir().join(format!("quadopt-paths-{}.vtk", std::process::id()));
    let v = json_stdout(&run(&["optimize", "data/plate_1hole.vtk", "-o", s(&target), "--json"]));
    assert_eq!(v["input_file"], "data/plate_1hole.vtk");
    assert_eq!(v["output_file"], s(&target));
    let v = json_stdout(&run(&["quality", "./data/plate_1hole.vtk", "--json"]));
    assert_eq!(v["file"], "./data/plate_1hole.vtk");
    let text =
        String::from_utf8(run(&["optimize", "data/plate_1hole.vtk", "-o", s(&target)]).stdout).unwrap();
    assert!(text.starts_with("data/plate_1hole.vtk: 70 vertices"), "{text}");
    assert!(!text.contains(absolute), "{text}");
    std::fs::remove_file(&target).unwrap();
}

#[test]
fn generate_writes_the_requested_synthetic_mesh() {
    let dir = scratch("generate");
    let path = dir.join("grid.obj");
    let out =
        quadopt(&["generate", "-o", s(&path), "--nx", "30", "--ny", "20", "--holes", "0", "--jitter", "0"]);
    assert!(out.status.success(), "stderr: {}", String::from_utf8_lossy(&out.stderr));
    let mesh = io::read_mesh(&path).unwrap();
    assert_eq!(mesh.points.len(), 31 * 21);
    assert_eq!(mesh.quads.len(), 600);
    // Quality of an unperturbed grid, as the quality command sees it.
    let q = json_stdout(&quadopt(&["quality", s(&path), "--json"]));
    assert_eq!(q["min"].as_f64(), Some(1.0));

    // --quads sizes the grid; holes and jitter make it worth optimizing.
    let path = dir.join("holes.vtk");
    assert!(quadopt(&["generate", "-o", s(&path), "--quads", "5000", "--jitter", "0.45"]).status.success());
    let q = json_stdout(&quadopt(&["quality", s(&path), "--json"]));
    let quads = q["quads"].as_u64().unwrap();
    assert!((4750..=5250).contains(&quads), "{quads} quads");
    assert!(q["inverted"].as_u64().unwrap() > 0);

    // Bad parameters are usage errors and write nothing.
    let bad = dir.join("bad.vtk");
    let out = quadopt(&["generate", "-o", s(&bad), "--hole-size", "1.5"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--hole-size"));
    assert!(!bad.exists());
    // So are more holes than the grid has room for (checked before allocating anything for
    // them: 2^32 - 1 hole centres would take 64 GiB).
    for (args, needle) in [
        (&["--quads", "1000", "--holes", "4294967295"][..], "4294967295 holes do not fit in a 35 x 35 grid"),
        (&["--nx", "3", "--ny", "50", "--holes", "10"][..], "(at most 9 holes, on a 3 x 3 lattice)"),
    ] {
        let out = quadopt(&[&["generate", "-o", s(&bad)][..], args].concat());
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.starts_with("quadopt: error: --holes: ") && err.contains(needle), "{args:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(!bad.exists());
    }
    let out = quadopt(&["generate", "-o", s(&bad), "--nx", "3", "--ny", "50", "--holes", "9"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
}

#[test]
fn a_closed_stdout_ends_the_output_quietly() {
    // `quadopt compare ... | head -1`: the reader goes away before the table is written.
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("data");
    let mut child = Command::new(env!("CARGO_BIN_EXE_quadopt"))
        .args(["compare", s(&data.join("plate_1hole.vtk")), s(&data.join("plate_2holes.vtk"))])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(out.status.code(), Some(0), "{stderr}");
}

#[test]
fn usage_errors_are_one_line_with_the_prefix() {
    let dir = scratch("usage");
    let good = dir.join("good.obj");
    io::write_mesh(&good, &jittered_grid(3)).unwrap();
    let g = s(&good);
    let cases: [(&[&str], &str); 8] = [
        (
            &["optimise", g],
            "unrecognized subcommand 'optimise'; tip: a similar subcommand exists: 'optimize'",
        ),
        (
            &["optimize", g],
            "the following required arguments were not provided: --output <OUTPUT> (see 'quadopt optimize --help')",
        ),
        (&["optimize", g, "-o", "x.vtk", "--bogus"], "unexpected argument '--bogus'"),
        (&["optimize", g, "-o", "x.vtk", "--max-iter", "many"], "invalid value 'many' for '--max-iter"),
        (&["optimize", g, "-o", "x.vtk", "--format", "stl"], "unknown mesh format 'stl'"),
        (&["--threads", "0", "quality", g], "'0' is not a number of threads"),
        (&["compare"], "required arguments were not provided"),
        (&["--bogus"], "unexpected argument '--bogus' found (see 'quadopt --help')"),
    ];
    for (args, needle) in cases {
        let out = quadopt(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8(out.stderr).unwrap();
        assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
        assert!(err.starts_with("quadopt: error: ") && err.contains(needle), "{args:?}: {err}");
        assert!(out.stdout.is_empty());
    }
    // Help and version are not errors.
    let out = quadopt(&["--help"]);
    assert_eq!(out.status.code(), Some(0));
    assert!(String::from_utf8(out.stdout).unwrap().contains("--threads"));
    let out = quadopt(&["--version"]);
    assert_eq!(out.status.code(), Some(0));
    assert!(String::from_utf8(out.stdout).unwrap().starts_with("quadopt "));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `--help` offers what the build does: every input format, and `--reader` (which only
/// `openmesh` makes useful) only in a build with OpenMesh, which the version line names.
#[test]
fn help_lists_what_this_build_reads() {
    let text = |args: &[&str]| String::from_utf8(quadopt(args).stdout).unwrap();
    let optimize = text(&["optimize", "--help"]);
    assert!(optimize.contains("Input mesh (.obj, .off, .vtk, .msh, .vtu"), "{optimize}");
    let with_openmesh = text(&["--version"]).contains("(OpenMesh support:");
    assert_eq!(with_openmesh, cfg!(feature = "openmesh"));
    for help in [text(&["--help"]), optimize.clone(), text(&["quality", "--help"])] {
        assert_eq!(help.contains("--reader"), with_openmesh, "{help}");
    }
    assert_eq!(optimize.contains(".ply and .om"), with_openmesh, "{optimize}");
    if !with_openmesh {
        // Hidden, not removed: asked for, it says why it is refused.
        let out = quadopt(&["--reader", "openmesh", "quality", "x.obj"]);
        assert_eq!(out.status.code(), Some(2));
        assert!(String::from_utf8_lossy(&out.stderr).contains("built without OpenMesh support"));
    }
}

/// A file `name` in `dir` with `bytes`.
fn file_with(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

/// Messages number quads and vertices from 0 and say so (files number their lines, and OBJ its
/// vertices, from 1).
#[test]
fn messages_say_that_they_number_from_0() {
    let dir = scratch("numbers");
    let out = dir.join("out.vtk");
    let o = s(&out);
    let write = |name: &str, text: &[u8]| file_with(&dir, name, text);
    let repeated = write("repeated.obj", b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 2 4\n");
    fails(
        &["optimize", s(&repeated), "-o", o],
        1,
        "repeated.obj: quad 0 uses vertex 1 more than once (quad and vertex numbers are 0-based)",
        Some(&out),
    );
    let nan = write("nan.obj", b"v 0 0 0\nv 1 0 0\nv nan 1 0\nv 0 1 0\nf 1 2 3 4\n");
    fails(
        &["quality", s(&nan)],
        1,
        "nan.obj: vertex 2 has a non-finite coordinate (vertex numbers are 0-based)",
        None,
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Bytes that are not OBJ, in a file named .obj, say so (not that the mesh has no quads).
#[test]
fn bytes_that_are_not_obj_say_so() {
    let dir = scratch("not-obj");
    let out = dir.join("out.vtk");
    let o = s(&out);
    let write = |name: &str, text: &[u8]| file_with(&dir, name, text);
    // A PNG's first bytes in a .obj: nothing in it is an OBJ statement.
    let binary = write("picture.obj", b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR\0\0\x01\0\xff\xfe\n\x07\x08");
    fails(
        &["optimize", s(&binary), "-o", o],
        1,
        "picture.obj: nothing in the file parsed as OBJ geometry: it has no vertex (v) or face (f) statement",
        Some(&out),
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Counts of one are singular: "1 quad", "1 iteration", "1 movable vertex".
#[test]
fn counts_of_one_are_singular() {
    let dir = scratch("singular");
    let out = dir.join("out.vtk");
    let o = s(&out);
    let write = |name: &str, text: &[u8]| file_with(&dir, name, text);
    // One quad; one iteration, one movable vertex: singular.
    let one = write("one.obj", b"v 0 0 0\nv 2 0 0\nv 2 2 0\nv 0 2 0\nv 9 9 0\nf 1 2 3 4\n");
    let text = String::from_utf8(quadopt(&["quality", s(&one)]).stdout).unwrap();
    assert!(text.starts_with(&format!("{}: 5 vertices, 1 quad\n", s(&one))), "{text}");
    let patch = write(
        "patch.obj",
        b"v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1.6 1.5 0\nv 2 1 0\nv 0 2 0\nv 1 2 0\nv 2 2 0\n\
          f 1 2 5 4\nf 2 3 6 5\nf 4 5 8 7\nf 5 6 9 8\n",
    );
    let run = quadopt(&["optimize", s(&patch), "-o", o, "--boundary", "fixed", "--max-iter", "1"]);
    let text = String::from_utf8(run.stdout).unwrap();
    assert!(text.starts_with(&format!("{}: 9 vertices, 4 quads\n", s(&patch))), "{text}");
    assert!(text.contains("\n1 iteration ("), "{text}");
    assert!(text.contains("; 4 corners, 1 movable vertex, 1 moved, 0 quads reoriented\n"), "{text}");
    let grid = dir.join("grid.obj");
    let out = quadopt(&["generate", "-o", s(&grid), "--nx", "1", "--ny", "1", "--holes", "0"]);
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.starts_with(&format!("wrote {}: 4 vertices, 1 quad;", s(&grid))), "{text}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn threads_give_bit_identical_files_and_no_progress_without_a_terminal() {
    let dir = scratch("threads");
    let input = dir.join("holes.vtk");
    let out = quadopt(&["generate", "-o", s(&input), "--quads", "3000", "--jitter", "0.45"]);
    assert!(out.status.success());
    let mut files = Vec::new();
    for threads in ["1", "2", "3"] {
        let output = dir.join(format!("out{threads}.vtk"));
        let out = quadopt(&["--threads", threads, "optimize", s(&input), "-o", s(&output)]);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        // Not a terminal: no progress bar, nothing at all on stderr.
        assert!(out.stderr.is_empty(), "stderr: {}", String::from_utf8_lossy(&out.stderr));
        files.push(std::fs::read(&output).unwrap());
    }
    assert!(files[0] != std::fs::read(&input).unwrap(), "the mesh was optimized");
    assert!(files[1] == files[0] && files[2] == files[0], "outputs differ between thread counts");
    // The option also goes after the subcommand.
    let output = dir.join("after.vtk");
    let out = quadopt(&["optimize", s(&input), "-o", s(&output), "--threads", "2", "--json"]);
    assert!(out.status.success() && out.stderr.is_empty());
    assert!(std::fs::read(&output).unwrap() == files[0]);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Runs `quadopt ARGS` on a pseudo-terminal (util-linux `script`), returning the terminal's
/// output once `until` appears in it (then ending the run) or the run ends; `None` without
/// `script`.
fn on_a_terminal(args: &[&str], until: &str) -> Option<String> {
    use std::io::Read;
    let command = std::iter::once(env!("CARGO_BIN_EXE_quadopt"))
        .chain(args.iter().copied())
        .map(|a| format!("'{a}'"))
        .collect::<Vec<_>>()
        .join(" ");
    let mut child = Command::new("script")
        .args(["-qec", &command, "/dev/null"])
        .stdin(std::process::Stdio::null())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::null())
        .spawn()
        .ok()?;
    let mut stdout = child.stdout.take()?;
    let mut seen = Vec::new();
    let mut buf = [0u8; 4096];
    loop {
        match stdout.read(&mut buf) {
            Ok(0) | Err(_) => break,
            Ok(k) => seen.extend_from_slice(&buf[..k]),
        }
        if String::from_utf8_lossy(&seen).contains(until) {
            let _ = child.kill();
            break;
        }
    }
    let _ = child.wait();
    Some(String::from_utf8_lossy(&seen).into_owned())
}

#[test]
fn a_long_run_on_a_terminal_draws_a_progress_bar_but_not_with_json() {
    if Command::new("script").arg("--version").output().is_err() {
        return; // no util-linux script
    }
    let dir = scratch("progress");
    let input = dir.join("holes.vtk");
    assert!(quadopt(&["generate", "-o", s(&input), "--quads", "20000", "--jitter", "0.45"]).status.success());
    // tau 0 never converges: the run lasts until the bar is seen (and is then ended).
    let out = dir.join("out.vtk");
    let long =
        ["optimize", s(&input), "-o", s(&out), "--boundary", "fixed", "--tau", "0", "--max-iter", "1000000"];
    let Some(text) = on_a_terminal(&long, "sweeps") else { return };
    assert!(text.contains("pass 1/1 [") && text.contains("/1000000 sweeps"), "{text}");
    // With --json, a run long enough for the bar shows none; the JSON line is all there is.
    let short = [
        "optimize",
        s(&input),
        "-o",
        s(&out),
        "--boundary",
        "fixed",
        "--tau",
        "0",
        "--max-iter",
        "150",
        "--json",
    ];
    let text = on_a_terminal(&short, "\u{0}").unwrap();
    assert!(!text.contains("/150 sweeps") && !text.contains("pass 1/1"), "{text}");
    let v: Value = serde_json::from_str(text.trim()).unwrap();
    assert_eq!(v["iterations"].as_u64(), Some(150), "{v}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_max_min_stage_and_the_stopping_rule_are_chosen_on_the_command_line() {
    let dir = scratch("maxmin");
    let input = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/plate_2holes.vtk");
    let output = dir.join("out.vtk");
    let run = |extra: &[&str]| {
        let mut args = vec!["optimize", s(&input), "-o", s(&output), "--json"];
        args.extend_from_slice(extra);
        json_stdout(&quadopt(&args))
    };
    let default = run(&[]);
    let stage = &default["max_min"];
    let (before, after) = (stage["before"]["min"].as_f64().unwrap(), stage["after"]["min"].as_f64().unwrap());
    assert!(after > before + 0.01, "the stage raises this mesh's minimum: {stage}");
    // The stage measures on the normalized coordinates, rounded to a grid of 2^-21 of the
    // shortest edge; the output on the returned ones.
    let output_min = default["output"]["min"].as_f64().unwrap();
    assert!((output_min - after).abs() < 1e-6, "the output is the stage's: {output_min} vs {after}");
    let without = run(&["--no-maxmin"]);
    assert!(without["max_min"].is_null(), "{without}");
    assert!(without["output"]["min"].as_f64().unwrap() < after, "the stage's gain: {without}");
    // The quality rule (the default) stops after fewer sweeps than the energy rule on this
    // mesh; --tau asks for the energy rule.
    let energy = run(&["--stop", "energy", "--no-maxmin"]);
    let (q, e) = (without["iterations"].as_u64().unwrap(), energy["iterations"].as_u64().unwrap());
    assert!(q < e, "quality rule {q} sweeps, energy rule {e}");
    let tau = run(&["--tau", "1e-7", "--no-maxmin"]);
    assert_eq!(tau["iterations"], energy["iterations"], "--tau implies --stop energy");
    fails(&["optimize", s(&input), "-o", s(&output), "--stop", "never"], 2, "unknown stopping rule", None);
}

/// The `count` values after the line `header` of `text` (a VTK `SCALARS` block after its
/// `LOOKUP_TABLE` line, or an MSH view's `tag value` lines after its tags), as written.
fn array_after(text: &str, header: &str, skip: usize, count: usize) -> Vec<String> {
    let start = text.find(header).unwrap_or_else(|| panic!("no {header:?} in the file"));
    let lines = text[start..].lines().skip(1 + skip).take(count);
    lines.map(|l| l.split_whitespace().last().unwrap().to_string()).collect()
}

#[test]
fn outputs_carry_the_quality_and_the_fixed_and_corner_flags() {
    let dir = scratch("annotated");
    let mut mesh = jittered_grid(6);
    let n = mesh.points.len();
    let fixed: Vec<bool> = (0..n).map(|i| i == 8 || i == 24).collect();
    mesh.fixed = Some(fixed.clone());
    let input = dir.join("in.vtk");
    io::write_mesh(&input, &mesh).unwrap();
    // The grid's four corners are its only corners (a square's boundary turns nowhere else).
    let corners: Vec<bool> = (0..n).map(|i| [0, 6, 42, 48].contains(&i)).collect();
    let flag = |f: &[bool]| f.iter().map(|&b| u8::from(b).to_string()).collect::<Vec<_>>();
    for ext in ["vtk", "msh"] {
        let output = dir.join(format!("out.{ext}"));
        let out = quadopt(&["optimize", s(&input), "-o", s(&output)]);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let text = std::fs::read_to_string(&output).unwrap();
        // The per-quad values are the signed scaled Jacobians of the written coordinates,
        // bit for bit (shortest round-trip formatting).
        let back = io::read_mesh(&output).unwrap();
        let planar = io::PlanarMesh::new(&back).unwrap();
        let expected: Vec<String> = planar.mesh.quality_values().iter().map(|v| format!("{v:?}")).collect();
        let m = back.quads.len();
        let (quality, fixed_read, corner_read) = if ext == "vtk" {
            (
                array_after(&text, "SCALARS scaled_jacobian double 1", 1, m),
                array_after(&text, "SCALARS fixed int 1", 1, n),
                array_after(&text, "SCALARS corner int 1", 1, n),
            )
        } else {
            // A view: its name, one real tag, three integer tags, then `tag value` lines.
            (
                array_after(&text, "\"scaled_jacobian\"", 6, m),
                array_after(&text, "\"fixed\"", 6, n),
                array_after(&text, "\"corner\"", 6, n),
            )
        };
        assert_eq!(quality, expected, "{ext}: scaled_jacobian");
        assert_eq!(fixed_read, flag(&fixed), "{ext}: fixed");
        assert_eq!(corner_read, flag(&corners), "{ext}: corner");
        // The readers skip the arrays they do not use and keep reading `fixed` (VTK).
        assert_eq!(back.quads, mesh.quads);
        if ext == "vtk" {
            assert_eq!(back.fixed.as_ref(), Some(&fixed));
        }
    }
    // `quality IN -o OUT` writes the input's values, with the mesh unchanged.
    let output = dir.join("quality.vtk");
    let out = quadopt(&["quality", s(&input), "-o", s(&output)]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = std::fs::read_to_string(&output).unwrap();
    let planar = io::PlanarMesh::new(&mesh).unwrap();
    let expected: Vec<String> = planar.mesh.quality_values().iter().map(|v| format!("{v:?}")).collect();
    assert!(expected.iter().any(|v| v.starts_with('-')), "the input has inverted quads, written signed");
    assert_eq!(array_after(&text, "SCALARS scaled_jacobian double 1", 1, mesh.quads.len()), expected);
    let back = io::read_mesh(&output).unwrap();
    assert_eq!(
        back.points.iter().map(|p| p.map(f64::to_bits)).collect::<Vec<_>>(),
        mesh.points.iter().map(|p| p.map(f64::to_bits)).collect::<Vec<_>>()
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn vtu_outputs_follow_encoding_and_zlib_and_match_the_vtk_output() {
    let dir = scratch("vtu");
    let mut mesh = jittered_grid(6);
    let n = mesh.points.len();
    mesh.fixed = Some((0..n).map(|i| i == 8 || i == 24).collect());
    let input = dir.join("in.vtk");
    io::write_mesh(&input, &mesh).unwrap();
    let reference = dir.join("out.vtk");
    assert!(quadopt(&["optimize", s(&input), "-o", s(&reference)]).status.success());
    let want = io::read_mesh(&reference).unwrap();
    let bits = |d: &MeshData| d.points.iter().map(|p| p.map(f64::to_bits)).collect::<Vec<_>>();
    let cases: [(&[&str], &str, bool); 4] = [
        (&[], r#"format="ascii""#, false),
        (&["--encoding", "binary"], r#"format="binary""#, false),
        (&["--encoding", "appended", "--zlib"], r#"<AppendedData encoding="raw">"#, true),
        (&["--encoding", "binary", "--zlib"], r#"format="binary""#, true),
    ];
    for (extra, marker, zlib) in cases {
        let output = dir.join("out.vtu");
        let mut args = vec!["optimize", s(&input), "-o", s(&output)];
        args.extend_from_slice(extra);
        let out = quadopt(&args);
        assert!(out.status.success(), "{extra:?}: {}", String::from_utf8_lossy(&out.stderr));
        let bytes = std::fs::read(&output).unwrap();
        let text = String::from_utf8_lossy(&bytes);
        assert!(text.contains(marker), "{extra:?}");
        assert_eq!(text.contains("vtkZLibDataCompressor"), zlib, "{extra:?}");
        assert!(text.contains(r#"Name="scaled_jacobian""#) && text.contains(r#"Name="corner""#));
        let got = io::read_mesh(&output).unwrap();
        assert_eq!(bits(&got), bits(&want), "{extra:?}: the same coordinates as the VTK output");
        assert_eq!(got.quads, want.quads);
        assert_eq!(got.fixed, mesh.fixed, "{extra:?}: fixed flags");
        // A VTU input is written back in its own encoding: optimizing the output again
        // (an idempotent no-op or not) keeps appended + zlib.
        let again = dir.join("again.vtu");
        assert!(quadopt(&["optimize", s(&output), "-o", s(&again)]).status.success());
        let back = io::read_mesh(&again).unwrap();
        assert_eq!((back.encoding, back.compressed), (got.encoding, got.compressed), "{extra:?}");
    }
    fails(
        &["optimize", s(&input), "-o", s(&dir.join("x.vtu")), "--encoding", "hex"],
        2,
        "unknown encoding 'hex' (expected ascii, binary or appended)",
        Some(&dir.join("x.vtu")),
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn fix_physical_pins_exactly_the_nodes_of_the_named_groups() {
    let dir = scratch("physical");
    let input = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/msh/plate_v41_binary.msh");
    let data = io::read_mesh(&input).unwrap();
    let group = |name: &str| data.physical_groups.iter().find(|g| g.name == name).unwrap().nodes.clone();
    let (wall, hole, corner) = (group("wall"), group("hole"), group("corner"));
    let run = |args: &[&str], name: &str| {
        let output = dir.join(name);
        let mut all = vec!["optimize", s(&input), "-o", s(&output)];
        all.extend_from_slice(args);
        let out = quadopt(&all);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        io::read_mesh(&output).unwrap()
    };
    let moved = |out: &MeshData, nodes: &[u32]| {
        nodes.iter().filter(|&&v| out.points[v as usize] != data.points[v as usize]).count()
    };
    // Without the option the wall's and the hole's nodes move (they slide or snap) ...
    let free = run(&[], "free.msh");
    assert!(moved(&free, &wall) > 5 && moved(&free, &hole) > 5);
    // ... with it they keep their coordinates bit for bit, and the written `fixed` flags
    // are exactly the groups' nodes.
    let pinned = run(&["--fix-physical", "wall", "--fix-physical", "corner"], "pinned.msh");
    assert_eq!(moved(&pinned, &wall), 0);
    assert!(moved(&pinned, &hole) > 5, "only the named groups are pinned");
    let want: Vec<bool> =
        (0..data.points.len() as u32).map(|v| wall.contains(&v) || corner.contains(&v)).collect();
    assert_eq!(pinned.fixed, Some(want));
    for (a, b) in wall.iter().map(|&v| (pinned.points[v as usize], data.points[v as usize])) {
        assert_eq!(a.map(f64::to_bits), b.map(f64::to_bits));
    }
    // Binary in, binary out.
    assert_eq!(pinned.encoding, io::Encoding::Binary);
    // An unknown name lists the names there are; a file without groups says so.
    let out_path = dir.join("x.msh");
    fails(
        &["optimize", s(&input), "-o", s(&out_path), "--fix-physical", "inlet"],
        1,
        "--fix-physical inlet: no physical point or curve of that name (the file has: corner, wall, hole)",
        Some(&out_path),
    );
    let vtk = dir.join("grid.vtk");
    io::write_mesh(&vtk, &jittered_grid(3)).unwrap();
    fails(
        &["optimize", s(&vtk), "-o", s(&out_path), "--fix-physical", "wall"],
        1,
        "(the file has none)",
        Some(&out_path),
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

// Quad-dominant meshes (quads and triangles) through every command.

/// A unit square (quad 0) with an equilateral triangle on its right edge (scaled Jacobian 1)
/// and a right isosceles triangle on its top edge (sin 45 degrees * 2 / sqrt(3) = sqrt(2/3)),
/// as OBJ text; with `fold`, the equilateral triangle's apex is pulled into the square, which
/// inverts that triangle.
fn square_and_two_triangles(fold: bool) -> String {
    let apex = if fold { "0.5 0.5".to_string() } else { format!("{} 0.5", 1.0 + 3f64.sqrt() / 2.0) };
    format!("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv {apex} 0\nv 0 2 0\nf 1 2 3 4\nf 2 5 3\nf 4 3 6\n")
}

/// The right isosceles triangle's scaled Jacobian.
fn right_isosceles() -> f64 {
    (2.0f64 / 3.0).sqrt()
}

fn close(v: &Value, want: f64) -> bool {
    v.as_f64().is_some_and(|x| (x - want).abs() < 1e-12)
}

#[test]
fn quality_reports_each_face_kind_of_a_mixed_mesh() {
    let dir = scratch("mixed-quality");
    let input = file_with(&dir, "mixed.obj", square_and_two_triangles(false).as_bytes());
    let v = json_stdout(&quadopt(&["quality", s(&input), "--json"]));
    let t = right_isosceles();
    assert_eq!(
        (v["faces"].as_u64(), v["quads"].as_u64(), v["triangles"].as_u64()),
        (Some(3), Some(1), Some(2))
    );
    assert!(close(&v["min"], t) && close(&v["avg"], (2.0 + t) / 3.0) && close(&v["max"], 1.0), "{v}");
    let quads = &v["by_kind"]["quads"];
    assert_eq!((quads["count"].as_u64(), quads["inverted"].as_u64()), (Some(1), Some(0)));
    assert!(close(&quads["min"], 1.0) && close(&quads["avg"], 1.0) && close(&quads["max"], 1.0), "{v}");
    let triangles = &v["by_kind"]["triangles"];
    assert_eq!((triangles["count"].as_u64(), triangles["inverted"].as_u64()), (Some(2), Some(0)));
    assert!(close(&triangles["min"], t) && close(&triangles["avg"], (1.0 + t) / 2.0), "{v}");
    assert!(close(&triangles["max"], 1.0), "{v}");
    // The histogram counts every face: sqrt(2/3) = 0.816 in (0.8, 0.9], the others in (0.9, 1].
    assert_eq!(v["histogram"], serde_json::json!([0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 2]));

    let out = quadopt(&["quality", s(&input)]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("6 vertices, 3 faces (1 quad, 2 triangles)"), "{text}");
    assert!(text.contains("scaled Jacobian: min 0.8165, avg 0.9388, max 1.0000; 0 inverted"), "{text}");
    assert!(text.contains("  quads           1: min 1.0000, avg 1.0000, max 1.0000; 0 inverted"), "{text}");
    assert!(text.contains("  triangles       2: min 0.8165, avg 0.9082, max 1.0000; 0 inverted"), "{text}");

    // A quad mesh has no per-kind key and no per-kind line, and says "quads".
    let grid = dir.join("grid.obj");
    io::write_mesh(&grid, &jittered_grid(4)).unwrap();
    let v = json_stdout(&quadopt(&["quality", s(&grid), "--json"]));
    for key in ["faces", "triangles", "by_kind"] {
        assert!(v.get(key).is_none(), "{key} in {v}");
    }
    assert_eq!(v["quads"].as_u64(), Some(16));
    let text = String::from_utf8(quadopt(&["quality", s(&grid)]).stdout).unwrap();
    assert!(text.contains(": 25 vertices, 16 quads\n") && !text.contains("triangles"), "{text}");

    // An inverted triangle is counted as inverted, in its kind and overall.
    let folded = file_with(&dir, "folded.obj", square_and_two_triangles(true).as_bytes());
    let v = json_stdout(&quadopt(&["quality", s(&folded), "--json"]));
    assert_eq!(v["inverted"].as_u64(), Some(1), "{v}");
    assert_eq!(v["by_kind"]["triangles"]["inverted"].as_u64(), Some(1), "{v}");
    assert_eq!(v["by_kind"]["quads"]["inverted"].as_u64(), Some(0), "{v}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A 4 x 4 grid with its interior jittered, every other cell of its first row split into two
/// triangles: a mixed mesh worth optimizing.
fn jittered_mixed_grid() -> String {
    let mesh = jittered_grid(4);
    let mut text = String::new();
    for p in &mesh.points {
        text += &format!("v {} {} {}\n", p[0], p[1], p[2]);
    }
    for (i, q) in mesh.quads.iter().enumerate() {
        let [a, b, c, d] = q.map(|v| v + 1);
        if i < 4 && i % 2 == 0 {
            text += &format!("f {a} {b} {c}\nf {a} {c} {d}\n");
        } else {
            text += &format!("f {a} {b} {c} {d}\n");
        }
    }
    text
}

#[test]
fn optimize_and_compare_report_each_face_kind_of_a_mixed_mesh() {
    let dir = scratch("mixed-optimize");
    let input = file_with(&dir, "mixed.obj", jittered_mixed_grid().as_bytes());
    let output = dir.join("out.vtk");
    let before = json_stdout(&quadopt(&["quality", s(&input), "--json"]));
    assert_eq!((before["quads"].as_u64(), before["triangles"].as_u64()), (Some(14), Some(4)));
    let v =
        json_stdout(&quadopt(&["optimize", s(&input), "-o", s(&output), "--boundary", "fixed", "--json"]));
    assert_eq!(
        (v["faces"].as_u64(), v["quads"].as_u64(), v["triangles"].as_u64()),
        (Some(18), Some(14), Some(4))
    );
    // The input's statistics per kind are those `quality` measures; the output's those of the
    // file written.
    assert_eq!(v["input_by_kind"], before["by_kind"]);
    let after = json_stdout(&quadopt(&["quality", s(&output), "--json"]));
    assert_eq!(v["output_by_kind"], after["by_kind"]);
    assert_eq!(after["triangles"].as_u64(), Some(4));
    for kind in ["quads", "triangles"] {
        let (i, o) = (&v["input_by_kind"][kind], &v["output_by_kind"][kind]);
        assert!(o["inverted"].as_u64() <= i["inverted"].as_u64(), "{kind}: {v}");
    }
    assert!(v["input"]["inverted"].as_u64().unwrap() > 0, "{v}");
    assert_eq!(v["output"]["inverted"].as_u64(), Some(0), "{v}");

    // The text report: the face counts, and a row per kind under the input's and the output's.
    let out = quadopt(&["optimize", s(&input), "-o", s(&output), "--boundary", "fixed"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("25 vertices, 18 faces (14 quads, 4 triangles)"), "{text}");
    let rows: Vec<&str> = text.lines().map(|l| l.split_whitespace().next().unwrap_or("")).collect();
    let at = |name: &str| rows.iter().position(|r| *r == name).unwrap();
    assert_eq!(&rows[at("input")..at("input") + 3], ["input", "quads", "triangles"], "{text}");
    assert_eq!(&rows[at("output")..at("output") + 3], ["output", "quads", "triangles"], "{text}");
    let row = |i: usize| text.lines().nth(i).unwrap().split_whitespace().skip(1).collect::<Vec<_>>();
    let fmt = |s: &Value| format!("{:.4}", s.as_f64().unwrap());
    let triangles = &v["output_by_kind"]["triangles"];
    assert_eq!(row(at("output") + 2)[..2], [fmt(&triangles["min"]), fmt(&triangles["avg"])], "{text}");
    assert!(text.contains("faces reoriented"), "{text}");

    // compare: the per-kind rows under the mesh's, and per-kind JSON for each run.
    let out = quadopt(&["compare", s(&input), "--effort", "fast"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 4, "{text}");
    assert!(
        lines[2].trim_start().starts_with("14 quads") && lines[3].trim_start().starts_with("4 triangles")
    );
    let pair = |s: &Value| format!("{:.3}/{:.3}", s["min"].as_f64().unwrap(), s["avg"].as_f64().unwrap());
    assert_eq!(lines[3].split_whitespace().nth(2), Some(pair(&before["by_kind"]["triangles"]).as_str()));
    let c = json_stdout(&quadopt(&["compare", s(&input), "--effort", "fast", "--json"]));
    let mesh = &c["meshes"][0];
    assert_eq!(mesh["input_by_kind"], before["by_kind"]);
    let runs = mesh["results"].as_array().unwrap();
    assert_eq!(runs.len(), 7);
    for r in runs {
        assert_eq!(r["output_by_kind"]["triangles"]["count"].as_u64(), Some(4), "{r}");
        assert_eq!(r["output_by_kind"]["quads"]["count"].as_u64(), Some(14), "{r}");
    }
    // A quad mesh's compare JSON has no per-kind key.
    let grid = dir.join("grid.obj");
    io::write_mesh(&grid, &jittered_grid(4)).unwrap();
    let c = json_stdout(&quadopt(&["compare", s(&grid), "--effort", "fast", "--json"]));
    assert!(c["meshes"][0].get("input_by_kind").is_none() && c["meshes"][0].get("triangles").is_none());
    assert!(c["meshes"][0]["results"][0].get("output_by_kind").is_none());
    let v = json_stdout(&quadopt(&["optimize", s(&grid), "-o", s(&output), "--json"]));
    for key in ["faces", "triangles", "input_by_kind", "output_by_kind"] {
        assert!(v.get(key).is_none(), "{key} in {v}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The mesh paths of an SVG (`<path d="...Z" fill=...>`, not the marks), as their corner counts
/// and tooltips.
fn svg_faces(svg: &str) -> Vec<(usize, String)> {
    svg.lines()
        .filter(|l| l.starts_with("<path d=\"M"))
        .map(|l| {
            let d = &l[l.find("d=\"").unwrap() + 3..l.find('Z').unwrap()];
            let tooltip = l.split("<title>").nth(1).unwrap().split('<').next().unwrap().to_string();
            (d.split_whitespace().count(), tooltip)
        })
        .collect()
}

#[test]
fn pictures_draw_triangles_as_triangles() {
    let dir = scratch("mixed-draw");
    let input = file_with(&dir, "mixed.obj", square_and_two_triangles(false).as_bytes());
    let svg = dir.join("mixed.svg");
    let out = quadopt(&["draw", s(&input), "-o", s(&svg)]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = std::fs::read_to_string(&svg).unwrap();
    let mut faces = svg_faces(&text);
    faces.sort();
    let t = format!("{:.4}", right_isosceles());
    assert_eq!(faces, [(3, t), (3, "1.0000".to_string()), (4, "1.0000".to_string())], "{text}");
    // The title has each kind's min and avg.
    assert!(text.contains("min/avg quads 1.000/1.000, triangles 0.816/0.908"), "{text}");

    // An inverted triangle is marked by a three-cornered outline (and hatched).
    let folded = file_with(&dir, "folded.obj", square_and_two_triangles(true).as_bytes());
    assert!(quadopt(&["draw", s(&folded), "-o", s(&svg)]).status.success());
    let text = std::fs::read_to_string(&svg).unwrap();
    let marks: Vec<&str> =
        text.lines().filter(|l| l.contains("class=\"inverted\"") && l.contains("<title>")).collect();
    assert_eq!(marks.len(), 1, "{text}");
    let d = marks[0].split("d=\"").nth(1).unwrap();
    let (outline, hatch) = d.split_once('Z').unwrap();
    assert_eq!(outline.split_whitespace().count(), 3, "{d}");
    assert!(hatch.contains('M'), "{d}");

    // Before and after: the histogram counts faces; PNG too.
    let both = dir.join("both.svg");
    let out = quadopt(&["draw", s(&folded), "--before-after", "--boundary", "fixed", "-o", s(&both)]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = std::fs::read_to_string(&both).unwrap();
    assert!(text.contains("share of faces") && !text.contains("share of quads"), "{text}");
    assert!(text.contains("triangles: min "), "{text}");
    assert_eq!(svg_faces(&text).iter().filter(|(n, _)| *n == 3).count(), 4, "two triangles a panel");
    let png = dir.join("both.png");
    assert!(quadopt(&["draw", s(&folded), "--before-after", "-o", s(&png)]).status.success());
    assert!(std::fs::read(&png).unwrap().starts_with(b"\x89PNG"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn generate_makes_quad_dominant_meshes() {
    let dir = scratch("generate-mixed");
    let path = dir.join("mixed.vtk");
    let out = quadopt(&[
        "generate",
        "-o",
        s(&path),
        "--nx",
        "20",
        "--ny",
        "20",
        "--holes",
        "0",
        "--triangles",
        "0.25",
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("441 vertices, 500 faces (300 quads, 200 triangles)"), "{text}");
    // A quarter of the 400 quads, each split in two.
    let mesh = io::read_mesh(&path).unwrap();
    let triangles = mesh.quads.iter().filter(|f| quadopt::face::is_triangle(f)).count();
    assert_eq!((mesh.points.len(), mesh.quads.len() - triangles, triangles), (441, 300, 200));
    // --triangles 0 is the quad mesh, byte for byte; 1 splits every quad.
    let (plain, zero, all) = (dir.join("plain.vtk"), dir.join("zero.vtk"), dir.join("all.vtk"));
    assert!(quadopt(&["generate", "-o", s(&plain), "--quads", "300"]).status.success());
    assert!(quadopt(&["generate", "-o", s(&zero), "--quads", "300", "--triangles", "0"]).status.success());
    assert_eq!(std::fs::read(&plain).unwrap(), std::fs::read(&zero).unwrap());
    assert!(quadopt(&["generate", "-o", s(&all), "--quads", "300", "--triangles", "1"]).status.success());
    let (q, a) = (io::read_mesh(&plain).unwrap(), io::read_mesh(&all).unwrap());
    assert!(a.quads.iter().all(quadopt::face::is_triangle));
    assert_eq!(a.quads.len(), 2 * q.quads.len());
    // Outside [0, 1]: a usage error, nothing written.
    let bad = dir.join("bad.vtk");
    for f in ["1.5", "-0.1", "nan"] {
        fails(&["generate", "-o", s(&bad), "--triangles", f], 2, "is not in [0, 1]", Some(&bad));
    }
    fails(&["generate", "-o", s(&bad), "--triangles", "half"], 2, "--triangles", Some(&bad));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_sample_report_has_a_row_per_face_kind_under_each_mixed_mesh() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("data");
    let out = quadopt(&[]);
    if !out.status.success() {
        return; // no bundled meshes: `no_arguments_reports_on_the_bundled_meshes` checks why
    }
    let text = String::from_utf8(out.stdout).unwrap();
    // The mesh rows, up to the notes on the surface samples.
    let lines: Vec<&str> =
        text.lines().skip(2).take_while(|l| !l.starts_with("on curved surfaces")).collect();
    assert!(text.contains("on curved surfaces") && text.contains("sphere_surface.vtk"), "{text}");
    let mut i = 0;
    while i < lines.len() {
        let cols: Vec<&str> = lines[i].split_whitespace().collect();
        let mesh = io::read_mesh(data.join(cols[0])).unwrap();
        let triangles = mesh.quads.iter().filter(|f| quadopt::face::is_triangle(f)).count();
        assert_eq!(cols[2].parse::<usize>().unwrap(), mesh.quads.len(), "{}", lines[i]);
        i += 1;
        if triangles == 0 {
            assert!(lines.get(i).is_none_or(|l| !l.starts_with(' ')), "{text}");
            continue;
        }
        let kinds: Vec<Vec<&str>> = lines[i..i + 2].iter().map(|l| l.split_whitespace().collect()).collect();
        assert_eq!((kinds[0][0], kinds[1][0]), ("quads", "triangles"), "{text}");
        assert_eq!(kinds[0][1].parse::<usize>().unwrap(), mesh.quads.len() - triangles, "{text}");
        assert_eq!(kinds[1][1].parse::<usize>().unwrap(), triangles, "{text}");
        i += 2;
    }
}

/// `quality` measures a mesh on a curved surface instead of refusing it: a half-cylinder strip
/// of planar rectangles (radius 1, six 30-degree columns, two rows) scores 1 by Verdict's 3D
/// measure on every face, and cos 15 degrees signed against the area-weighted vertex normals
/// (radial at every vertex but the strip's two straight ends, where a face's own normal is
/// the vertex's: each quad has a corner at 15 degrees). `optimize` keeps it on its surface.
#[test]
fn quality_measures_a_curved_mesh_by_both_measures() {
    let dir = scratch("curved-quality");
    let strip = dir.join("strip.obj");
    let mut text = String::new();
    for row in 0..3 {
        for col in 0..7 {
            let a = (col as f64 * 30.0).to_radians();
            text += &format!("v {:?} {:?} {row}\n", a.cos(), a.sin());
        }
    }
    for row in 0..2 {
        for col in 0..6 {
            let v = |r: usize, c: usize| r * 7 + c + 1;
            text += &format!(
                "f {} {} {} {}\n",
                v(row, col),
                v(row + 1, col),
                v(row + 1, col + 1),
                v(row, col + 1)
            );
        }
    }
    std::fs::write(&strip, text).unwrap();
    let out = quadopt(&["quality", s(&strip)]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let stdout = String::from_utf8(out.stdout).unwrap();
    assert!(stdout.contains("21 vertices, 12 quads, on a curved surface"), "{stdout}");
    assert!(stdout.contains("scaled Jacobian (Verdict, 3D): min 1.0000, avg 1.0000"), "{stdout}");
    assert!(stdout.contains("signed against the surface normal: min 0.9659, avg 0.9659"), "{stdout}");
    let v = json_stdout(&quadopt(&["quality", s(&strip), "--json"]));
    let cos15 = 15f64.to_radians().cos();
    assert_eq!(v["surface"], true);
    for key in ["min", "avg", "max"] {
        let (signed, verdict) = (v[key].as_f64().unwrap(), v["verdict"][key].as_f64().unwrap());
        assert!((signed - cos15).abs() < 1e-12, "{key}: {signed}");
        assert!((verdict - 1.0).abs() < 1e-12, "{key}: {verdict}");
    }
    assert_eq!((v["inverted"].as_u64(), v["verdict"]["inverted"].as_u64()), (Some(0), Some(0)));
    // -o writes the signed values as scaled_jacobian.
    let written = dir.join("strip.vtk");
    assert!(quadopt(&["quality", s(&strip), "-o", s(&written)]).status.success());
    let text = std::fs::read_to_string(&written).unwrap();
    assert!(text.contains("SCALARS scaled_jacobian"), "{text}");
    // `optimize` keeps it on its cylinder: the strip of rectangles is as good as it gets.
    let out = dir.join("out.obj");
    let r = json_stdout(&quadopt(&["optimize", s(&strip), "-o", s(&out), "--json"]));
    assert_eq!(r["surface"], true);
    assert!(r["output"]["min"].as_f64().unwrap() >= r["input"]["min"].as_f64().unwrap(), "{r}");
    assert!(r["surface_fidelity"]["max_distance_relative"].as_f64().unwrap() < 1e-9, "{r}");
    // Measured against its input, with the distances.
    let v = json_stdout(&quadopt(&["quality", s(&out), "--reference", s(&strip), "--json"]));
    assert!(v["surface_fidelity"]["max_distance"].as_f64().unwrap() < 1e-12, "{v}");
    assert_eq!(v["min"], r["output"]["min"], "{v} {r}");
    std::fs::remove_dir_all(&dir).unwrap();
}
