//! A [`Picture`] as SVG text: faces (quads and triangles) as paths with their scaled Jacobian
//! as a tooltip, the marks of inverted faces as paths of class `inverted`, the colour bar as a gradient, text in
//! the viewer's monospace font.

use super::{Anchor, Item, Picture, Rgb, colour};
use std::fmt::Write;

fn hex(Rgb(r, g, b): Rgb) -> String {
    format!("#{r:02x}{g:02x}{b:02x}")
}

fn escape(t: &str) -> String {
    t.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;")
}

/// The SVG text of `picture`.
pub fn render(picture: &Picture) -> String {
    let (w, h) = (picture.width, picture.height);
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}">"#
    );
    let _ = writeln!(s, r#"<rect width="100%" height="100%" fill="white"/>"#);
    for item in &picture.items {
        match item {
            Item::Faces { faces, stroke } => {
                let _ = writeln!(
                    s,
                    r##"<g stroke="{}" stroke-width="{stroke:.3}" stroke-linejoin="round">"##,
                    hex(Rgb::EDGE)
                );
                for q in faces {
                    let mut d = String::new();
                    for (i, [x, y]) in q.corners().iter().enumerate() {
                        let _ = write!(d, "{}{x:.2},{y:.2} ", if i == 0 { "M" } else { "L" });
                    }
                    let fill = hex(colour(f64::from(q.sj)));
                    let _ = writeln!(s, r#"<path d="{d}Z" fill="{fill}"><title>{:.4}</title></path>"#, q.sj);
                }
                let _ = writeln!(s, "</g>");
            }
            Item::Marks { marks, width } => {
                let _ = writeln!(
                    s,
                    r#"<g fill="none" stroke="{}" stroke-width="{width:.3}" stroke-linejoin="round">"#,
                    hex(Rgb::MARK)
                );
                for m in marks {
                    let mut d = String::new();
                    for (i, [x, y]) in m.outline.iter().enumerate() {
                        let _ = write!(d, "{}{x:.2},{y:.2} ", if i == 0 { "M" } else { "L" });
                    }
                    d.push('Z');
                    for [[xa, ya], [xb, yb]] in &m.hatch {
                        let _ = write!(d, " M{xa:.2},{ya:.2} L{xb:.2},{yb:.2}");
                    }
                    let _ = match &m.tooltip {
                        Some(t) => {
                            writeln!(
                                s,
                                r#"<path class="inverted" d="{d}"><title>{}</title></path>"#,
                                escape(t)
                            )
                        }
                        None => writeln!(s, r#"<path class="inverted" d="{d}"/>"#),
                    };
                }
                let _ = writeln!(s, "</g>");
            }
            Item::Rect { x, y, w, h, fill, stroke, tooltip } => {
                let stroke =
                    stroke.map(|c| format!(r#" stroke="{}" stroke-width="0.5""#, hex(c))).unwrap_or_default();
                let open = format!(
                    r#"<rect x="{x:.2}" y="{y:.2}" width="{w:.2}" height="{h:.2}" fill="{}"{stroke}"#,
                    hex(*fill)
                );
                let _ = match tooltip {
                    Some(t) => writeln!(s, "{open}><title>{}</title></rect>", escape(t)),
                    None => writeln!(s, "{open}/>"),
                };
            }
            Item::ColourBar { x, y, w, h } => {
                let stops: Vec<String> = [(0.0, 1.0), (0.5, 0.0), (1.0, -1.0)]
                    .iter()
                    .map(|(at, sj)| format!(r#"<stop offset="{at}" stop-color="{}"/>"#, hex(colour(*sj))))
                    .collect();
                let _ = writeln!(
                    s,
                    r#"<defs><linearGradient id="sj" x1="0" y1="0" x2="0" y2="1">{}</linearGradient></defs>"#,
                    stops.concat()
                );
                let _ = writeln!(
                    s,
                    r##"<rect x="{x}" y="{y}" width="{w}" height="{h}" fill="url(#sj)" stroke="{}" stroke-width="0.5"/>"##,
                    hex(Rgb::EDGE)
                );
            }
            Item::Text { x, y, size, anchor, text } => {
                let baseline = y + 0.8 * *size as f32;
                let anchor = match anchor {
                    Anchor::Start => "",
                    Anchor::Middle => r#" text-anchor="middle""#,
                    Anchor::End => r#" text-anchor="end""#,
                };
                let _ = writeln!(
                    s,
                    r#"<text x="{x:.1}" y="{baseline:.1}" font-family="monospace" font-size="{size}"{anchor}>{}</text>"#,
                    escape(text)
                );
            }
        }
    }
    let _ = writeln!(s, "</svg>");
    s
}
