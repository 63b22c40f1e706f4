//! The reference surface: the input faces triangulated, frozen for a run, and the exact
//! closest point on it.

use glam::DVec3;

use super::bvh::{Bvh, squared_length};
use crate::alloc::{out_of_memory, try_copy, try_with_capacity};
use crate::error::{Error, Result};
use crate::face::{self, Face};

/// The closest point of a [`ReferenceSurface`] to a query point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Closest {
    /// The closest point on the surface.
    pub point: DVec3,
    /// The triangle it lies on: its index in [`ReferenceSurface::triangles`]. Of several
    /// triangles at the same distance (a point on a shared edge), the lowest index.
    pub triangle: u32,
    /// The input face that triangle came from (0-based, in the order the faces were given).
    pub face: u32,
    /// The distance from the query point to `point`.
    pub distance: f64,
}

/// Which feature of a triangle the closest point lies on: the Voronoi regions of Ericson's
/// "Real-Time Collision Detection", 5.1.5, plus the degenerate case.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TriangleRegion {
    /// The first vertex, `a`.
    VertexA,
    /// The second vertex, `b`.
    VertexB,
    /// The third vertex, `c`.
    VertexC,
    /// The inside of edge `ab`.
    EdgeAB,
    /// The inside of edge `bc`.
    EdgeBC,
    /// The inside of edge `ca`.
    EdgeCA,
    /// The inside of the triangle (the point's projection onto its plane).
    Interior,
    /// The triangle has no area (its cross product is zero): the closest point of its three
    /// edges, as segments.
    Degenerate,
}

/// The input surface, triangulated and frozen: every moved vertex of a mesh on a curved
/// surface is put back on it, at its closest point.
///
/// A triangle is taken as it is; a quad `[a, b, c, d]` is split along the diagonal whose two
/// triangles' normals make the smaller angle (`a-c` into `[a, b, c]`, `[a, c, d]`; `b-d` into
/// `[a, b, d]`, `[b, c, d]`), `a-c` unless `b-d` is better by more than 1e-12 radians (so a
/// planar convex quad is split along `a-c`). For a non-planar quad this choice defines the
/// surface: it is the flatter of the two folds, and for a planar non-convex quad the one
/// diagonal that lies inside it. A split with a zero-area triangle counts as the worst (its
/// angle is pi). Triangles keep the faces' orientation and are numbered in face order.
///
/// Queries take `&self` and the type is `Send + Sync`; a query's result depends only on the
/// surface and the query point, never on the order of traversal or the thread it runs on.
#[derive(Clone, Debug)]
pub struct ReferenceSurface {
    points: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
    /// The input face of each triangle.
    faces: Vec<u32>,
    /// The triangle across each edge of each triangle (edge `k` from corner `k` to `k + 1`),
    /// [`NO_TRIANGLE`] at a border or an edge shared by more than two triangles: what the
    /// local walk of [`closest_point_near`](Self::closest_point_near) moves along.
    neighbours: Vec<[u32; 3]>,
    /// Per triangle, which side of its plane each neighbour's third corner is on: bit `k` for
    /// neighbour `k` strictly above (the normal's side), bit `k + 3` strictly below. The
    /// walk's test of which neighbours rise towards a point, without loading them.
    rises: Vec<u8>,
    bvh: Bvh,
}

/// No triangle: a border edge's neighbour, or a hint that is none.
pub const NO_TRIANGLE: u32 = u32::MAX;

/// Steps of the local walk before it hands the query to the tree.
const MAX_WALK: usize = 64;

/// Triangles around one vertex the local walk looks at, at most (a larger fan is cut there).
const MAX_FAN: usize = 64;

/// The angle (0 to pi) between the normals of triangles `t` and `u`; pi if either has no
/// area.
fn normal_angle(points: &[DVec3], t: [u32; 3], u: [u32; 3]) -> f64 {
    let n = |t: [u32; 3]| {
        let [a, b, c] = t.map(|v| points[v as usize]);
        (b - a).cross(c - a)
    };
    let (m, n) = (n(t), n(u));
    if squared_length(m) == 0.0 || squared_length(n) == 0.0 {
        return std::f64::consts::PI;
    }
    m.cross(n).length().atan2(m.dot(n))
}

