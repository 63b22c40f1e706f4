//! The marking of an inverted face (quad or triangle): its outline and diagonal hatch lines clipped to it, in
//! picture coordinates, so that an inverted quad never looks like a barely valid one (both are
//! red) and a few of them are easy to find in a large mesh.
//!
//! The hatch lines are the lines `x + y = k * HATCH_SPACING` of the whole picture, so the
//! hatching of neighbouring faces lines up. A face is clipped by the crossing rule (an edge
//! crosses a line when its ends lie strictly on different sides), which gives each line an even
//! number of crossings; pairing them in order along the line gives the parts inside the quad,
//! for a folded (self-intersecting) quad both of its lobes. Faces are drawn with the nonzero
//! fill rule, which for three or four corners fills the same region as this even-odd pairing
//! (a polygon of at most four sides winds at most once around any point).

use super::Mark;

/// Between two hatch lines, along the x axis, in pixels.
pub const HATCH_SPACING: f32 = 5.0;

/// The mark of a face with `corners` (three or four, in picture coordinates); `tooltip` is
/// SVG's `<title>`.
pub fn mark(corners: &[[f32; 2]], tooltip: Option<String>) -> Mark {
    Mark { outline: corners.to_vec(), hatch: hatch(corners, HATCH_SPACING), tooltip }
}

