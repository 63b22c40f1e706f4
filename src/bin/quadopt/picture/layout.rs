//! Where things go: the mesh panels on one scale (inverted faces marked over them), their
//! captions, the legend to their right, and (before/after) the histogram underneath with its
//! axes labelled, every item inside the frame.

use super::{
    Anchor, BIN_LABELS, Face, Item, Picture, Rgb, TEXT, colour, hatch, histogram, is_inverted, text_width,
};
use crate::plural::face_words;
use glam::DVec2;
use quadopt::quality::ByFaceKind;
use quadopt::{Mesh, QualityStats, face};
use std::borrow::Cow;

const MARGIN: f32 = 20.0;
/// The width of an inverted face's outline and hatching: wider than any edge, so that an
/// inverted face is a visible dot even where faces are smaller than a pixel.
const MARK_WIDTH: f32 = 1.5;
/// Between two panels.
const GAP: f32 = 40.0;
/// The colour bar's height and width.
const BAR: (f32, f32) = (200.0, 20.0);
/// The histogram's series.
const INPUT: Rgb = Rgb(150, 150, 150);
const OPTIMIZED: Rgb = Rgb(60, 110, 180);
/// The histogram's plot height.
const PLOT: f32 = 160.0;
/// The steps between the histogram's ticks, in percent: the first that needs at most
/// `MAX_TICK_STEPS` of them to reach the largest share.
const TICK_STEPS: [u32; 4] = [2, 5, 10, 20];
const MAX_TICK_STEPS: u32 = 5;

/// What a panel shows: faces over points in the drawing's plane (y up), each face's value
/// (its colour), and the order to draw them in (later over earlier; all in order if `None`).
pub struct Panel<'a> {
    pub points: Cow<'a, [DVec2]>,
    pub faces: &'a [face::Face],
    pub values: Vec<f64>,
    pub order: Option<Vec<u32>>,
}

impl<'a> Panel<'a> {
    /// A planar mesh as it lies, coloured by its scaled Jacobians.
    pub fn of_mesh(mesh: &'a Mesh) -> Panel<'a> {
        Panel {
            points: Cow::Borrowed(mesh.points()),
            faces: mesh.faces(),
            values: mesh.quality_values(),
            order: None,
        }
    }

    /// The faces to draw, in order.
    fn drawn(&self) -> Box<dyn Iterator<Item = usize> + '_> {
        match &self.order {
            Some(order) => Box::new(order.iter().map(|&f| f as usize)),
            None => Box::new(0..self.faces.len()),
        }
    }
}

/// One mesh and its title line.
pub fn single(mesh: &Mesh, title: &str) -> Picture {
    single_panel(&Panel::of_mesh(mesh), title)
}

/// One panel and its title line.
pub fn single_panel(panel: &Panel, title: &str) -> Picture {
    let mut p = Builder::new(title);
    let panels = p.panels(&[panel], 800.0);
    p.legend(panels.right + GAP, panels.top);
    p.finish()
}

/// The input (`before`) and the optimized mesh (`after`) side by side on one scale and one
/// colour scale, each headed and with its min / avg / inverted underneath, and the histogram
/// of both below. A mesh with triangles has two more lines under each panel, the min and avg
/// of its quads and of its triangles, and its histogram counts faces.
pub fn before_after(before: &Mesh, after: &Mesh, title: &str, headings: [&str; 2]) -> Picture {
    before_after_panels([&Panel::of_mesh(before), &Panel::of_mesh(after)], title, headings)
}