/// How much better (in radians) the `b-d` split of a quad must be to be chosen over `a-c`.
const SPLIT_TOLERANCE: f64 = 1e-12;

/// The two triangles of quad `q`, as the type's documentation describes.
fn split_quad(points: &[DVec3], q: &Face) -> [[u32; 3]; 2] {
    let [a, b, c, d] = *q;
    let ac = [[a, b, c], [a, c, d]];
    let bd = [[a, b, d], [b, c, d]];
    let angle_ac = normal_angle(points, ac[0], ac[1]);
    let angle_bd = normal_angle(points, bd[0], bd[1]);
    if angle_bd < angle_ac - SPLIT_TOLERANCE { bd } else { ac }
}

impl ReferenceSurface {
    /// The surface of `faces` (triangles and quads, as [`crate::face`] stores them) over
    /// `points`, triangulated and with its bounding-volume hierarchy built.
    ///
    /// Errors: no faces ([`Error::NoQuads`]); a non-finite coordinate of any point
    /// ([`Error::NonFiniteCoordinate`]); a corner that is not a vertex
    /// ([`Error::IndexOutOfRange`], which also catches [`face::NO_VERTEX`] in one of the first
    /// three slots); a face using a vertex twice ([`Error::RepeatedVertex`]); memory
    /// ([`Error::OutOfMemory`]). Faces with no area are accepted: their triangles are
    /// degenerate, and the query handles them as segments.
    pub fn new(points: &[DVec3], faces: &[Face]) -> Result<ReferenceSurface> {
        if faces.is_empty() {
            return Err(Error::NoQuads);
        }
        if let Some(vertex) = points.iter().position(|p| !p.is_finite()) {
            return Err(Error::NonFiniteCoordinate { vertex });
        }
        for (i, f) in faces.iter().enumerate() {
            let corners = face::vertices(f);
            for (k, &v) in corners.iter().enumerate() {
                if v as usize >= points.len() {
                    return Err(Error::IndexOutOfRange {
                        quad: i,
                        corner: k,
                        index: v as u64,
                        vertex_count: points.len(),
                    });
                }
                if corners[..k].contains(&v) {
                    return Err(Error::RepeatedVertex { quad: i, vertex: v });
                }
            }
        }
        // Triangle and face numbers are u32.
        if faces.len() > (u32::MAX / 2) as usize {
            return Err(out_of_memory::<[u32; 3]>("reference triangles", faces.len().saturating_mul(2)));
        }
        let count = faces.iter().map(|f| if face::is_triangle(f) { 1 } else { 2 }).sum();
        let mut triangles = try_with_capacity(count, "reference triangles")?;
        let mut of_face = try_with_capacity(count, "reference triangle faces")?;
        for (i, f) in faces.iter().enumerate() {
            if face::is_triangle(f) {
                triangles.push([f[0], f[1], f[2]]);
                of_face.push(i as u32);
            } else {
                triangles.extend_from_slice(&split_quad(points, f));
                of_face.extend_from_slice(&[i as u32, i as u32]);
            }
        }
        let points = try_copy(points, "reference points")?;
        let bvh = Bvh::new(&points, &triangles)?;
        let neighbours = edge_neighbours(&triangles)?;
        let mut rises = try_with_capacity(triangles.len(), "reference neighbour sides")?;
        rises.extend((0..triangles.len()).map(|t| neighbour_sides(&points, &triangles, &neighbours, t)));
        Ok(ReferenceSurface { points, triangles, faces: of_face, neighbours, rises, bvh })
    }

    /// The vertices, as given.
    pub fn points(&self) -> &[DVec3] {
        &self.points
    }

