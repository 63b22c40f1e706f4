//! The optimizer's internal vertex and quad order, chosen for memory locality.
//!
//! A sweep reads, for every vertex, its ring's positions and its star's quads. In the order a
//! mesher writes them those are scattered over the arrays, and on a large mesh the sweep
//! waits on memory: on a 186k-quad gmsh plate, loading the star's quads and positions was a
//! third of a sweep (perf). Numbered along a Hilbert curve, the vertices of a star lie close
//! together in memory, and so do the quads, ordered by their vertices in that numbering.
//! Measured there (20 sweeps): 2.2 s in gmsh's order, 1.4 s renumbered, 3.9 s shuffled.
//!
//! A mesh numbered locally already (a row-major grid, say: 90% of its edges and of its
//! consecutive quads within 4,096 indices) keeps its order. Otherwise the order depends only
//! on the mesh given to [`crate::Optimizer::new`], not on how the caller numbered it (but for
//! vertices closer than 2^-16 of the mesh's extent, kept in the caller's order), so a run is
//! the same on any number of threads and for any non-local numbering of one mesh.
//! Results are mapped back to the caller's numbering; fixed vertices come back bit for bit.

use crate::error::Result;
use crate::mesh::Mesh;
use glam::DVec2;

/// Meshes with fewer vertices keep their own order: their arrays fit in a core's cache, and
/// renumbering gains nothing there (measured: 9.4k vertices, 100 sweeps in 0.52 s in gmsh's
/// order, 0.51 s renumbered).
pub(crate) const MIN_VERTICES: usize = 16_384;

/// Index distance within which two vertices (or two quads) count as close in memory: 4,096
/// vertices' positions are 64 KB, well inside a core's cache.
const LOCAL_SPAN: u32 = 4096;

/// The fraction of edges, and of consecutive quads, that must be close in memory for the
/// caller's order to be kept. Measured: a row-major grid has all of them close, the same
/// grid renumbered along a Hilbert curve 99%; a gmsh plate (186k quads, Frontal-Delaunay and
/// Blossom) 29% of its edges, a shuffled one 4%.
const LOCAL_FRACTION: f64 = 0.9;

/// Whether the quads' order and their vertices' numbering are already local: then
/// renumbering would cost its memory for nothing (measured on a 1M-quad row-major grid:
/// no faster, 40 MB more).
fn already_local(quads: &[[u32; 4]]) -> bool {
    let close = |a: u32, b: u32| a.abs_diff(b) < LOCAL_SPAN;
    let (mut edges, mut all_edges) = (0, 0);
    for q in quads {
        let n = crate::face::corner_count(q);
        edges += (0..n).filter(|&i| close(q[i], q[(i + 1) % n])).count();
        all_edges += n;
    }
    let neighbours = quads.windows(2).filter(|w| close(w[0][0], w[1][0])).count();
    let enough = |count: usize, of: usize| count as f64 >= LOCAL_FRACTION * of as f64;
    enough(edges, all_edges) && enough(neighbours, quads.len().saturating_sub(1))
}

/// Bits per axis of the Hilbert curve's grid.
const HILBERT_BITS: u32 = 16;

/// The internal order: `vertex_of[i]` is the caller's index of internal vertex `i`,
/// `quad_of[k]` the caller's index of internal quad `k`.
#[derive(Clone, Debug)]
pub(crate) struct Renumbering {
    vertex_of: Vec<u32>,
    quad_of: Vec<u32>,
}