/// [`before_after`] of two panels of one mesh.
pub fn before_after_panels(shown: [&Panel; 2], title: &str, headings: [&str; 2]) -> Picture {
    let mut p = Builder::new(title);
    let values = shown.map(|panel| panel.values.clone());
    let mixed = shown[0].faces.iter().any(face::is_triangle);
    let heading_top = p.bottom + 14.0;
    p.bottom = heading_top + TEXT as f32 + 8.0;
    let panels = p.panels(&shown, 560.0);
    let mut bottom = panels.bottom;
    for (i, (heading, values)) in headings.iter().zip(&values).enumerate() {
        let x = panels.left[i];
        p.text(x, heading_top, heading);
        let q = QualityStats::from_values(values);
        p.text(
            x,
            panels.bottom + 10.0,
            &format!("min {:.3}  avg {:.3}  {} inverted", q.min, q.avg, q.inverted),
        );
        bottom = bottom.max(panels.bottom + 10.0 + TEXT as f32);
        if mixed {
            let k = ByFaceKind::new(shown[i].faces, values);
            for (line, (name, s)) in [("quads", k.quads), ("triangles", k.triangles)].into_iter().enumerate()
            {
                let y = panels.bottom + 10.0 + (line + 1) as f32 * (TEXT as f32 + 4.0);
                p.text(x, y, &kind_line(name, s));
                bottom = bottom.max(y + TEXT as f32);
            }
        }
    }
    p.legend(panels.right + GAP, panels.top);
    p.bottom = p.bottom.max(bottom) + 30.0;
    p.histogram(&values, mixed);
    p.finish()
}

/// Where the panels went: their left edges, top, right end and bottom.
struct Panels {
    left: Vec<f32>,
    top: f32,
    right: f32,
    bottom: f32,
}

/// A picture under construction; `right` and `bottom` are how far its items reach.
struct Builder {
    items: Vec<Item>,
    right: f32,
    bottom: f32,
}

impl Builder {
    fn new(title: &str) -> Builder {
        let mut b = Builder { items: Vec::new(), right: 0.0, bottom: 0.0 };
        b.text(MARGIN, MARGIN, title);
        b
    }

    fn push(&mut self, item: Item) {
        let (_, _, right, bottom) = item.bounds();
        self.right = self.right.max(right);
        self.bottom = self.bottom.max(bottom);
        self.items.push(item);
    }

    fn text(&mut self, x: f32, y: f32, text: &str) {
        self.push(Item::Text { x, y, size: TEXT, anchor: Anchor::Start, text: text.to_string() });
    }

    /// The meshes in a row below what is there, the longer side of their common bounding box
    /// `size` pixels.
    fn panels(&mut self, meshes: &[&Panel], size: f64) -> Panels {
        let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        for m in meshes {
            let points = &m.points;
            for &v in m.faces.iter().flat_map(face::vertices) {
                lo = lo.min(points[v as usize]);
                hi = hi.max(points[v as usize]);
            }
        }
        let extent = (hi - lo).max(DVec2::splat(1e-300));
        let scale = size / extent.x.max(extent.y);
        let (w, h) = ((extent.x * scale) as f32, (extent.y * scale) as f32);
        let top = self.bottom + 12.0;
        let mut left = Vec::new();
        for (i, m) in meshes.iter().enumerate() {
            let x0 = MARGIN + i as f32 * (w + GAP);
            left.push(x0);
            let points = &m.points;
            let map = |p: DVec2| [x0 + ((p.x - lo.x) * scale) as f32, top + ((hi.y - p.y) * scale) as f32];
            let mut faces = Vec::with_capacity(m.faces.len());
            let mut marks = Vec::new();
            for (f, sj) in m.drawn().map(|f| (&m.faces[f], m.values[f])) {
                let corners =
                    f.map(|v| if v == face::NO_VERTEX { [0.0; 2] } else { map(points[v as usize]) });
                let corners = &corners[..face::corner_count(f)];
                faces.push(Face::new(corners, sj as f32));
                if is_inverted(sj) {
                    marks.push(hatch::mark(corners, Some(format!("inverted: {sj:.4}"))));
                }
            }
            let stroke = 0.6f64.min(0.15 * size / (m.faces.len() as f64).sqrt().max(1.0)) as f32;
            self.push(Item::Faces { faces, stroke });
            if !marks.is_empty() {
                self.push(Item::Marks { marks, width: MARK_WIDTH });
            }
        }
        let right = MARGIN + meshes.len() as f32 * (w + GAP) - GAP;
        self.right = self.right.max(right);
        self.bottom = self.bottom.max(top + h);
        Panels { left, top, right, bottom: top + h }
    }

