//! Structured grids, the meshes most tests start from, and their conversions.
//!
//! An `nx` x `ny` [`Grid`] has the vertices (i, j), `0 <= i <= nx`, `0 <= j <= ny`, vertex
//! (i, j) at index `j (nx + 1) + i` (row by row, i fastest), and one quad per cell: cell
//! (i, j) is `[(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)]`, counter-clockwise wherever x
//! grows with i and y with j. The points come from a closure called once per vertex in index
//! order, so a closure that draws random numbers (a jitter) draws them in a fixed order:
//! the meshes, and the thresholds tests assert on them, never change.

use quadopt::DVec2;
use quadopt::io::MeshData;

/// The shape of a structured grid: `nx` cells along x, `ny` along y.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Grid {
    pub nx: usize,
    pub ny: usize,
}

impl Grid {
    pub fn new(nx: usize, ny: usize) -> Grid {
        Grid { nx, ny }
    }

    /// `n` x `n` cells.
    pub fn square(n: usize) -> Grid {
        Grid::new(n, n)
    }

    pub fn vertex_count(self) -> usize {
        (self.nx + 1) * (self.ny + 1)
    }

    /// The index of vertex (i, j).
    pub fn index(self, i: usize, j: usize) -> usize {
        j * (self.nx + 1) + i
    }

    /// Vertex (i, j) is on the left or right side (i = 0 or nx).
    pub fn on_vertical_side(self, i: usize, _j: usize) -> bool {
        i == 0 || i == self.nx
    }

    /// Vertex (i, j) is on the bottom or top side (j = 0 or ny).
    pub fn on_horizontal_side(self, _i: usize, j: usize) -> bool {
        j == 0 || j == self.ny
    }

    pub fn on_boundary(self, i: usize, j: usize) -> bool {
        self.on_vertical_side(i, j) || self.on_horizontal_side(i, j)
    }

    pub fn is_corner(self, i: usize, j: usize) -> bool {
        self.on_vertical_side(i, j) && self.on_horizontal_side(i, j)
    }

    pub fn is_interior(self, i: usize, j: usize) -> bool {
        !self.on_boundary(i, j)
    }

    /// One value per vertex in index order: `f(i, j)`, called once for each vertex, row by
    /// row (points, fixed flags, 3D points).
    pub fn per_vertex<T>(self, mut f: impl FnMut(usize, usize) -> T) -> Vec<T> {
        let mut out = Vec::with_capacity(self.vertex_count());
        for j in 0..=self.ny {
            for i in 0..=self.nx {
                out.push(f(i, j));
            }
        }
        out
    }

    /// The points of the grid's vertices, vertex (i, j) at `place(i, j)` (see [`Grid::per_vertex`]).
    pub fn points(self, place: impl FnMut(usize, usize) -> DVec2) -> Vec<DVec2> {
        self.per_vertex(place)
    }

    /// Every cell's quad, row by row.
    pub fn quads(self) -> Vec<[u32; 4]> {
        self.quads_without(|_, _| false)
    }

    /// The quads of the cells `skip(i, j)` does not reject, row by row.
    pub fn quads_without(self, mut skip: impl FnMut(usize, usize) -> bool) -> Vec<[u32; 4]> {
        let row = self.nx as u32 + 1;
        let mut quads = Vec::with_capacity(self.nx * self.ny);
        for j in 0..self.ny {
            for i in 0..self.nx {
                if !skip(i, j) {
                    let a = self.index(i, j) as u32;
                    quads.push([a, a + 1, a + row + 1, a + row]);
                }
            }
        }
        quads
    }

    /// The grid with vertex (i, j) at `place(i, j)`: points and quads.
    pub fn placed(self, place: impl FnMut(usize, usize) -> DVec2) -> (Vec<DVec2>, Vec<[u32; 4]>) {
        (self.points(place), self.quads())
    }

    /// The grid of unit squares, vertex (i, j) at (i, j): points and quads.
    pub fn unit(self) -> (Vec<DVec2>, Vec<[u32; 4]>) {
        self.placed(|i, j| DVec2::new(i as f64, j as f64))
    }
}

/// The grid on the coordinates `xs` and `ys` (vertex (i, j) at (xs[i], ys[j])) without the
/// cells `skip(i, j)` rejects: points and quads.
pub fn on_coordinates(
    xs: &[f64],
    ys: &[f64],
    skip: impl FnMut(usize, usize) -> bool,
) -> (Vec<DVec2>, Vec<[u32; 4]>) {
    let grid = Grid::new(xs.len() - 1, ys.len() - 1);
    (grid.points(|i, j| DVec2::new(xs[i], ys[j])), grid.quads_without(skip))
}

/// The interior vertices of a quad list (those used by four quads), of `vertex_count`.
pub fn interior_mask(vertex_count: usize, quads: &[[u32; 4]]) -> Vec<bool> {
    let mut uses = vec![0; vertex_count];
    for q in quads {
        for &v in q {
            uses[v as usize] += 1;
        }
    }
    uses.iter().map(|&c| c == 4).collect()
}

/// Flat arrays, as the C ABI takes them: x, y per point and four indices per quad.
pub fn flat(points: &[DVec2], quads: &[[u32; 4]]) -> (Vec<f64>, Vec<u32>) {
    (points.iter().flat_map(|p| p.to_array()).collect(), quads.iter().flatten().copied().collect())
}

/// A mesh file's data: the points in the plane z = `z`, no fixed flags.
pub fn mesh_data_at_z(points: &[DVec2], quads: Vec<[u32; 4]>, z: f64) -> MeshData {
    MeshData::new(points.iter().map(|p| [p.x, p.y, z]).collect(), quads)
}
