//! Pictures from the CLI (`draw`, `draw --before-after`, `optimize --picture`): PNG and SVG
//! of the same drawing have the same frame, the PNG's legend and border are where they should
//! be, and the numbers a picture shows are the ones `quality` and `optimize` report.
#![cfg(feature = "cli")]

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use tiny_skia::Pixmap;

fn quadopt(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_quadopt")).args(args).output().unwrap()
}

fn ok(out: Output) -> Output {
    assert!(out.status.success(), "stderr: {}", String::from_utf8_lossy(&out.stderr));
    out
}

fn scratch(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("quadopt-pictures-{}-{test}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// A bundled sample with one inverted quad (81 quads).
fn sample() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("data/patch_notched.vtk")
}

/// The `width` and `height` attributes of an SVG's root element.
fn svg_size(svg: &str) -> (u32, u32) {
    let root = &svg[svg.find("<svg").unwrap()..];
    let attr = |name: &str| -> u32 {
        let at = root.find(&format!(" {name}=\"")).unwrap() + name.len() + 3;
        root[at..].split('"').next().unwrap().parse().unwrap()
    };
    (attr("width"), attr("height"))
}

/// The width and height in a PNG's IHDR chunk.
fn png_size(png: &[u8]) -> (u32, u32) {
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    assert_eq!(&png[12..16], b"IHDR");
    let be = |b: &[u8]| u32::from_be_bytes(b.try_into().unwrap());
    (be(&png[16..20]), be(&png[20..24]))
}

fn json(out: Output) -> Value {
    serde_json::from_slice(&ok(out).stdout).unwrap()
}

/// The texts of an SVG's `<text>` elements, in order.
fn texts(svg: &str) -> Vec<&str> {
    svg.split("<text")
        .skip(1)
        .map(|t| t[t.find('>').unwrap() + 1..t.find("</text>").unwrap()].trim())
        .collect()
}

/// The histogram tooltips of an SVG: (series, bin, count).
fn bars(svg: &str) -> Vec<(String, String, usize)> {
    svg.split("<rect")
        .skip(1)
        .filter_map(|r| {
            let t = &r[r.find("<title>")? + 7..r.find("</title>")?];
            let (name, rest) = t.split_once(' ')?;
            let (bin, count) = rest.rsplit_once(": ")?;
            Some((name.to_string(), bin.to_string(), count.trim_end_matches(" quads").parse().ok()?))
        })
        .collect()
}

#[test]
fn png_and_svg_of_one_drawing_have_one_frame_and_the_png_draws_its_legend_inside() {
    let dir = scratch("frame");
    let input = sample();
    for extra in [&[][..], &["--before-after"][..]] {
        let (svg, png) = (dir.join("p.svg"), dir.join("p.png"));
        ok(quadopt(&[&["draw", s(&input), "-o", s(&svg)][..], extra].concat()));
        ok(quadopt(&[&["draw", s(&input), "-o", s(&png)][..], extra].concat()));
        let svg = std::fs::read_to_string(&svg).unwrap();
        let bytes = std::fs::read(&png).unwrap();
        let (w, h) = png_size(&bytes);
        assert_eq!((w, h), svg_size(&svg), "{extra:?}");
        let pixmap = Pixmap::decode_png(&bytes).unwrap();
        let px = |x: u32, y: u32| {
            let c = pixmap.pixel(x, y).unwrap();
            (c.red(), c.green(), c.blue(), c.alpha())
        };
        // A white border: nothing is drawn in the outer 10 pixels.
        for x in 0..w {
            for y in (0..10).chain(h - 10..h) {
                assert_eq!(px(x, y), (255, 255, 255, 255), "{extra:?}: ({x}, {y})");
            }
        }
        for y in 0..h {
            for x in (0..10).chain(w - 10..w) {
                assert_eq!(px(x, y), (255, 255, 255, 255), "{extra:?}: ({x}, {y})");
            }
        }
        // The legend is the rightmost thing in the top part of the picture: its colour bar
        // runs down to dark red (-1) and its labels are black text, both in the last 200
        // columns and inside the frame.
        let legend = (w - 200..w - 10).flat_map(|x| (0..h.min(400)).map(move |y| (x, y)));
        let (mut dark_red, mut black) = (0, 0);
        for (x, y) in legend {
            match px(x, y) {
                (r, 0, 0, 255) if (120..=136).contains(&r) => dark_red += 1,
                (0, 0, 0, 255) => black += 1,
                _ => {}
            }
        }
        assert!(dark_red > 20 && black > 50, "{extra:?}: {dark_red} dark red, {black} black legend pixels");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn before_after_shows_the_numbers_quality_and_optimize_report() {
    let dir = scratch("numbers");
    let input = sample();
    let svg = dir.join("ba.svg");
    ok(quadopt(&["draw", "--before-after", s(&input), "-o", s(&svg), "--boundary", "fixed"]));
    let svg = std::fs::read_to_string(&svg).unwrap();
    let before = json(quadopt(&["quality", s(&input), "--json"]));
    let out = dir.join("out.vtk");
    let report = json(quadopt(&["optimize", s(&input), "-o", s(&out), "--boundary", "fixed", "--json"]));
    let after = &report["output"];
    let caption = |v: &Value| {
        format!(
            "min {:.3}  avg {:.3}  {} inverted",
            v["min"].as_f64().unwrap(),
            v["avg"].as_f64().unwrap(),
            v["inverted"].as_u64().unwrap()
        )
    };
    let texts = texts(&svg);
    let at =
        |t: &str| texts.iter().position(|x| *x == t).unwrap_or_else(|| panic!("no text {t:?} in {texts:?}"));
    assert!(at("input") < at("optimized (ep, fixed)"));
    assert!(at(&caption(&before)) < at(&caption(after)), "{texts:?}");
    // The histogram's bars: every quad once per series, the same bins as `quality` reports,
    // and the bin at or below 0 holds the inverted quads.
    let bars = bars(&svg);
    let after_quality = json(quadopt(&["quality", s(&out), "--json"]));
    for (series, q) in [("input", &before), ("optimized", &after_quality)] {
        let counts: Vec<u64> = bars.iter().filter(|b| b.0 == series).map(|b| b.2 as u64).collect();
        let expected: Vec<u64> =
            q["histogram"].as_array().unwrap().iter().map(|v| v.as_u64().unwrap()).collect();
        assert_eq!(counts, expected, "{series}");
        assert_eq!(counts.iter().sum::<u64>(), 81);
        let inverted = bars.iter().find(|b| b.0 == series && b.1 == "&lt;=0").unwrap().2;
        assert_eq!(inverted as u64, q["inverted"].as_u64().unwrap(), "{series}");
    }
    assert_eq!(before["inverted"], 1);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn optimize_picture_changes_nothing_else_and_bad_names_fail_before_the_run() {
    let dir = scratch("optimize");
    let input = sample();
    let (plain, pictured) = (dir.join("plain.vtk"), dir.join("pictured.vtk"));
    let picture = dir.join("ba.png");
    ok(quadopt(&["optimize", s(&input), "-o", s(&plain)]));
    let out = ok(quadopt(&["optimize", s(&input), "-o", s(&pictured), "--picture", s(&picture)]));
    assert_eq!(std::fs::read(&plain).unwrap(), std::fs::read(&pictured).unwrap());
    let (w, h) = png_size(&std::fs::read(&picture).unwrap());
    assert!(w > 1000 && h > 600, "{w} x {h}: not two panels and a histogram");
    assert!(String::from_utf8_lossy(&out.stdout).contains(s(&picture)), "the report names the picture");
    // A picture name without .png or .svg: one line, exit 1, and neither file written.
    let (mesh, bad) = (dir.join("never.vtk"), dir.join("ba.jpg"));
    let r = quadopt(&["optimize", s(&input), "-o", s(&mesh), "--picture", s(&bad)]);
    assert_eq!(r.status.code(), Some(1));
    let err = String::from_utf8(r.stderr).unwrap();
    assert!(err.contains("expected the extension .png or .svg") && err.lines().count() == 1, "{err}");
    assert!(!mesh.exists() && !bad.exists());
    let r = quadopt(&["optimize", s(&input), "-o", s(&mesh), "--picture", "-"]);
    assert_eq!(r.status.code(), Some(2), "{}", String::from_utf8_lossy(&r.stderr));
    assert!(r.stdout.is_empty() && !mesh.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}