    /// The colour scale, its title over it, at (`x`, `y`), and under it a sample of how an
    /// inverted face is marked.
    fn legend(&mut self, x: f32, y: f32) {
        self.text(x, y, "scaled");
        self.text(x, y + TEXT as f32 + 4.0, "Jacobian");
        let top = y + 2.0 * TEXT as f32 + 16.0;
        self.push(Item::ColourBar { x, y: top, w: BAR.1, h: BAR.0 });
        for (v, label) in [(1.0, "1"), (0.5, "0.5"), (0.0, "0"), (-0.5, "-0.5"), (-1.0, "-1")] {
            let tick = top + (1.0 - v) / 2.0 * BAR.0;
            self.text(x + BAR.1 + 8.0, tick - TEXT as f32 / 2.0, label);
        }
        let (sy, side) = (top + BAR.0 + 2.0 * TEXT as f32, BAR.1);
        self.push(Item::Rect {
            x,
            y: sy,
            w: side,
            h: side,
            fill: colour(-0.25),
            stroke: None,
            tooltip: None,
        });
        let corners = [[x, sy], [x + side, sy], [x + side, sy + side], [x, sy + side]];
        self.push(Item::Marks { marks: vec![hatch::mark(&corners, None)], width: MARK_WIDTH });
        self.text(x + side + 8.0, sy + (side - TEXT as f32) / 2.0, "inverted");
    }

    /// The share of faces in each bin of [`histogram`], input and optimized, below what is there
    /// and as wide as the picture (at least as wide as its labels need): the y axis titled over
    /// its ticks (in percent, from 0 to the largest share rounded up to a tick), the series'
    /// swatches on the title's line, the bins' labels under the bars and the x axis's title
    /// under them. The title and tooltips say "quads" for a quad mesh, "faces" for one with
    /// triangles (`mixed`).
    fn histogram(&mut self, values: &[Vec<f64>; 2], mixed: bool) {
        let (one, many) = face_words(mixed);
        let counts = values.each_ref().map(|v| histogram(v));
        let shares: Vec<[f64; 11]> =
            counts.iter().zip(values).map(|(c, v)| c.map(|n| n as f64 / v.len().max(1) as f64)).collect();
        let largest = shares.iter().flatten().fold(0.0f64, |a, &b| a.max(b));
        let (step, ticks) = ticks(largest);
        let top_share = f64::from(step * ticks) / 100.0;
        let y = self.bottom;
        let title = &format!("share of {many}");
        self.text(MARGIN, y, title);
        // Swatches for the two series, on the title's line, after it.
        let mut sx = MARGIN + text_width(title, TEXT) + 30.0;
        for (name, fill) in [("input", INPUT), ("optimized", OPTIMIZED)] {
            self.push(Item::Rect {
                x: sx,
                y,
                w: TEXT as f32,
                h: TEXT as f32,
                fill,
                stroke: None,
                tooltip: None,
            });
            self.text(sx + TEXT as f32 + 6.0, y, name);
            sx += TEXT as f32 + 6.0 + text_width(name, TEXT) + 20.0;
        }
        let widest = format!("{}%", step * ticks);
        let x0 = MARGIN + text_width(&widest, TEXT) + 14.0;
        let x1 = self.right.max(x0 + 11.0 * 96.0);
        let (y0, y1) = (y + 2.0 * TEXT as f32 + 10.0, y + 2.0 * TEXT as f32 + 10.0 + PLOT);
        let rule = |x: f32, y: f32, w: f32, h: f32, fill: Rgb| Item::Rect {
            x,
            y,
            w,
            h,
            fill,
            stroke: None,
            tooltip: None,
        };
        for t in 0..=ticks {
            let ty = y1 - t as f32 / ticks as f32 * PLOT;
            if t > 0 {
                self.push(rule(x0, ty, x1 - x0, 1.0, Rgb::GRID));
            }
            self.push(rule(x0 - 5.0, ty, 5.0, 1.0, Rgb::BLACK));
            self.push(Item::Text {
                x: x0 - 8.0,
                y: ty - TEXT as f32 / 2.0,
                size: TEXT,
                anchor: Anchor::End,
                text: format!("{}%", step * t),
            });
        }
        let group = (x1 - x0) / 11.0;
        let bar = group * 0.36;
        for (bin, label) in BIN_LABELS.iter().enumerate() {
            let gx = x0 + bin as f32 * group;
            for (series, (name, fill)) in [("input", INPUT), ("optimized", OPTIMIZED)].into_iter().enumerate()
            {
                let share = shares[series][bin];
                let h = ((share / top_share) as f32 * PLOT).max(0.0);
                let range = if bin == 0 { "<=0".to_string() } else { bin_range(bin) };
                self.push(Item::Rect {
                    x: gx + group * 0.14 + series as f32 * bar,
                    y: y1 - h,
                    w: bar,
                    h,
                    fill,
                    stroke: None,
                    tooltip: Some(format!(
                        "{name} {range}: {}",
                        crate::plural::count(counts[series][bin], one, many)
                    )),
                });
            }
            self.push(Item::Text {
                x: gx + group / 2.0,
                y: y1 + 8.0,
                size: TEXT,
                anchor: Anchor::Middle,
                text: label.to_string(),
            });
        }
        // The axes, over the bars' feet.
        self.push(rule(x0, y1, x1 - x0, 1.0, Rgb::BLACK));
        self.push(rule(x0, y0, 1.0, PLOT + 1.0, Rgb::BLACK));
        self.push(Item::Text {
            x: (x0 + x1) / 2.0,
            y: y1 + 8.0 + TEXT as f32 + 10.0,
            size: TEXT,
            anchor: Anchor::Middle,
            text: "scaled Jacobian (<=0: inverted)".to_string(),
        });
    }

