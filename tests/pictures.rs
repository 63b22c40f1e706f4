//! Pictures from the CLI (`draw`, `draw --before-after`, `optimize --picture`): PNG and SVG
//! of the same drawing have the same frame, the PNG's legend and border are where they should
//! be, the numbers a picture shows are the ones `quality` and `optimize` report, inverted quads
//! are marked in both formats, and the histogram's axes are labelled.
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

/// The bundled sample of the paper's mazewheel, with five inverted quads.
fn mazewheel() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("data/mazewheel.vtk")
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

/// The `y` attribute and the text of an SVG's `<text>` elements, in order.
fn placed_texts(svg: &str) -> Vec<(f64, &str)> {
    svg.split("<text")
        .skip(1)
        .map(|t| {
            let y = &t[t.find(" y=\"").unwrap() + 4..];
            let y = y[..y.find('"').unwrap()].parse().unwrap();
            (y, t[t.find('>').unwrap() + 1..t.find("</text>").unwrap()].trim())
        })
        .collect()
}

/// The values in the tooltips of an SVG's marks of inverted quads (`<path class="inverted">`
/// with a `<title>`; the legend's sample has none).
fn marked(svg: &str) -> Vec<f64> {
    svg.split(r#"<path class="inverted""#)
        .skip(1)
        .filter_map(|p| {
            // The element: up to its end tag, or its own end when it has no content.
            let end = p.find("</path>").unwrap_or(p.len()).min(p.find("/>").unwrap_or(p.len()));
            let p = &p[..end];
            let t = &p[p.find("<title>")? + 7..p.find("</title>")?];
            Some(t.strip_prefix("inverted: ").unwrap().parse().unwrap())
        })
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
            // "1 quad", "2 quads": the tooltip counts in the singular and the plural.
            let count = count.strip_suffix(" quads").or_else(|| count.strip_suffix(" quad"))?;
            Some((name.to_string(), bin.to_string(), count.parse().ok()?))
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

#[test]
fn inverted_quads_are_outlined_and_hatched_in_svg_and_png() {
    let dir = scratch("inverted");
    let input = mazewheel();
    let quality = json(quadopt(&["quality", s(&input), "--json"]));
    let inverted = quality["inverted"].as_u64().unwrap() as usize;
    assert_eq!(inverted, 5);
    // SVG: one mark per inverted quad, each titled with its value, the worst one the minimum.
    let svg = dir.join("p.svg");
    ok(quadopt(&["draw", s(&input), "-o", s(&svg)]));
    let svg = std::fs::read_to_string(&svg).unwrap();
    let values = marked(&svg);
    assert_eq!(values.len(), inverted, "{values:?}");
    assert!(values.iter().all(|&v| v <= 0.0), "{values:?}");
    let worst = values.iter().copied().fold(f64::INFINITY, f64::min);
    assert!((worst - quality["min"].as_f64().unwrap()).abs() < 1e-4, "{worst} {}", quality["min"]);
    // The legend shows the marking: a sample (without a title) and its label.
    assert_eq!(svg.matches(r#"<path class="inverted""#).count(), inverted + 1);
    assert!(texts(&svg).contains(&"inverted"));
    // Before and after: the input's five, none in the result (which has none).
    let ba = dir.join("ba.svg");
    ok(quadopt(&["draw", "--before-after", s(&input), "-o", s(&ba)]));
    assert_eq!(marked(&std::fs::read_to_string(&ba).unwrap()).len(), inverted);
    // PNG: the marks are the only black in the mesh panel, below the title and left of the
    // legend (edges are grey): some where quads are inverted, none where none are.
    let dark_in_panel = |args: &[&str]| {
        let (png, svg) = (dir.join("p.png"), dir.join("same.svg"));
        ok(quadopt(&[&["draw", s(&input), "-o", s(&png)][..], args].concat()));
        ok(quadopt(&[&["draw", s(&input), "-o", s(&svg)][..], args].concat()));
        // The legend's left edge: the colour bar's, in the SVG of the same drawing.
        let svg = std::fs::read_to_string(&svg).unwrap();
        let bar = &svg[..svg.find(r#"fill="url(#sj)""#).unwrap()];
        let bar = &bar[bar.rfind(r#"<rect x=""#).unwrap() + 9..];
        let legend = bar[..bar.find('"').unwrap()].parse::<f64>().unwrap() as u32;
        let pixmap = Pixmap::decode_png(&std::fs::read(&png).unwrap()).unwrap();
        let mut dark = 0;
        for y in 48..pixmap.height() - 10 {
            for x in 10..legend - 10 {
                let c = pixmap.pixel(x, y).unwrap();
                dark += usize::from(c.red() < 60 && c.green() < 60 && c.blue() < 60);
            }
        }
        dark
    };
    let marked_pixels = dark_in_panel(&[]);
    assert!(marked_pixels > 5 * 40, "{marked_pixels} dark pixels for 5 inverted quads");
    assert_eq!(dark_in_panel(&["--optimized"]), 0);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_histogram_axes_are_titled_and_ticked_up_to_the_largest_share() {
    let dir = scratch("axes");
    let input = mazewheel();
    let (svg, out) = (dir.join("ba.svg"), dir.join("out.vtk"));
    ok(quadopt(&["draw", "--before-after", s(&input), "-o", s(&svg)]));
    ok(quadopt(&["optimize", s(&input), "-o", s(&out)]));
    let svg = std::fs::read_to_string(&svg).unwrap();
    let texts = placed_texts(&svg);
    let at = |t: &str| texts.iter().position(|x| x.1 == t).unwrap_or_else(|| panic!("no {t:?} in {texts:?}"));
    // The y axis's title heads the histogram; the x axis's title is the last text, under the
    // bins' labels.
    let (y_title, x_title) = (at("share of quads"), at("scaled Jacobian (&lt;=0: inverted)"));
    assert_eq!(x_title, texts.len() - 1);
    assert!(texts[x_title].0 > texts[at(".9-1")].0 && texts[at(".9-1")].0 > texts[y_title].0);
    // Ticks: 0%, s%, 2s%, ... from the bottom up, evenly spaced, the top one the first at or
    // above the largest share of a bin in either series.
    let ticks: Vec<(f64, u32)> =
        texts.iter().filter_map(|(y, t)| Some((*y, t.strip_suffix('%')?.parse().ok()?))).collect();
    assert!((3..=6).contains(&ticks.len()), "{ticks:?}");
    let step = ticks[1].1;
    for (k, (y, v)) in ticks.iter().enumerate() {
        assert_eq!(*v, k as u32 * step, "{ticks:?}");
        let spacing = ticks[0].0 - ticks[1].0;
        assert!(spacing > 0.0 && (ticks[0].0 - y - k as f64 * spacing).abs() < 0.2, "{ticks:?}");
    }
    let mut largest = 0.0f64;
    for mesh in [&input, &out] {
        let q = json(quadopt(&["quality", s(mesh), "--json"]));
        let h: Vec<f64> = q["histogram"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
        let total: f64 = h.iter().sum();
        largest = h.iter().fold(largest, |a, &n| a.max(n / total * 100.0));
    }
    let top = f64::from(ticks.last().unwrap().1);
    assert!(top >= largest && top - f64::from(step) < largest, "ticks {ticks:?}, largest share {largest}%");
    std::fs::remove_dir_all(&dir).unwrap();
}
