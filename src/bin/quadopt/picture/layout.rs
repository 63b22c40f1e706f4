//! Where things go: the mesh panels on one scale, their captions, the legend to their right,
//! and (before/after) the histogram underneath, every item inside the frame.

use super::{Anchor, BIN_LABELS, Item, Picture, Quad, Rgb, TEXT, histogram, text_width};
use glam::DVec2;
use quadopt::{QuadMesh, QualityStats};

const MARGIN: f32 = 20.0;
/// Between two panels.
const GAP: f32 = 40.0;
/// The colour bar's height and width.
const BAR: (f32, f32) = (200.0, 20.0);
/// The histogram's series.
const INPUT: Rgb = Rgb(150, 150, 150);
const OPTIMIZED: Rgb = Rgb(60, 110, 180);

/// One mesh and its title line.
pub fn single(mesh: &QuadMesh, title: &str) -> Picture {
    let mut p = Builder::new(title);
    let panels = p.panels(&[mesh], 800.0);
    p.legend(panels.right + GAP, panels.top);
    p.finish()
}

/// The input (`before`) and the optimized mesh (`after`) side by side on one scale and one
/// colour scale, each headed and with its min / avg / inverted underneath, and the histogram
/// of both below.
pub fn before_after(before: &QuadMesh, after: &QuadMesh, title: &str, headings: [&str; 2]) -> Picture {
    let mut p = Builder::new(title);
    let values = [before.quality_values(), after.quality_values()];
    let heading_top = p.bottom + 14.0;
    p.bottom = heading_top + TEXT as f32 + 8.0;
    let panels = p.panels(&[before, after], 560.0);
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
    }
    p.legend(panels.right + GAP, panels.top);
    p.bottom = p.bottom.max(bottom) + 30.0;
    p.histogram(&values);
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
    fn panels(&mut self, meshes: &[&QuadMesh], size: f64) -> Panels {
        let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        for m in meshes {
            let points = m.points();
            for &v in m.quads().iter().flatten() {
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
            let points = m.points();
            let map = |p: DVec2| [x0 + ((p.x - lo.x) * scale) as f32, top + ((hi.y - p.y) * scale) as f32];
            let quads = m
                .quads()
                .iter()
                .zip(m.quality_values())
                .map(|(q, sj)| Quad { corners: q.map(|v| map(points[v as usize])), sj: sj as f32 })
                .collect();
            let stroke = 0.6f64.min(0.15 * size / (m.quads().len() as f64).sqrt().max(1.0)) as f32;
            self.push(Item::Quads { quads, stroke });
        }
        let right = MARGIN + meshes.len() as f32 * (w + GAP) - GAP;
        self.right = self.right.max(right);
        self.bottom = self.bottom.max(top + h);
        Panels { left, top, right, bottom: top + h }
    }

    /// The colour scale, its title over it, at (`x`, `y`).
    fn legend(&mut self, x: f32, y: f32) {
        self.text(x, y, "scaled");
        self.text(x, y + TEXT as f32 + 4.0, "Jacobian");
        let top = y + 2.0 * TEXT as f32 + 16.0;
        self.push(Item::ColourBar { x, y: top, w: BAR.1, h: BAR.0 });
        for (v, label) in [(1.0, "1"), (0.5, "0.5"), (0.0, "0"), (-0.5, "-0.5"), (-1.0, "-1")] {
            let tick = top + (1.0 - v) / 2.0 * BAR.0;
            self.text(x + BAR.1 + 8.0, tick - TEXT as f32 / 2.0, label);
        }
    }

    /// The share of quads in each bin of [`histogram`], input and optimized, below what is there
    /// and as wide as the picture (at least as wide as its labels need).
    fn histogram(&mut self, values: &[Vec<f64>; 2]) {
        let counts = values.each_ref().map(|v| histogram(v));
        let shares: Vec<[f64; 11]> =
            counts.iter().zip(values).map(|(c, v)| c.map(|n| n as f64 / v.len().max(1) as f64)).collect();
        // The axis's top: the largest share rounded up to 10%.
        let top_share =
            (shares.iter().flatten().fold(0.0f64, |a, &b| a.max(b)) * 10.0).ceil().max(1.0) / 10.0;
        let y = self.bottom;
        let heading = "share of quads by scaled Jacobian (<=0: inverted)";
        self.text(MARGIN, y, heading);
        // Swatches for the two series, on the heading's line, after it.
        let mut sx = MARGIN + text_width(heading, TEXT) + 30.0;
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
        let axis_label = format!("{:.0}%", top_share * 100.0);
        let x0 = MARGIN + text_width(&axis_label, TEXT) + 10.0;
        let x1 = self.right.max(x0 + 11.0 * 96.0);
        let (y0, y1) = (y + 2.0 * TEXT as f32 + 10.0, y + 2.0 * TEXT as f32 + 170.0);
        self.text(MARGIN, y0 - TEXT as f32 / 2.0, &axis_label);
        self.text(MARGIN, y1 - TEXT as f32 / 2.0, &format!("{:>w$}", "0%", w = axis_label.len()));
        self.push(Item::Rect {
            x: x0,
            y: y1,
            w: x1 - x0,
            h: 1.0,
            fill: Rgb::BLACK,
            stroke: None,
            tooltip: None,
        });
        let group = (x1 - x0) / 11.0;
        let bar = group * 0.36;
        for (bin, label) in BIN_LABELS.iter().enumerate() {
            let gx = x0 + bin as f32 * group;
            for (series, (name, fill)) in [("input", INPUT), ("optimized", OPTIMIZED)].into_iter().enumerate()
            {
                let share = shares[series][bin];
                let h = ((share / top_share) as f32 * (y1 - y0)).max(0.0);
                let range = if bin == 0 { "<=0".to_string() } else { bin_range(bin) };
                self.push(Item::Rect {
                    x: gx + group * 0.14 + series as f32 * bar,
                    y: y1 - h,
                    w: bar,
                    h,
                    fill,
                    stroke: None,
                    tooltip: Some(format!("{name} {range}: {} quads", counts[series][bin])),
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
    }

    fn finish(self) -> Picture {
        Picture {
            width: (self.right + MARGIN).ceil() as u32,
            height: (self.bottom + MARGIN).ceil() as u32,
            items: self.items,
        }
    }
}

/// "(a, b]" for bin `bin` >= 1 of [`histogram`].
fn bin_range(bin: usize) -> String {
    format!("({:.1}, {:.1}]", (bin - 1) as f64 / 10.0, bin as f64 / 10.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn jittered_grid(n: u32) -> QuadMesh {
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
        QuadMesh::new(points, quads, None).unwrap()
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
        let tall = QuadMesh::new(
            vec![DVec2::new(0.0, 0.0), DVec2::new(0.1, 0.0), DVec2::new(0.1, 10.0), DVec2::new(0.0, 10.0)],
            vec![[0, 1, 2, 3]],
            None,
        )
        .unwrap();
        assert_inside(&before_after(&tall, &tall, "t", ["before", "after"]));
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
            .filter(|i| matches!(i, Item::Quads { .. }))
            .map(Item::bounds)
            .map(|(l, _, r, _)| r - l)
            .collect();
        // The second mesh is half the size of the first, drawn at the same scale.
        assert_eq!(widths.len(), 2);
        assert!((widths[1] / widths[0] - 0.5).abs() < 0.01, "{widths:?}");
        let mut total = [0usize; 2];
        for item in &p.items {
            if let Item::Rect { tooltip: Some(t), .. } = item {
                let n: usize = t.rsplit(": ").next().unwrap().trim_end_matches(" quads").parse().unwrap();
                total[usize::from(t.starts_with("optimized"))] += n;
            }
        }
        assert_eq!(total, [25, 25]);
    }
}
