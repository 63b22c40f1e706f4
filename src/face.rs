//! The face model: a face is a quad or a triangle, stored in the same four slots.
//!
//! A triangle's fourth slot holds [`NO_VERTEX`]. One fixed-size record for both kinds keeps
//! the flat arrays (and the C ABI's stride of four) and lets every loop over a face's corners
//! run over `corner_count` entries; quad-only meshes are stored, and give results, exactly as
//! before. Nothing here depends on coordinates, so a surface mesh uses the same faces.

/// The fourth index of a triangle: "no vertex".
pub const NO_VERTEX: u32 = u32::MAX;

/// A face: four vertex indices, counter-clockwise, or three and [`NO_VERTEX`].
pub type Face = [u32; 4];

/// The triangle `[a, b, c]`.
#[inline]
pub const fn triangle(a: u32, b: u32, c: u32) -> Face {
    [a, b, c, NO_VERTEX]
}

/// Whether `f` is a triangle.
#[inline]
pub const fn is_triangle(f: &Face) -> bool {
    f[3] == NO_VERTEX
}

/// Number of corners of `f`: 3 or 4.
#[inline]
pub const fn corner_count(f: &Face) -> usize {
    if is_triangle(f) { 3 } else { 4 }
}

/// The vertices of `f`, in order.
#[inline]
pub fn vertices(f: &Face) -> &[u32] {
    &f[..corner_count(f)]
}

/// `f` with its orientation reversed, keeping its first vertex.
#[inline]
pub fn reversed(f: Face) -> Face {
    if is_triangle(&f) { [f[0], f[2], f[1], NO_VERTEX] } else { [f[0], f[3], f[2], f[1]] }
}

/// The vertex of the fourth corner as the quality measure reads it: a triangle's last vertex
/// again, which Verdict measures as the triangle (a quad collapsed onto its last edge).
#[inline]
pub const fn fourth_corner(f: &Face) -> u32 {
    if is_triangle(f) { f[2] } else { f[3] }
}

/// The position of `v` in `f`, if it is a corner of it.
#[inline]
pub fn position(f: &Face, v: u32) -> Option<usize> {
    vertices(f).iter().position(|&u| u == v)
}

/// The corners of `f` after corner `k`, counter-clockwise: the next vertex, the opposite one
/// ([`NO_VERTEX`] for a triangle) and the previous one.
#[inline]
pub fn after(f: &Face, k: usize) -> (u32, u32, u32) {
    let n = corner_count(f);
    if n == 3 {
        (f[(k + 1) % 3], NO_VERTEX, f[(k + 2) % 3])
    } else {
        (f[(k + 1) % 4], f[(k + 2) % 4], f[(k + 3) % 4])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn triangles_and_quads_share_one_record() {
        let t = triangle(4, 5, 6);
        let q = [1, 2, 3, 4];
        assert!(is_triangle(&t) && !is_triangle(&q));
        assert_eq!((corner_count(&t), corner_count(&q)), (3, 4));
        assert_eq!((vertices(&t), vertices(&q)), (&[4, 5, 6][..], &[1, 2, 3, 4][..]));
        assert_eq!(reversed(t), [4, 6, 5, NO_VERTEX]);
        assert_eq!(reversed(q), [1, 4, 3, 2]);
        assert_eq!((fourth_corner(&t), fourth_corner(&q)), (6, 4));
        assert_eq!((position(&t, 6), position(&t, NO_VERTEX), position(&q, 3)), (Some(2), None, Some(2)));
        assert_eq!(after(&t, 2), (4, NO_VERTEX, 5));
        assert_eq!(after(&q, 3), (1, 2, 3));
    }
}
