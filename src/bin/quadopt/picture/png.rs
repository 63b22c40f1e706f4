//! A [`Picture`] rasterized with tiny-skia and encoded as PNG. Text is drawn with an 8x8
//! public-domain bitmap font (font8x8), scaled by whole pixels: no system font is needed, and
//! every machine draws the same picture.

use super::{Item, Picture, Rgb, colour};
use tiny_skia::{
    Color, FillRule, GradientStop, LineJoin, LinearGradient, Paint, PathBuilder, Pixmap, Point,
    PremultipliedColorU8, Rect, SpreadMode, Stroke, Transform,
};

fn paint(Rgb(r, g, b): Rgb) -> Paint<'static> {
    let mut p = Paint { anti_alias: true, ..Paint::default() };
    p.set_color_rgba8(r, g, b, 255);
    p
}

/// The PNG file of `picture`, or why there is none (a frame too large to allocate).
pub fn render(picture: &Picture) -> Result<Vec<u8>, String> {
    let (w, h) = (picture.width, picture.height);
    let mut pixmap =
        Pixmap::new(w, h).ok_or_else(|| format!("a picture of {w} x {h} pixels is too large to draw"))?;
    pixmap.fill(Color::WHITE);
    let id = Transform::identity();
    for item in &picture.items {
        match item {
            Item::Faces { faces, stroke } => {
                // Each face filled alone (its own colour), then every edge in one stroked path,
                // so that an edge shared by two faces is not darkened twice.
                let mut edges = PathBuilder::new();
                for q in faces {
                    let mut pb = PathBuilder::new();
                    for (i, &[x, y]) in q.corners().iter().enumerate() {
                        if i == 0 {
                            pb.move_to(x, y);
                            edges.move_to(x, y);
                        } else {
                            pb.line_to(x, y);
                            edges.line_to(x, y);
                        }
                    }
                    pb.close();
                    edges.close();
                    if let Some(path) = pb.finish() {
                        pixmap.fill_path(&path, &paint(colour(f64::from(q.sj))), FillRule::Winding, id, None);
                    }
                }
                if let Some(path) = edges.finish() {
                    let s = Stroke { width: *stroke, line_join: LineJoin::Round, ..Stroke::default() };
                    pixmap.stroke_path(&path, &paint(Rgb::EDGE), &s, id, None);
                }
            }
            Item::Marks { marks, width } => {
                // Outlines and hatch lines in one stroked path.
                let mut pb = PathBuilder::new();
                for m in marks {
                    for (i, &[x, y]) in m.outline.iter().enumerate() {
                        if i == 0 {
                            pb.move_to(x, y);
                        } else {
                            pb.line_to(x, y);
                        }
                    }
                    pb.close();
                    for [[xa, ya], [xb, yb]] in &m.hatch {
                        pb.move_to(*xa, *ya);
                        pb.line_to(*xb, *yb);
                    }
                }
                if let Some(path) = pb.finish() {
                    let s = Stroke { width: *width, line_join: LineJoin::Round, ..Stroke::default() };
                    pixmap.stroke_path(&path, &paint(Rgb::MARK), &s, id, None);
                }
            }
            Item::Rect { x, y, w, h, fill, stroke, .. } => {
                if let Some(r) = Rect::from_xywh(*x, *y, *w, *h) {
                    pixmap.fill_rect(r, &paint(*fill), id, None);
                    if let Some(c) = stroke {
                        let path = PathBuilder::from_rect(r);
                        pixmap.stroke_path(
                            &path,
                            &paint(*c),
                            &Stroke { width: 0.5, ..Stroke::default() },
                            id,
                            None,
                        );
                    }
                }
            }
            Item::ColourBar { x, y, w, h } => {
                let stops = [(0.0, 1.0), (0.5, 0.0), (1.0, -1.0)]
                    .map(|(at, sj)| {
                        let Rgb(r, g, b) = colour(sj);
                        GradientStop::new(at, Color::from_rgba8(r, g, b, 255))
                    })
                    .to_vec();
                let shader = LinearGradient::new(
                    Point::from_xy(0.0, *y),
                    Point::from_xy(0.0, y + h),
                    stops,
                    SpreadMode::Pad,
                    id,
                );
                if let (Some(shader), Some(r)) = (shader, Rect::from_xywh(*x, *y, *w, *h)) {
                    let p = Paint { shader, anti_alias: true, ..Paint::default() };
                    pixmap.fill_rect(r, &p, id, None);
                    let path = PathBuilder::from_rect(r);
                    pixmap.stroke_path(
                        &path,
                        &paint(Rgb::EDGE),
                        &Stroke { width: 0.5, ..Stroke::default() },
                        id,
                        None,
                    );
                }
            }
            Item::Text { x, y, size, anchor, text } => {
                let left = anchor.left(*x, super::text_width(text, *size));
                glyphs(&mut pixmap, left.round() as i64, y.round() as i64, (*size / 8).max(1) as i64, text);
            }
        }
    }
    pixmap.encode_png().map_err(|e| format!("cannot encode the picture as PNG: {e}"))
}

/// `text` in black, its top left at (`x`, `y`), each font pixel `scale` pixels square;
/// characters outside ASCII as '?'. Pixels outside the frame are dropped.
fn glyphs(pixmap: &mut Pixmap, x: i64, y: i64, scale: i64, text: &str) {
    let (w, h) = (i64::from(pixmap.width()), i64::from(pixmap.height()));
    let black = PremultipliedColorU8::from_rgba(0, 0, 0, 255).expect("opaque black is premultiplied");
    let pixels = pixmap.pixels_mut();
    for (i, c) in text.chars().enumerate() {
        let code = if c.is_ascii() { c as usize } else { '?' as usize };
        let glyph = font8x8::legacy::BASIC_LEGACY[code];
        let x0 = x + i as i64 * 8 * scale;
        for (row, bits) in glyph.iter().enumerate() {
            for col in 0..8 {
                if bits & (1 << col) == 0 {
                    continue;
                }
                for dy in 0..scale {
                    for dx in 0..scale {
                        let (px, py) = (x0 + col * scale + dx, y + row as i64 * scale + dy);
                        if (0..w).contains(&px) && (0..h).contains(&py) {
                            pixels[(py * w + px) as usize] = black;
                        }
                    }
                }
            }
        }
    }
}