    /// The triangles, counter-clockwise as their faces were, in face order (a quad's two
    /// triangles one after the other).
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// The number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// The input face that triangle `t` came from.
    pub fn triangle_face(&self, t: u32) -> u32 {
        self.faces[t as usize]
    }

    /// The corners of triangle `t`.
    pub fn triangle_corners(&self, t: u32) -> [DVec3; 3] {
        self.triangles[t as usize].map(|v| self.points[v as usize])
    }

    /// The unit normal of triangle `t` (right-handed with its corners' order), or zero if it
    /// has no area.
    pub fn triangle_normal(&self, t: u32) -> DVec3 {
        let [a, b, c] = self.triangle_corners(t);
        (b - a).cross(c - a).normalize_or_zero()
    }

    /// The closest point of the surface to `p`. Of triangles at the same (computed)
    /// distance, the lowest-numbered wins, so the answer is that of
    /// [`closest_point_exhaustive`](Self::closest_point_exhaustive) exactly. A `p` with a
    /// coordinate that is not finite gives a NaN point and distance (at triangle 0), never a
    /// panic.
    pub fn closest_point(&self, p: DVec3) -> Closest {
        if !p.is_finite() {
            return self.not_finite();
        }
        let (d2, t, q) = self.bvh.closest(p, None);
        self.closest(d2, t, q)
    }

    /// [`closest_point`](Self::closest_point), starting from triangle `hint` (e.g. the one a
    /// vertex was on before it moved a little): its distance bounds the search from the start,
    /// so fewer boxes are opened. The answer is the same whatever the hint; a hint that is
    /// not a triangle is ignored.
    pub fn closest_point_from(&self, p: DVec3, hint: u32) -> Closest {
        if !p.is_finite() {
            return self.not_finite();
        }
        let start = self.triangles.get(hint as usize).map(|_| {
            let [a, b, c] = self.triangle_corners(hint);
            let (q, _) = closest_point_on_triangle(p, a, b, c);
            (squared_length(p - q), hint, q)
        });
        let (d2, t, q) = self.bvh.closest(p, start);
        self.closest(d2, t, q)
    }

    /// A closest point of the surface near triangle `hint`: from `hint`, the walk moves to the
    /// neighbouring triangle (across the edge, or around the vertex, the point lies on; any of
    /// the three when the point is inside the triangle) while that is strictly closer to `p`,
    /// so it ends at a local minimum of the distance, the
    /// closest point of the surface around where it ends. For a point that moved a little
    /// from triangle `hint` (a vertex's candidate position) that is the closest point of the
    /// sheet it is on, at the cost of a few point-triangle tests instead of a descent of the
    /// tree; the global closest point may be another sheet's (a thin wall's other side). A
    /// `hint` that is not a triangle, and a walk longer than 64 steps, take the global query
    /// ([`closest_point_from`](Self::closest_point_from)). The answer depends only on `p` and
    /// `hint`.
    pub fn closest_point_near(&self, p: DVec3, hint: u32) -> Closest {
        if !p.is_finite() {
            return self.not_finite();
        }
        if hint as usize >= self.triangles.len() {
            return self.closest_point(p);
        }
        let test = |t: u32| {
            let [a, b, c] = self.triangle_corners(t);
            let (q, region) = closest_point_on_triangle(p, a, b, c);
            (squared_length(p - q), q, region)
        };
        let (mut t, (mut d2, mut q, mut region)) = (hint, test(hint));
        let mut fan = [NO_TRIANGLE; MAX_FAN];
        for _ in 0..MAX_WALK {
            let corner = match region {
                TriangleRegion::Interior => None,
                TriangleRegion::VertexA => Some(0),
                TriangleRegion::VertexB => Some(1),
                TriangleRegion::VertexC => Some(2),
                TriangleRegion::EdgeAB | TriangleRegion::EdgeBC | TriangleRegion::EdgeCA => None,
                TriangleRegion::Degenerate => None,
            };
            let candidates: &[u32] = match (corner, region) {
                (Some(k), _) => {
                    let n = self.fan(t, self.triangles[t as usize][k], &mut fan);
                    &fan[..n]
                }
                (None, TriangleRegion::EdgeAB) => &self.neighbours[t as usize][..1],
                (None, TriangleRegion::EdgeBC) => &self.neighbours[t as usize][1..2],
                (None, TriangleRegion::EdgeCA) => &self.neighbours[t as usize][2..],
                // Inside the triangle: the neighbours that rise towards `p`. On the concave side
                // of the surface a point projects into the interior of several triangles around
                // its closest one, each a local minimum of its own.
                (None, TriangleRegion::Interior) => {
                    let n = self.rising_neighbours(t, p, &mut fan);
                    &fan[..n]
                }
                // On a degenerate triangle: all three neighbours.
                _ => &self.neighbours[t as usize],
            };
            let mut next: Option<(f64, u32, DVec3, TriangleRegion)> = None;
            for &u in candidates {
                if u == NO_TRIANGLE || u == t {
                    continue;
                }
                let (du, qu, ru) = test(u);
                if du < next.map_or(d2, |(d, ..)| d) {
                    next = Some((du, u, qu, ru));
                }
            }
            match next {
                Some((du, u, qu, ru)) => (d2, t, q, region) = (du, u, qu, ru),
                // No neighbour is closer: a local minimum.
                None => return self.closest(d2, t, q),
            }
        }
        let (d2, t, q) = self.bvh.closest(p, Some((d2, t, q)));
        self.closest(d2, t, q)
    }

