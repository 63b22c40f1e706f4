//! An SVG picture of a quad mesh: every quad filled by the colour of its scaled Jacobian (red
//! for 0 and below, white for 1, as in the paper's figures), edges in grey, and a legend.

use quadopt::QuadMesh;
use std::fmt::Write;

/// The fill colour of a scaled Jacobian: dark red at -1, red at 0, white at 1.
pub fn colour(sj: f64) -> (u8, u8, u8) {
    let sj = if sj.is_finite() { sj.clamp(-1.0, 1.0) } else { -1.0 };
    if sj >= 0.0 {
        let c = (255.0 * sj).round() as u8;
        (255, c, c)
    } else {
        ((255.0 - 127.0 * -sj).round() as u8, 0, 0)
    }
}

fn hex((r, g, b): (u8, u8, u8)) -> String {
    format!("#{r:02x}{g:02x}{b:02x}")
}

/// The SVG text of `mesh` with a title line.
pub fn render(mesh: &QuadMesh, title: &str) -> String {
    const SIZE: f64 = 800.0;
    const MARGIN: f64 = 20.0;
    const LEGEND: f64 = 110.0;
    let points = mesh.points();
    let used: Vec<usize> = mesh.quads().iter().flatten().map(|&v| v as usize).collect();
    let (mut lo, mut hi) = (glam::DVec2::splat(f64::INFINITY), glam::DVec2::splat(f64::NEG_INFINITY));
    for &v in &used {
        lo = lo.min(points[v]);
        hi = hi.max(points[v]);
    }
    let extent = (hi - lo).max(glam::DVec2::splat(1e-300));
    let scale = SIZE / extent.x.max(extent.y);
    let (w, h) = (extent.x * scale + 2.0 * MARGIN, extent.y * scale + 2.0 * MARGIN + 30.0);
    let map = |p: glam::DVec2| (MARGIN + (p.x - lo.x) * scale, 30.0 + MARGIN + (hi.y - p.y) * scale);
    let mut s = String::new();
    let width = w + LEGEND;
    let height = h.max(300.0);
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0}" height="{height:.0}" viewBox="0 0 {width:.1} {height:.1}">"#
    );
    let _ = writeln!(s, r#"<rect width="100%" height="100%" fill="white"/>"#);
    let _ = writeln!(
        s,
        r#"<text x="{MARGIN}" y="20" font-family="sans-serif" font-size="14">{}</text>"#,
        escape(title)
    );
    let stroke = (0.6f64).min(0.15 * SIZE / (mesh.quads().len() as f64).sqrt().max(1.0));
    let _ = writeln!(s, r##"<g stroke="#555" stroke-width="{stroke:.3}" stroke-linejoin="round">"##);
    for (q, sj) in mesh.quads().iter().zip(mesh.quality_values()) {
        let mut d = String::new();
        for (i, &v) in q.iter().enumerate() {
            let (x, y) = map(points[v as usize]);
            let _ = write!(d, "{}{x:.2},{y:.2} ", if i == 0 { "M" } else { "L" });
        }
        let _ = writeln!(s, r#"<path d="{d}Z" fill="{}"><title>{sj:.4}</title></path>"#, hex(colour(sj)));
    }
    let _ = writeln!(s, "</g>");
    // Legend: a vertical bar from 1 (top) to -1 (bottom).
    let (lx, ly, lh) = (w + 20.0, 50.0, 200.0);
    let _ = writeln!(
        s,
        r#"<defs><linearGradient id="sj" x1="0" y1="0" x2="0" y2="1"><stop offset="0" stop-color="{}"/><stop offset="0.5" stop-color="{}"/><stop offset="1" stop-color="{}"/></linearGradient></defs>"#,
        hex(colour(1.0)),
        hex(colour(0.0)),
        hex(colour(-1.0))
    );
    let _ = writeln!(
        s,
        r##"<rect x="{lx}" y="{ly}" width="20" height="{lh}" fill="url(#sj)" stroke="#555" stroke-width="0.5"/>"##
    );
    let _ = writeln!(
        s,
        r#"<text x="{lx}" y="{}" font-family="sans-serif" font-size="12">scaled Jacobian</text>"#,
        ly - 10.0
    );
    for v in [1.0, 0.5, 0.0, -0.5, -1.0] {
        let y = ly + (1.0 - v) / 2.0 * lh;
        let _ = writeln!(
            s,
            r#"<text x="{}" y="{:.1}" font-family="sans-serif" font-size="12">{v}</text>"#,
            lx + 26.0,
            y + 4.0
        );
    }
    let _ = writeln!(s, "</svg>");
    s
}

fn escape(t: &str) -> String {
    t.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;")
}
