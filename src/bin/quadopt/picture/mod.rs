//! Pictures of quad and quad-dominant meshes, each face (quad or triangle) coloured by its
//! scaled Jacobian (red for 0 and below, white for 1, as in the paper's figures), inverted
//! faces outlined and hatched ([`hatch`]): one mesh
//! ([`layout::single`]), or input and output side by side on one colour scale with a
//! histogram of both ([`layout::before_after`]).
//!
//! A layout builds a [`Picture`], a display list in pixels; [`svg`] and [`png`] render the same
//! list, so both formats show the same thing. Text is measured with the PNG renderer's 8x8
//! bitmap font (a glyph cell of `size` pixels a character); SVG's monospace glyphs are
//! narrower, so a layout that keeps every item inside the frame keeps it there in both.

pub mod hatch;
pub mod layout;
pub mod png;
pub mod surface;
pub mod svg;

/// An sRGB colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rgb(pub u8, pub u8, pub u8);

impl Rgb {
    pub const BLACK: Rgb = Rgb(0, 0, 0);
    pub const EDGE: Rgb = Rgb(0x55, 0x55, 0x55);
    /// The outline and hatching of inverted faces.
    pub const MARK: Rgb = Rgb::BLACK;
    /// The histogram's grid lines.
    pub const GRID: Rgb = Rgb(0xdd, 0xdd, 0xdd);
}

/// Whether a face of scaled Jacobian `sj` is inverted: at or below 0 (as
/// [`quadopt::QualityStats::inverted`] counts), or NaN.
pub fn is_inverted(sj: f64) -> bool {
    sj <= 0.0 || sj.is_nan()
}

/// The fill colour of a scaled Jacobian: dark red at -1, red at 0, white at 1.
pub fn colour(sj: f64) -> Rgb {
    let sj = if sj.is_finite() { sj.clamp(-1.0, 1.0) } else { -1.0 };
    if sj >= 0.0 {
        let c = (255.0 * sj).round() as u8;
        Rgb(255, c, c)
    } else {
        Rgb((255.0 - 127.0 * -sj).round() as u8, 0, 0)
    }
}

/// One face of a mesh panel, a quad or a triangle, in picture coordinates (y down).
#[derive(Clone, Copy, Debug)]
pub struct Face {
    /// The corners; a triangle's fourth is unused.
    corners: [[f32; 2]; 4],
    /// 3 or 4.
    len: u8,
    /// Its scaled Jacobian (the fill colour, and the SVG tooltip).
    pub sj: f32,
}

impl Face {
    /// A quad (four `corners`) or a triangle (three).
    pub fn new(corners: &[[f32; 2]], sj: f32) -> Face {
        assert!(matches!(corners.len(), 3 | 4), "a face has 3 or 4 corners, not {}", corners.len());
        let mut c = [corners[0]; 4];
        c[..corners.len()].copy_from_slice(corners);
        Face { corners: c, len: corners.len() as u8, sj }
    }

    /// Its corners, in order: three for a triangle, four for a quad.
    pub fn corners(&self) -> &[[f32; 2]] {
        &self.corners[..usize::from(self.len)]
    }
}

/// The marking of an inverted face ([`hatch::mark`]): its outline and the hatch lines inside
/// it, in picture coordinates.
#[derive(Clone, Debug)]
pub struct Mark {
    /// The face's corners (three or four).
    pub outline: Vec<[f32; 2]>,
    pub hatch: Vec<[[f32; 2]; 2]>,
    /// SVG's `<title>` (PNG ignores it); none for the legend's sample.
    pub tooltip: Option<String>,
}

/// Where a text's `x` is: its left end, its centre, or its right end.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Anchor {
    Start,
    Middle,
    End,
}

/// One thing drawn, in the order given (later items over earlier ones).
#[derive(Clone, Debug)]
pub enum Item {
    /// A mesh: every face filled by its colour, edges `stroke` pixels wide.
    Faces { faces: Vec<Face>, stroke: f32 },
    /// Inverted faces' marks, outline and hatch lines `width` pixels wide in [`Rgb::MARK`].
    Marks { marks: Vec<Mark>, width: f32 },
    /// A rectangle; `tooltip` is SVG's `<title>` (PNG ignores it).
    Rect { x: f32, y: f32, w: f32, h: f32, fill: Rgb, stroke: Option<Rgb>, tooltip: Option<String> },
    /// The colour scale from 1 at the top to -1 at the bottom.
    ColourBar { x: f32, y: f32, w: f32, h: f32 },
    /// One line of ASCII text whose glyph cells are `size` pixels square, `y` its top.
    Text { x: f32, y: f32, size: u32, anchor: Anchor, text: String },
}