    /// The neighbours of triangle `t` whose third corner is strictly on the side of `t`'s
    /// plane that `p` is on, written into `out`; returns how many. Only those can be closer to
    /// a `p` that projects inside `t`: every point of another neighbour is at least as far
    /// from `p` as `t`'s plane is. (The sides are computed once, in `rises`.)
    fn rising_neighbours(&self, t: u32, p: DVec3, out: &mut [u32; MAX_FAN]) -> usize {
        let [a, b, c] = self.triangle_corners(t);
        let side = (b - a).cross(c - a).dot(p - a);
        let rises = self.rises[t as usize];
        let mask = if side > 0.0 {
            rises & 0b111
        } else if side < 0.0 {
            rises >> 3
        } else {
            0
        };
        let mut n = 0;
        for (k, &u) in self.neighbours[t as usize].iter().enumerate() {
            if mask & (1 << k) != 0 {
                out[n] = u;
                n += 1;
            }
        }
        n
    }

    /// The triangles around vertex `x` of triangle `t` (found across the edges at `x`, so a
    /// vertex where the surface is not a disc gives the part of its fan `t` is in), written
    /// into `out`; returns how many.
    fn fan(&self, t: u32, x: u32, out: &mut [u32; MAX_FAN]) -> usize {
        out[0] = t;
        let mut n = 1;
        // Around one way; if that ends at a border rather than back at `t`, the other way.
        for side in 0..2 {
            let (mut prev, mut cur) = (NO_TRIANGLE, t);
            loop {
                let tri = self.triangles[cur as usize];
                let Some(k) = tri.iter().position(|&v| v == x) else { return n };
                // The two edges at x: k (x to the next corner) and k + 2 (the previous to x).
                let across = self.neighbours[cur as usize];
                let (first, second) = (across[k], across[(k + 2) % 3]);
                let step = match prev {
                    NO_TRIANGLE if side == 0 => first,
                    NO_TRIANGLE => second,
                    _ if first == prev => second,
                    _ => first,
                };
                if step == t {
                    return n;
                }
                if step == NO_TRIANGLE || n == MAX_FAN {
                    break;
                }
                out[n] = step;
                n += 1;
                (prev, cur) = (cur, step);
            }
        }
        n
    }

