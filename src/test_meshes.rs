//! Meshes for the unit tests.

use crate::Mesh;
use glam::DVec2;

/// An `nx` by `ny` grid of unit squares, vertex (i, j) at index j * (nx + 1) + i.
pub(crate) fn grid(nx: u32, ny: u32) -> Mesh {
    let mut p = Vec::new();
    for j in 0..=ny {
        for i in 0..=nx {
            p.push(DVec2::new(i as f64, j as f64));
        }
    }
    let mut q = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            let a = j * (nx + 1) + i;
            q.push([a, a + 1, a + nx + 2, a + nx + 1]);
        }
    }
    Mesh::new(p, q, None).unwrap()
}