/// A display list and its frame, in pixels.
#[derive(Clone, Debug)]
pub struct Picture {
    pub width: u32,
    pub height: u32,
    pub items: Vec<Item>,
}

/// The size of text, in pixels a glyph cell (a multiple of 8: the font's cells are 8x8).
pub const TEXT: u32 = 16;

/// The width of `text` in glyph cells of `size` pixels.
pub fn text_width(text: &str, size: u32) -> f32 {
    (text.chars().count() as u32 * size) as f32
}

impl Item {
    /// The box the item covers: (left, top, right, bottom).
    pub fn bounds(&self) -> (f32, f32, f32, f32) {
        match self {
            Item::Faces { faces, stroke } => {
                let mut b = (f32::INFINITY, f32::INFINITY, f32::NEG_INFINITY, f32::NEG_INFINITY);
                for p in faces.iter().flat_map(|f| f.corners().iter().copied()) {
                    b = (b.0.min(p[0]), b.1.min(p[1]), b.2.max(p[0]), b.3.max(p[1]));
                }
                let s = stroke / 2.0;
                (b.0 - s, b.1 - s, b.2 + s, b.3 + s)
            }
            Item::Marks { marks, width } => {
                let mut b = (f32::INFINITY, f32::INFINITY, f32::NEG_INFINITY, f32::NEG_INFINITY);
                for p in marks.iter().flat_map(|m| m.outline.iter().copied()) {
                    b = (b.0.min(p[0]), b.1.min(p[1]), b.2.max(p[0]), b.3.max(p[1]));
                }
                let s = width / 2.0;
                (b.0 - s, b.1 - s, b.2 + s, b.3 + s)
            }
            Item::Rect { x, y, w, h, .. } | Item::ColourBar { x, y, w, h } => (*x, *y, x + w, y + h),
            Item::Text { x, y, size, anchor, text } => {
                let w = text_width(text, *size);
                let left = anchor.left(*x, w);
                (left, *y, left + w, y + *size as f32)
            }
        }
    }
}

impl Anchor {
    /// The left end of a text `width` pixels wide anchored at `x`.
    pub fn left(self, x: f32, width: f32) -> f32 {
        match self {
            Anchor::Start => x,
            Anchor::Middle => x - width / 2.0,
            Anchor::End => x - width,
        }
    }
}

/// The faces of `values` by their bins (the library's, which `quality` prints and reports).
pub use quadopt::quality::histogram;

/// The labels of [`histogram`]'s bins.
pub const BIN_LABELS: [&str; 11] =
    ["<=0", "0-.1", ".1-.2", ".2-.3", ".3-.4", ".4-.5", ".5-.6", ".6-.7", ".7-.8", ".8-.9", ".9-1"];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn histogram_bins_as_the_inverted_count_and_tenths() {
        let values = [-0.5, 0.0, 1e-9, 0.099, 0.1, 0.10001, 0.25, 0.95, 0.999, 1.0, f64::NAN];
        let h = histogram(&values);
        assert_eq!(h, [3, 3, 1, 1, 0, 0, 0, 0, 0, 0, 3]);
        assert_eq!(h.iter().sum::<usize>(), values.len());
        assert_eq!(h[0], quadopt::QualityStats::from_values(&values[..10]).inverted + 1);
    }

    #[test]
    fn a_face_keeps_three_or_four_corners() {
        let t = Face::new(&[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]], 0.5);
        assert_eq!(t.corners(), [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]);
        let q = Face::new(&[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]], 1.0);
        assert_eq!(q.corners().len(), 4);
        let faces = vec![t, q];
        let (l, t, r, b) = Item::Faces { faces, stroke: 0.0 }.bounds();
        assert_eq!((l, t, r, b), (0.0, 0.0, 1.0, 1.0));
    }

    #[test]
    fn colours_run_from_dark_red_through_red_to_white() {
        assert_eq!(colour(-1.0), Rgb(128, 0, 0));
        assert_eq!(colour(0.0), Rgb(255, 0, 0));
        assert_eq!(colour(0.5), Rgb(255, 128, 128));
        assert_eq!(colour(1.0), Rgb(255, 255, 255));
        assert_eq!(colour(f64::NAN), colour(-1.0));
    }
}