    /// The closest point by testing every triangle, without the tree: the reference the tests
    /// and benchmarks compare the tree with.
    pub fn closest_point_exhaustive(&self, p: DVec3) -> Closest {
        if !p.is_finite() {
            return self.not_finite();
        }
        let mut best = (f64::INFINITY, u32::MAX, DVec3::ZERO);
        for t in 0..self.triangles.len() as u32 {
            let [a, b, c] = self.triangle_corners(t);
            let (q, _) = closest_point_on_triangle(p, a, b, c);
            let d2 = squared_length(p - q);
            // The first triangle wins a tie (the tree's rule), also one at infinity.
            if d2 < best.0 || (d2 == best.0 && best.1 == u32::MAX) {
                best = (d2, t, q);
            }
        }
        self.closest(best.0, best.1, best.2)
    }

    /// The answer to a query from a non-finite point: NaN at triangle 0.
    fn not_finite(&self) -> Closest {
        Closest { point: DVec3::NAN, triangle: 0, face: self.faces[0], distance: f64::NAN }
    }

    /// The answer for the best `(squared distance, triangle, point)`.
    fn closest(&self, d2: f64, t: u32, q: DVec3) -> Closest {
        if t == u32::MAX {
            return self.not_finite();
        }
        Closest { point: q, triangle: t, face: self.faces[t as usize], distance: d2.sqrt() }
    }

    /// The tree's shape, for the documentation and benchmarks: node count, leaf count, depth.
    #[doc(hidden)]
    pub fn tree_shape(&self) -> (usize, usize, usize) {
        self.bvh.shape()
    }
}

/// Which side of triangle `t`'s plane the third corner of each of its `neighbours` is on
/// ([`ReferenceSurface`]'s `rises`).
fn neighbour_sides(points: &[DVec3], triangles: &[[u32; 3]], neighbours: &[[u32; 3]], t: usize) -> u8 {
    let tri = triangles[t];
    let [a, b, c] = tri.map(|v| points[v as usize]);
    let normal = (b - a).cross(c - a);
    let mut sides = 0;
    for (k, &u) in neighbours[t].iter().enumerate() {
        if u == NO_TRIANGLE {
            continue;
        }
        // u's corner off the shared edge: its three corners less the edge's two.
        let [x, y, z] = triangles[u as usize];
        let third = x.wrapping_add(y).wrapping_add(z).wrapping_sub(tri[k]).wrapping_sub(tri[(k + 1) % 3]);
        let rise = normal.dot(points[third as usize] - a);
        if rise > 0.0 {
            sides |= 1 << k;
        } else if rise < 0.0 {
            sides |= 1 << (k + 3);
        }
    }
    sides
}

/// The triangle across each edge of each triangle ([`ReferenceSurface`]'s `neighbours`).
fn edge_neighbours(triangles: &[[u32; 3]]) -> Result<Vec<[u32; 3]>> {
    let mut edges: Vec<(u32, u32, u32, u8)> = try_with_capacity(triangles.len() * 3, "reference edges")?;
    for (t, tri) in triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            edges.push((a.min(b), a.max(b), t as u32, k as u8));
        }
    }
    edges.sort_unstable();
    let mut neighbours = try_with_capacity(triangles.len(), "reference neighbours")?;
    neighbours.resize(triangles.len(), [NO_TRIANGLE; 3]);
    let mut i = 0;
    while i < edges.len() {
        let mut j = i + 1;
        while j < edges.len() && (edges[j].0, edges[j].1) == (edges[i].0, edges[i].1) {
            j += 1;
        }
        // Exactly two triangles on the edge: each other's neighbours there.
        if j - i == 2 {
            let ((_, _, s, ks), (_, _, u, ku)) = (edges[i], edges[i + 1]);
            neighbours[s as usize][ks as usize] = u;
            neighbours[u as usize][ku as usize] = s;
        }
        i = j;
    }
    Ok(neighbours)
}