/// The parts of the lines `x + y = k * spacing` inside the face with `corners`.
pub fn hatch(corners: &[[f32; 2]], spacing: f32) -> Vec<[[f32; 2]; 2]> {
    let n = corners.len();
    let u: Vec<f32> = corners.iter().map(|[x, y]| x + y).collect();
    let (lo, hi) = u.iter().fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), &v| (a.min(v), b.max(v)));
    let mut segments = Vec::new();
    if !(lo.is_finite() && hi.is_finite() && spacing > 0.0) {
        return segments;
    }
    // Only the lines strictly inside the face's range: one through a corner at the end of
    // the range would be a point.
    let first = (lo / spacing).floor() as i64 + 1;
    let last = (hi / spacing).ceil() as i64 - 1;
    let mut crossings: Vec<[f32; 2]> = Vec::with_capacity(4);
    for k in first..=last {
        let c = k as f32 * spacing;
        crossings.clear();
        for i in 0..n {
            let j = (i + 1) % n;
            if (u[i] > c) != (u[j] > c) {
                let t = (c - u[i]) / (u[j] - u[i]);
                let [(xi, yi), (xj, yj)] = [i, j].map(|n| (corners[n][0], corners[n][1]));
                crossings.push([xi + t * (xj - xi), yi + t * (yj - yi)]);
            }
        }
        // Along the line, by x - y.
        crossings.sort_by(|a, b| (a[0] - a[1]).total_cmp(&(b[0] - b[1])));
        // A part shorter than a thousandth of a pixel (a line through a corner, or a face
        // of no area) is not drawn.
        let visible = |p: &&[[f32; 2]]| (p[1][0] - p[0][0]).abs() + (p[1][1] - p[0][1]).abs() > 1e-3;
        segments.extend(crossings.chunks_exact(2).filter(visible).map(|p| [p[0], p[1]]));
    }
    segments
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The winding number of `corners` around `p`.
    fn winding(corners: &[[f32; 2]], p: [f32; 2]) -> i32 {
        let mut w = 0;
        let n = corners.len();
        for i in 0..n {
            let (a, b) = (corners[i], corners[(i + 1) % n]);
            let cross = (b[0] - a[0]) * (p[1] - a[1]) - (p[0] - a[0]) * (b[1] - a[1]);
            if a[1] <= p[1] && b[1] > p[1] && cross > 0.0 {
                w += 1;
            } else if a[1] > p[1] && b[1] <= p[1] && cross < 0.0 {
                w -= 1;
            }
        }
        w
    }

    /// The distance from `p` to the nearest edge of `corners`.
    fn to_boundary(corners: &[[f32; 2]], p: [f32; 2]) -> f32 {
        let n = corners.len();
        (0..n)
            .map(|i| {
                let (a, b) = (corners[i], corners[(i + 1) % n]);
                let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
                let len2 = (dx * dx + dy * dy).max(f32::MIN_POSITIVE);
                let t = (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2).clamp(0.0, 1.0);
                ((p[0] - a[0] - t * dx).powi(2) + (p[1] - a[1] - t * dy).powi(2)).sqrt()
            })
            .fold(f32::INFINITY, f32::min)
    }

    /// Every segment lies inside the face, and the segments cover its part of each line.
    fn check(corners: &[[f32; 2]], spacing: f32) -> Vec<[[f32; 2]; 2]> {
        let segments = hatch(corners, spacing);
        for s in &segments {
            for t in [0.01, 0.5, 0.99] {
                let p = [s[0][0] + t * (s[1][0] - s[0][0]), s[0][1] + t * (s[1][1] - s[0][1])];
                assert_ne!(winding(corners, p), 0, "{p:?} of {s:?} outside {corners:?}");
            }
        }
        // Points on the hatch lines inside the quad (off its edges) lie on a segment.
        for k in -100..100 {
            let c = k as f32 * spacing;
            for step in 0..200 {
                let x = -50.0 + step as f32 * 0.5;
                let p = [x, c - x];
                if winding(corners, p) != 0 && to_boundary(corners, p) > 1e-3 {
                    let on = segments.iter().any(|s| {
                        let (a, b) = (s[0][0].min(s[1][0]), s[0][0].max(s[1][0]));
                        (s[0][0] + s[0][1] - c).abs() < 1e-3 && (a - 1e-3..=b + 1e-3).contains(&x)
                    });
                    assert!(on, "{p:?} inside {corners:?} is on no segment");
                }
            }
        }
        segments
    }

    #[test]
    fn a_square_is_hatched_by_the_lines_strictly_inside_it() {
        let square = [[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]];
        let s = check(&square, 5.0);
        // x + y = 5, 10, 15; not the corners' lines 0 and 20.
        assert_eq!(s.len(), 3);
        assert_eq!(s[1], [[0.0, 10.0], [10.0, 0.0]]);
        // Either orientation gives the same lines.
        let mut reversed = square;
        reversed.reverse();
        assert_eq!(check(&reversed, 5.0).len(), 3);
    }

    #[test]
    fn a_triangle_is_hatched_inside_its_three_edges() {
        // The lines x + y = 5 and 10 cross the right triangle (0,0), (10,0), (0,10)... and
        // x + y = 10 is its hypotenuse: only x + y = 5 is strictly inside.
        let s = check(&[[0.0, 0.0], [10.0, 0.0], [0.0, 10.0]], 5.0);
        assert_eq!(s.len(), 1);
        let [[xa, ya], [xb, yb]] = s[0];
        assert_eq!((xa + ya, xb + yb), (5.0, 5.0));
        assert!(((xb - xa).abs() - 5.0).abs() < 1e-4, "{s:?}");
        // A finer spacing: three lines, each ending on the legs.
        let s = check(&[[0.0, 0.0], [10.0, 0.0], [0.0, 10.0]], 2.5);
        assert_eq!(s.len(), 3);
    }

    #[test]
    fn a_folded_quad_is_hatched_in_both_lobes_and_a_concave_one_in_two_parts() {
        let bowtie = [[0.0, 0.0], [10.0, 10.0], [10.0, 0.0], [0.0, 10.0]];
        let s = check(&bowtie, 2.0);
        assert!(s.len() > 4);
        let arrow = [[0.0, 0.0], [10.0, 10.0], [0.0, 4.0], [-10.0, 10.0]];
        let s = check(&arrow, 1.5);
        assert!(s.len() > 4);
        // A degenerate quad (a segment) has nothing inside.
        assert!(hatch(&[[0.0, 0.0], [4.0, 0.0], [8.0, 0.0], [2.0, 0.0]], 1.0).is_empty());
        assert!(hatch(&[[f32::NAN, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]], 1.0).is_empty());
    }
}