    fn finish(self) -> Picture {
        Picture {
            width: (self.right + MARGIN).ceil() as u32,
            height: (self.bottom + MARGIN).ceil() as u32,
            items: self.items,
        }
    }
}

/// The histogram's ticks for a largest share of `largest` (in [0, 1]): the step in percent
/// and the number of steps, the first of [`TICK_STEPS`] that reaches `largest` in at most
/// [`MAX_TICK_STEPS`] steps (at least one step).
fn ticks(largest: f64) -> (u32, u32) {
    let percent = largest.clamp(0.0, 1.0) * 100.0;
    // A share a rounding error above a tick (0.6 as 60.000000000000007 %) stays at that tick.
    let steps = |step: u32| ((percent / f64::from(step) - 1e-9).ceil() as u32).max(1);
    let step = TICK_STEPS.into_iter().find(|&s| steps(s) <= MAX_TICK_STEPS).unwrap_or(TICK_STEPS[3]);
    (step, steps(step))
}

/// "quads: min 0.500  avg 0.900", or "triangles: none".
fn kind_line(name: &str, s: Option<QualityStats>) -> String {
    s.map_or(format!("{name}: none"), |s| format!("{name}: min {:.3}  avg {:.3}", s.min, s.avg))
}

/// "(a, b]" for bin `bin` >= 1 of [`histogram`].
fn bin_range(bin: usize) -> String {
    format!("({:.1}, {:.1}]", (bin - 1) as f64 / 10.0, bin as f64 / 10.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn jittered_grid(n: u32) -> Mesh {
        let mut points = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                let inner = i > 0 && j > 0 && i < n && j < n;
                let d = if inner { 0.45 * ((i * 7 + j * 3) as f64).sin() } else { 0.0 };
                points.push(DVec2::new(i as f64 + d, j as f64 * 2.0 - d));
            }
        }
        let mut quads = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let v = j * (n + 1) + i;
                quads.push([v, v + 1, v + n + 2, v + n + 1]);
            }
        }
        Mesh::new(points, quads, None).unwrap()
    }

    fn assert_inside(p: &Picture) {
        for item in &p.items {
            let (l, t, r, b) = item.bounds();
            assert!(
                l >= 0.0 && t >= 0.0 && r <= p.width as f32 && b <= p.height as f32,
                "{item:?} outside {}x{}",
                p.width,
                p.height
            );
        }
    }

    #[test]
    fn every_item_is_inside_the_frame() {
        let m = jittered_grid(6);
        assert_inside(&single(&m, "a title long enough to be wider than the mesh and its legend together"));
        assert_inside(&single(&m, "t"));
        assert_inside(&before_after(&m, &m, "t", ["before", "after"]));
        // A tall thin mesh: the histogram is wider than the panels.
        let tall = Mesh::new(
            vec![DVec2::new(0.0, 0.0), DVec2::new(0.1, 0.0), DVec2::new(0.1, 10.0), DVec2::new(0.0, 10.0)],
            vec![[0, 1, 2, 3]],
            None,
        )
        .unwrap();
        assert_inside(&before_after(&tall, &tall, "t", ["before", "after"]));
    }

    /// A 2x2 grid whose centre is pushed into the upper right quad, which is inverted.
    fn one_inverted() -> Mesh {
        let mut points: Vec<DVec2> = (0..9).map(|i| DVec2::new(f64::from(i % 3), f64::from(i / 3))).collect();
        points[4] = DVec2::new(1.9, 1.9);
        let quads = vec![[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 7]];
        Mesh::new(points, quads, None).unwrap()
    }

    /// The marks of a picture's mesh panels (those with a tooltip, not the legend's sample).
    fn marks(p: &Picture) -> Vec<&super::super::Mark> {
        p.items
            .iter()
            .filter_map(|i| if let Item::Marks { marks, .. } = i { Some(marks) } else { None })
            .flatten()
            .filter(|m| m.tooltip.is_some())
            .collect()
    }

    #[test]
    fn every_inverted_quad_is_marked_and_no_other() {
        let m = one_inverted();
        let values = m.quality_values();
        let inverted: Vec<usize> = (0..values.len()).filter(|&q| values[q] <= 0.0).collect();
        assert_eq!(inverted, [3], "{values:?}");
        let p = single(&m, "t");
        let marks = marks(&p);
        assert_eq!(marks.len(), 1);
        assert_eq!(marks[0].tooltip.as_deref(), Some(format!("inverted: {:.4}", values[3]).as_str()));
        assert!(!marks[0].hatch.is_empty());
        // The mark is the inverted quad's outline, drawn after (over) the quads.
        let quads = p.items.iter().position(|i| matches!(i, Item::Faces { .. })).unwrap();
        let Item::Faces { faces: drawn, .. } = &p.items[quads] else { unreachable!() };
        assert_eq!(marks[0].outline, drawn[3].corners());
        assert!(p.items[quads + 1..].iter().any(|i| matches!(i, Item::Marks { .. })));
        // Before and after: the marks of both panels; a valid mesh has none but the legend's.
        assert_eq!(self::marks(&before_after(&m, &m, "t", ["a", "b"])).len(), 2);
        assert!(self::marks(&single(&jittered_grid(4), "t")).is_empty());
        assert_inside(&p);
    }

    #[test]
    fn the_histogram_axis_ticks_reach_the_largest_share_in_at_most_five_steps() {
        assert_eq!(ticks(0.7), (20, 4));
        assert_eq!(ticks(0.6), (20, 3));
        assert_eq!(ticks(1.0), (20, 5));
        assert_eq!(ticks(0.5), (10, 5));
        assert_eq!(ticks(0.25), (5, 5));
        assert_eq!(ticks(0.26), (10, 3));
        assert_eq!(ticks(0.1), (2, 5));
        assert_eq!(ticks(1.0 / 11.0), (2, 5));
        assert_eq!(ticks(0.0), (2, 1));
        for k in 1..=1000 {
            let share = f64::from(k) / 1000.0;
            let (step, n) = ticks(share);
            assert!(n <= 5 && f64::from(step * n) >= share * 100.0 - 1e-9, "{share}: {step} x {n}");
        }
    }

    /// A 2x2 grid whose upper right quad is split into two triangles, the centre pushed across
    /// the split quad's right edge, which inverts the triangle (4, 5, 8).
    fn mixed_with_an_inverted_triangle() -> Mesh {
        let mut points: Vec<DVec2> = (0..9).map(|i| DVec2::new(f64::from(i % 3), f64::from(i / 3))).collect();
        points[4] = DVec2::new(2.2, 1.5);
        let faces =
            vec![[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], face::triangle(4, 5, 8), face::triangle(4, 8, 7)];
        Mesh::with_faces(points, faces, None).unwrap()
    }

    #[test]
    fn triangles_are_drawn_and_marked_with_three_corners_and_counted_as_faces() {
        let m = mixed_with_an_inverted_triangle();
        let values = m.quality_values();
        let inverted: Vec<usize> = (0..values.len()).filter(|&f| values[f] <= 0.0).collect();
        assert!(inverted.contains(&3), "{values:?}");
        let p = before_after(&m, &m, "t", ["before", "after"]);
        assert_inside(&p);
        let drawn: Vec<&Face> = p
            .items
            .iter()
            .filter_map(|i| if let Item::Faces { faces, .. } = i { Some(faces) } else { None })
            .flatten()
            .collect();
        let corners: Vec<usize> = drawn.iter().map(|f| f.corners().len()).collect();
        assert_eq!(corners, [4, 4, 4, 3, 3, 4, 4, 4, 3, 3]);
        // Each panel marks each inverted face by its corners as drawn, in the order drawn.
        let marks = marks(&p);
        assert_eq!(marks.len(), 2 * inverted.len());
        let second = inverted.iter().map(|f| f + 5);
        for (mark, f) in marks.iter().zip(inverted.iter().copied().chain(second)) {
            assert_eq!(mark.outline, drawn[f].corners());
            assert!(!mark.hatch.is_empty());
        }
        // Each kind's min and avg under the panels; the histogram's title and tooltips count
        // faces, every face in one bin.
        let texts: Vec<&str> = p
            .items
            .iter()
            .filter_map(|i| if let Item::Text { text, .. } = i { Some(text.as_str()) } else { None })
            .collect();
        let triangles = QualityStats::from_values(&values[3..]);
        let line = format!("triangles: min {:.3}  avg {:.3}", triangles.min, triangles.avg);
        assert_eq!(texts.iter().filter(|t| **t == line).count(), 2, "{line} in {texts:?}");
        assert!(texts.contains(&"share of faces"), "{texts:?}");
        let mut total = 0;
        for item in &p.items {
            if let Item::Rect { tooltip: Some(t), .. } = item {
                let (n, what) = t.rsplit(": ").next().unwrap().split_once(' ').unwrap();
                assert!(what == "faces" || what == "face", "{t}");
                total += n.parse::<usize>().unwrap();
            }
        }
        assert_eq!(total, 10);
    }

    #[test]
    fn both_panels_share_one_scale_and_the_histogram_counts_every_quad() {
        let before = jittered_grid(5);
        let mut after = jittered_grid(5);
        let moved: Vec<DVec2> = after.points().iter().map(|p| *p * 0.5).collect();
        after.set_points(&moved).unwrap();
        let p = before_after(&before, &after, "t", ["before", "after"]);
        let widths: Vec<f32> = p
            .items
            .iter()
            .filter(|i| matches!(i, Item::Faces { .. }))
            .map(Item::bounds)
            .map(|(l, _, r, _)| r - l)
            .collect();
        // The second mesh is half the size of the first, drawn at the same scale.
        assert_eq!(widths.len(), 2);
        assert!((widths[1] / widths[0] - 0.5).abs() < 0.01, "{widths:?}");
        let mut total = [0usize; 2];
        for item in &p.items {
            if let Item::Rect { tooltip: Some(t), .. } = item {
                let n: usize = t.rsplit(": ").next().unwrap().split(' ').next().unwrap().parse().unwrap();
                total[usize::from(t.starts_with("optimized"))] += n;
            }
        }
        assert_eq!(total, [25, 25]);
    }
}