/// The closest point of segment `ab` to `p`, and its parameter `t` in [0, 1] (`a + t (b - a)`).
/// A segment of zero length gives `a`.
pub fn closest_point_on_segment(p: DVec3, a: DVec3, b: DVec3) -> (DVec3, f64) {
    let ab = b - a;
    let len2 = ab.dot(ab);
    if len2 <= 0.0 {
        return (a, 0.0);
    }
    let t = ((p - a).dot(ab) / len2).clamp(0.0, 1.0);
    let q = if t >= 1.0 { b } else { a + ab * t };
    (clamp_to_box(q, a, b, b), t)
}

/// `q` clamped into the axis-aligned box of `a`, `b`, `c`. The exact closest point lies in
/// that box, so clamping a computed one never moves it away from the exact one; and it makes
/// the computed distance to the triangle never less than the computed distance to its box,
/// which is what lets the tree prune boxes without ever losing a tie.
#[inline]
fn clamp_to_box(q: DVec3, a: DVec3, b: DVec3, c: DVec3) -> DVec3 {
    q.clamp(a.min(b).min(c), a.max(b).max(c))
}

/// The closest point of triangle `abc` to `p`, and the region it lies in.
///
/// A well-shaped triangle (every angle's sine at least 1e-3) goes through Ericson,
/// "Real-Time Collision Detection", 5.1.5: the vertex and edge regions by the book's sign
/// tests; inside, the projection onto the triangle's plane (along its cross product, more
/// accurate than the book's barycentric quotient). The book's interior test divides by the
/// squared area and loses about `eps / sin²` of the smallest angle, so a thin triangle (a
/// needle or a sliver) takes a path that stays exact: the projection along the normal of its
/// largest angle (the accurate one), kept if it is inside by the three edge-side tests, else
/// the closest of the three edges as segments. A triangle with no area (zero cross product,
/// e.g. collinear or repeated corners) gives the closest point of its edges,
/// [`TriangleRegion::Degenerate`]. Never NaN for finite input; the point is clamped into the
/// triangle's bounding box (see the tree's pruning).
pub fn closest_point_on_triangle(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> (DVec3, TriangleRegion) {
    let ab = b - a;
    let ac = c - a;
    let n = ab.cross(ac);
    let n2 = n.dot(n);
    let bc = c - b;
    let (lab, lac, lbc) = (ab.dot(ab), ac.dot(ac), bc.dot(bc));
    let longest = (lab * lac).max(lab * lbc).max(lac * lbc);
    if !(n2 >= f64::MIN_POSITIVE && n2 * THIN >= longest) {
        return closest_on_thin_triangle(p, a, b, c);
    }
    let ap = p - a;
    let d1 = ab.dot(ap);
    let d2 = ac.dot(ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return (a, TriangleRegion::VertexA);
    }
    let bp = p - b;
    let d3 = ab.dot(bp);
    let d4 = ac.dot(bp);
    if d3 >= 0.0 && d4 <= d3 {
        return (b, TriangleRegion::VertexB);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = ratio(d1, d1 - d3);
        return (clamp_to_box(a + ab * v, a, b, c), TriangleRegion::EdgeAB);
    }
    let cp = p - c;
    let d5 = ab.dot(cp);
    let d6 = ac.dot(cp);
    if d6 >= 0.0 && d5 <= d6 {
        return (c, TriangleRegion::VertexC);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = ratio(d2, d2 - d6);
        return (clamp_to_box(a + ac * w, a, b, c), TriangleRegion::EdgeCA);
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        let w = ratio(d4 - d3, (d4 - d3) + (d5 - d6));
        return (clamp_to_box(b + bc * w, a, b, c), TriangleRegion::EdgeBC);
    }
    let q = p - n * (n.dot(ap) / n2);
    (clamp_to_box(q, a, b, c), TriangleRegion::Interior)
}

/// A triangle is thin when its squared cross product times this is below the largest product
/// of two of its squared edge lengths: when the sine of its smallest angle is below 1e-3.
const THIN: f64 = 1e6;

/// [`closest_point_on_triangle`] for a thin or degenerate triangle.
#[cold]
fn closest_on_thin_triangle(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> (DVec3, TriangleRegion) {
    // The normal from the two edges at the largest angle (opposite the longest edge).
    let (lab, lbc, lca) = ((b - a).length_squared(), (c - b).length_squared(), (a - c).length_squared());
    let n = if lbc >= lab && lbc >= lca {
        (b - a).cross(c - a)
    } else if lca >= lab {
        (c - b).cross(a - b)
    } else {
        (a - c).cross(b - c)
    };
    let n2 = n.dot(n);
    if n2.is_nan() || n2 < f64::MIN_POSITIVE {
        return (closest_on_edges(p, a, b, c).0, TriangleRegion::Degenerate);
    }
    let q = p - n * (n.dot(p - a) / n2);
    let inside = [(a, b), (b, c), (c, a)].iter().all(|&(u, v)| n.dot((v - u).cross(q - u)) >= 0.0);
    if inside && q.is_finite() {
        return (clamp_to_box(q, a, b, c), TriangleRegion::Interior);
    }
    let (point, edge, t) = closest_on_edges(p, a, b, c);
    use TriangleRegion::*;
    let region = match (edge, t) {
        (0, t) if t <= 0.0 => VertexA,
        (0, t) if t >= 1.0 => VertexB,
        (0, _) => EdgeAB,
        (1, t) if t <= 0.0 => VertexB,
        (1, t) if t >= 1.0 => VertexC,
        (1, _) => EdgeBC,
        (_, t) if t <= 0.0 => VertexC,
        (_, t) if t >= 1.0 => VertexA,
        _ => EdgeCA,
    };
    (point, region)
}

/// `x / y` clamped to [0, 1], 0 when `y` is not positive (a zero-length edge).
#[inline]
fn ratio(x: f64, y: f64) -> f64 {
    if y > 0.0 { (x / y).clamp(0.0, 1.0) } else { 0.0 }
}

/// The closest of the closest points of segments `ab`, `bc`, `ca` (the first on a tie): the
/// point, which edge (0, 1, 2) and its parameter there.
fn closest_on_edges(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> (DVec3, usize, f64) {
    let (q, t) = closest_point_on_segment(p, a, b);
    let mut best = (q, 0, t);
    let mut best_d2 = squared_length(p - q);
    for (k, (u, v)) in [(b, c), (c, a)].into_iter().enumerate() {
        let (q, t) = closest_point_on_segment(p, u, v);
        let d2 = squared_length(p - q);
        if d2 < best_d2 {
            (best, best_d2) = ((q, k + 1, t), d2);
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_reference_surface_is_send_and_sync() {
        fn check<T: Send + Sync>() {}
        check::<ReferenceSurface>();
    }

    #[test]
    fn a_twisted_quad_is_split_along_its_flatter_diagonal() {
        // A planar convex quad: both splits are flat, so a-c.
        let p = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
        ];
        assert_eq!(split_quad(&p, &[0, 1, 2, 3]), [[0, 1, 2], [0, 2, 3]]);
        // A dart: d is inside triangle abc, so only b-d lies inside the quad.
        let dart = [p[0], p[1], p[2], DVec3::new(0.7, 0.3, 0.0)];
        assert_eq!(split_quad(&dart, &[0, 1, 2, 3]), [[0, 1, 3], [1, 2, 3]]);
        // Lifting c to z = 1: a-c's normals are (0,-1,1) and (-1,0,1), 60 degrees apart;
        // b-d's are (0,0,1) and (-1,-1,1), 54.7 degrees apart.
        let lifted = [p[0], p[1], DVec3::new(1.0, 1.0, 1.0), p[3]];
        let a_c = normal_angle(&lifted, [0, 1, 2], [0, 2, 3]);
        let b_d = normal_angle(&lifted, [0, 1, 3], [1, 2, 3]);
        assert!(b_d < a_c, "{b_d} {a_c}");
        assert_eq!(split_quad(&lifted, &[0, 1, 2, 3]), [[0, 1, 3], [1, 2, 3]]);
    }
}