impl Renumbering {
    /// The order for `mesh`, or `None` when it keeps its own (small, see [`MIN_VERTICES`], or
    /// already local).
    pub fn new(mesh: &Mesh) -> Result<Option<Renumbering>> {
        let points = mesh.points();
        if points.len() < MIN_VERTICES || already_local(mesh.quads()) {
            return Ok(None);
        }
        let (lo, hi) =
            points.iter().fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(lo, hi), &p| (lo.min(p), hi.max(p)));
        let extent = (hi - lo).max_element();
        let cells = f64::from((1u32 << HILBERT_BITS) - 1);
        let scale = if extent > 0.0 && extent.is_finite() { cells / extent } else { 0.0 };
        let mut keyed = crate::alloc::try_with_capacity::<(u32, u32)>(points.len(), "vertex order")?;
        keyed.extend(points.iter().enumerate().map(|(i, &p)| {
            let g = ((p - lo) * scale).clamp(DVec2::ZERO, DVec2::splat(cells));
            (hilbert_index(g.x as u32, g.y as u32), i as u32)
        }));
        // Ties (vertices in one cell) in the caller's order: the sort is total.
        keyed.sort_unstable();
        let mut vertex_of = crate::alloc::try_with_capacity(points.len(), "vertex order")?;
        vertex_of.extend(keyed.iter().map(|&(_, i)| i));
        // Reuse the keys' memory: internal index of each caller's vertex.
        let mut internal = keyed;
        for (k, &v) in vertex_of.iter().enumerate() {
            internal[v as usize].0 = k as u32;
        }
        let quads = mesh.quads();
        // By the quad's vertices in the internal order, smallest first: the quads of one
        // vertex are neighbours, and (quads being distinct) no two tie, so the order does not
        // depend on the caller's.
        let mut quad_keys = crate::alloc::try_with_capacity::<([u32; 4], u32)>(quads.len(), "quad order")?;
        quad_keys.extend(quads.iter().enumerate().map(|(k, q)| {
            // A triangle's NO_VERTEX stays itself (it sorts last).
            let mut key = q.map(|v| internal.get(v as usize).map_or(v, |i| i.0));
            key.sort_unstable();
            (key, k as u32)
        }));
        quad_keys.sort_unstable();
        let mut quad_of = crate::alloc::try_with_capacity(quads.len(), "quad order")?;
        quad_of.extend(quad_keys.iter().map(|&(_, k)| k));
        Ok(Some(Renumbering { vertex_of, quad_of }))
    }

    /// `mesh` in the internal order (which must be the order of a mesh with its
    /// connectivity).
    pub fn internal(&self, mesh: &Mesh) -> Result<Mesh> {
        mesh.renumbered(&self.vertex_of, &self.quad_of)
    }

    /// Writes the positions of `internal` (a mesh in the internal order) into `mesh`.
    pub fn write_back(&self, internal: &Mesh, mesh: &mut Mesh) {
        let out = mesh.points_mut();
        for (&v, &p) in self.vertex_of.iter().zip(internal.points()) {
            out[v as usize] = p;
        }
    }

    /// The caller's index of internal quad `k`.
    pub fn quad(&self, k: u32) -> u32 {
        self.quad_of[k as usize]
    }
}

/// Position of grid cell (x, y) along the Hilbert curve over a 2^16 x 2^16 grid (the
/// classic bit-by-bit construction, most significant bit first).
fn hilbert_index(mut x: u32, mut y: u32) -> u32 {
    let n = 1u32 << HILBERT_BITS;
    let mut d = 0u32;
    let mut s = n >> 1;
    while s > 0 {
        let rx = u32::from(x & s != 0);
        let ry = u32::from(y & s != 0);
        d += s * s * ((3 * rx) ^ ry);
        // Turn the quadrant so that the curve's pieces join.
        if ry == 0 {
            if rx == 1 {
                (x, y) = (n - 1 - x, n - 1 - y);
            }
            std::mem::swap(&mut x, &mut y);
        }
        s >>= 1;
    }
    d
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_row_major_grid_is_local_and_a_shuffled_one_is_not() {
        let n = 200u32;
        let grid: Vec<[u32; 4]> = (0..n * n)
            .map(|k| {
                let (i, j) = (k % n, k / n);
                let v = j * (n + 1) + i;
                [v, v + 1, v + n + 2, v + n + 1]
            })
            .collect();
        assert!(already_local(&grid));
        // Vertices numbered at random (a fixed odd multiplier modulo a power of two above
        // the vertex count is a permutation that scatters neighbours).
        let scatter = |v: u32| v.wrapping_mul(2_654_435_761) % (1 << 16);
        let shuffled: Vec<[u32; 4]> = grid.iter().map(|q| q.map(scatter)).collect();
        assert!(!already_local(&shuffled));
        // Quads in a scattered order, vertices local: not local either.
        let mut quads_shuffled = grid.clone();
        quads_shuffled.sort_by_key(|q| scatter(q[0]));
        assert!(!already_local(&quads_shuffled));
    }

    #[test]
    fn the_hilbert_index_walks_the_grid_cell_by_neighbouring_cell() {
        // Over an 8x8 corner of the grid the curve's first 64 cells are the corner's cells,
        // each next to the one before.
        let mut cell_at = vec![None; 64];
        for x in 0..8u32 {
            for y in 0..8u32 {
                let d = hilbert_index(x, y) as usize;
                assert!(d < 64, "({x}, {y}) -> {d}");
                assert!(cell_at[d].is_none());
                cell_at[d] = Some((x, y));
            }
        }
        for w in cell_at.windows(2) {
            let ((x0, y0), (x1, y1)) = (w[0].unwrap(), w[1].unwrap());
            assert_eq!(x0.abs_diff(x1) + y0.abs_diff(y1), 1, "{w:?}");
        }
    }
}
