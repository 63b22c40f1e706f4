//! Synthetic meshes for benchmarks and stress tests: a structured grid with circular holes cut
//! out (their boundaries are the grid's staircase) and the interior vertices randomly
//! perturbed. Generation is deterministic: the same [`Synthetic`] always gives the same mesh,
//! on every platform (a PCG generator seeded with [`Synthetic::seed`]).
//!
//! ```
//! use quadopt::synthetic::Synthetic;
//! let mesh = Synthetic::with_quads(10_000).generate();
//! assert!((mesh.quads().len() as f64 - 10_000.0).abs() < 500.0);
//! assert!(mesh.quality().min < 0.9); // the jitter made it worth optimizing
//! ```

use crate::alloc::{try_filled, try_with_capacity};
use crate::error::{Error, Result};
use crate::face::{Face, triangle};
use crate::mesh::Mesh;
use crate::quality::{corners, scaled_jacobian};
use glam::DVec2;
use rand_core::{RngCore, SeedableRng};
use rand_pcg::Pcg64Mcg;

/// Parameters of a synthetic mesh: an `nx` by `ny` grid of unit squares with `holes` circular
/// holes on a regular lattice, interior vertices jittered by up to `jitter` grid spacings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Synthetic {
    /// Cells along x (>= 1).
    pub nx: u32,
    /// Cells along y (>= 1).
    pub ny: u32,
    /// Number of holes, placed on the smallest square lattice that holds them. That lattice may
    /// not be finer than the grid (at most `min(nx, ny)` sites per side, so at most
    /// `min(nx, ny)^2` holes).
    pub holes: u32,
    /// Hole diameter as a fraction of the lattice spacing, in [0, 1).
    pub hole_size: f64,
    /// Largest displacement of an interior vertex along x and along y, in grid spacings.
    /// Below 0.25 no quad can fold (each corner's cross product stays above 1 - 4 * jitter);
    /// from about 0.4 on some do, like a tangled input.
    pub jitter: f64,
    /// Seed of the random perturbation.
    pub seed: u64,
}

impl Default for Synthetic {
    fn default() -> Self {
        Synthetic { nx: 100, ny: 100, holes: 4, hole_size: 0.5, jitter: 0.3, seed: 1 }
    }
}

impl Synthetic {
    /// A square grid with the default holes and jitter, sized to have about `quads` quads.
    pub fn with_quads(quads: usize) -> Synthetic {
        let d = Synthetic::default();
        // Fraction of the domain the holes remove: k*k lattice cells, `holes` of them with a
        // disc of diameter hole_size.
        let k = lattice_side(d.holes) as f64;
        let removed = d.holes as f64 * std::f64::consts::PI * (d.hole_size / 2.0).powi(2) / (k * k);
        let side = ((quads as f64 / (1.0 - removed)).sqrt().round() as u32).max(1);
        Synthetic { nx: side, ny: side, ..d }
    }

    /// Builds the mesh. Vertices are numbered row by row, unused grid points dropped.
    ///
    /// # Panics
    /// Where [`Synthetic::try_generate`] fails: a grid too large for `u32` vertex indices or
    /// for the memory available.
    pub fn generate(&self) -> Mesh {
        self.try_generate().unwrap_or_else(|e| panic!("{e}"))
    }

    /// Builds the mesh, or fails with [`Error::InvalidOption`] for a grid whose vertices
    /// `u32` indices cannot number or for more holes than fit in the grid (see
    /// [`Synthetic::holes`]), or [`Error::OutOfMemory`] for a grid too large for the memory
    /// available (checked before anything of that size is allocated).
    pub fn try_generate(&self) -> Result<Mesh> {
        let (points, quads, _) = self.grid()?;
        Mesh::new(points, quads, None)
    }

    /// Builds a quad-dominant mesh: the mesh of [`Synthetic::try_generate`] (the same
    /// vertices, at the same positions) with `round(triangles * quads)` of its quads, chosen by
    /// the seeded generator, each split along a diagonal into two triangles (the diagonal whose
    /// worse triangle has the larger scaled Jacobian; the first one on a tie). Deterministic
    /// like the quad mesh; `triangles = 0` gives that mesh. Fails where
    /// [`Synthetic::try_generate`] does, and with [`Error::InvalidOption`] (`"triangles"`) for a
    /// fraction outside [0, 1].
    ///
    /// ```
    /// use quadopt::synthetic::Synthetic;
    /// let s = Synthetic { nx: 20, ny: 20, holes: 0, ..Synthetic::default() };
    /// let mesh = s.generate_quad_dominant(0.25).unwrap();
    /// assert_eq!(mesh.triangle_count(), 2 * 100);
    /// assert_eq!(mesh.faces().len() - mesh.triangle_count(), 300);
    /// assert_eq!(mesh.points(), s.generate().points());
    /// ```
    pub fn generate_quad_dominant(&self, triangles: f64) -> Result<Mesh> {
        if !(0.0..=1.0).contains(&triangles) {
            return Err(Error::InvalidOption {
                name: "triangles",
                reason: format!("the fraction of quads split into triangles, {triangles}, is not in [0, 1]"),
            });
        }
        let (points, quads, mut rng) = self.grid()?;
        let split = (triangles * quads.len() as f64).round() as usize;
        let mut faces = try_with_capacity(quads.len() + split, "faces")?;
        // Selection sampling (Knuth's algorithm S): exactly `split` quads, each set of them
        // equally likely, in one pass.
        let mut wanted = split;
        for (seen, q) in quads.iter().enumerate() {
            let left = (quads.len() - seen) as u64;
            if wanted > 0 && rng.next_u64() % left < wanted as u64 {
                wanted -= 1;
                let [a, b] = split_quad(&points, q);
                faces.push(a);
                faces.push(b);
            } else {
                faces.push(*q);
            }
        }
        drop(quads);
        Mesh::with_faces(points, faces, None)
    }

    /// The grid's vertices and quads (counter-clockwise), and the generator after the jitter.
    fn grid(&self) -> Result<(Vec<DVec2>, Vec<[u32; 4]>, Pcg64Mcg)> {
        let (nx, ny) = (self.nx.max(1) as usize, self.ny.max(1) as usize);
        // Every grid point gets an index below u32::MAX (the mark of an unused point).
        let grid_points = (nx as u128 + 1) * (ny as u128 + 1);
        if grid_points >= u128::from(u32::MAX) {
            return Err(Error::InvalidOption {
                name: "grid size",
                reason: format!(
                    "a {nx} x {ny} grid has {grid_points} vertices, more than uint32 indices can number ({})",
                    u32::MAX - 1
                ),
            });
        }
        let k = lattice_side(self.holes);
        let side = nx.min(ny);
        if k > side {
            return Err(Error::InvalidOption {
                name: "holes",
                reason: format!(
                    "{} holes do not fit in a {nx} x {ny} grid: their {k} x {k} lattice is finer than the grid \
                     (at most {} holes, on a {side} x {side} lattice)",
                    self.holes,
                    side * side
                ),
            });
        }
        let kept = self.kept_cells(nx, ny)?;
        // Grid vertex (i, j) has index j * (nx + 1) + i; count the kept cells around each.
        let stride = nx + 1;
        let mut incident = try_filled(stride * (ny + 1), 0u8, "grid points")?;
        for j in 0..ny {
            for i in 0..nx {
                if kept[j * nx + i] {
                    for g in
                        [j * stride + i, j * stride + i + 1, (j + 1) * stride + i, (j + 1) * stride + i + 1]
                    {
                        incident[g] += 1;
                    }
                }
            }
        }
        let mut index = try_filled(incident.len(), u32::MAX, "grid point indices")?;
        let mut points =
            try_with_capacity(incident.iter().filter(|&&n| n > 0).count(), "vertex coordinates")?;
        let mut rng = Pcg64Mcg::seed_from_u64(self.seed);
        for j in 0..=ny {
            for i in 0..=nx {
                let g = j * stride + i;
                if incident[g] == 0 {
                    continue;
                }
                let mut p = DVec2::new(i as f64, j as f64);
                // Only vertices with four kept cells around them are interior; boundary
                // vertices stay on the (staircase) boundary.
                if incident[g] == 4 {
                    p += self.jitter * DVec2::new(symmetric_unit(&mut rng), symmetric_unit(&mut rng));
                }
                index[g] = points.len() as u32;
                points.push(p);
            }
        }
        let mut quads = try_with_capacity(kept.iter().filter(|&&k| k).count(), "quads")?;
        for j in 0..ny {
            for i in 0..nx {
                if kept[j * nx + i] {
                    let a = j * stride + i;
                    quads.push([index[a], index[a + 1], index[a + stride + 1], index[a + stride]]);
                }
            }
        }
        drop((incident, index, kept));
        Ok((points, quads, rng))
    }

    /// Which cells survive: those whose centre lies outside every hole. A hole's radius is
    /// less than half the lattice spacing, so it lies inside its own lattice cell: only the
    /// hole of the lattice cell holding a cell's centre can contain it.
    fn kept_cells(&self, nx: usize, ny: usize) -> Result<Vec<bool>> {
        let k = lattice_side(self.holes);
        let (w, h) = (nx as f64, ny as f64);
        let radius = self.hole_size.clamp(0.0, 0.999) * 0.5 * (w / k as f64).min(h / k as f64);
        let mut kept = try_filled(nx * ny, true, "grid cells")?;
        for j in 0..ny {
            for i in 0..nx {
                let c = DVec2::new(i as f64 + 0.5, j as f64 + 0.5);
                let (a, b) = (lattice_cell(c.x, w, k), lattice_cell(c.y, h, k));
                let n = b * k + a;
                if n < self.holes as usize {
                    let o = DVec2::new(a as f64 + 0.5, b as f64 + 0.5) * DVec2::new(w, h) / k as f64;
                    kept[j * nx + i] = (c - o).length() >= radius;
                }
            }
        }
        Ok(kept)
    }
}

/// Side of the smallest square lattice with at least `holes` sites.
fn lattice_side(holes: u32) -> usize {
    let mut k = 1;
    while k * k < holes as usize {
        k += 1;
    }
    k
}

/// The lattice cell (of `k` along a side of length `len`) that holds the coordinate `x`.
fn lattice_cell(x: f64, len: f64, k: usize) -> usize {
    ((x * k as f64 / len) as usize).min(k - 1)
}

/// The quad `q` as two triangles, split along the diagonal that makes the worse of them
/// better (the diagonal from the first corner on a tie): a non-convex quad is split along
/// its inside diagonal. Both keep the quad's orientation.
fn split_quad(points: &[DVec2], q: &[u32; 4]) -> [Face; 2] {
    let [a, b, c, d] = *q;
    let worse = |s: [Face; 2]| {
        s.map(|t| scaled_jacobian(&corners(points, &t))).into_iter().fold(f64::INFINITY, f64::min)
    };
    let (first, second) = ([triangle(a, b, c), triangle(a, c, d)], [triangle(a, b, d), triangle(b, c, d)]);
    if worse(second) > worse(first) { second } else { first }
}

/// A uniform number in [-1, 1) from 53 random bits.
fn symmetric_unit(rng: &mut Pcg64Mcg) -> f64 {
    (rng.next_u64() >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::topology::Topology;

    #[test]
    fn plain_grid_has_the_expected_counts_and_perfect_quality() {
        let m = Synthetic { nx: 5, ny: 3, holes: 0, jitter: 0.0, ..Synthetic::default() }.generate();
        assert_eq!(m.points().len(), 6 * 4);
        assert_eq!(m.quads().len(), 15);
        assert_eq!(m.quality().min, 1.0);
    }

    #[test]
    fn holes_add_boundary_loops_and_keep_the_boundary_unjittered() {
        let s = Synthetic { nx: 40, ny: 40, holes: 4, jitter: 0.24, ..Synthetic::default() };
        let m = s.generate();
        let topo = Topology::new(&m);
        assert_eq!(topo.loop_count(), 5, "outer boundary and four holes");
        for l in topo.boundary_loops() {
            for &v in l {
                let p = m.points()[v as usize];
                assert_eq!(p, p.round(), "boundary vertex {v} moved off the grid");
            }
        }
        // Below a quarter spacing of jitter, no quad can fold.
        assert_eq!(m.quality().inverted, 0);
        assert!(m.quality().min < 0.7);
    }

    #[test]
    fn generation_is_deterministic_and_seed_dependent() {
        let s = Synthetic { nx: 20, ny: 20, ..Synthetic::default() };
        assert_eq!(s.generate().points(), s.generate().points());
        assert_ne!(s.generate().points(), Synthetic { seed: 2, ..s }.generate().points());
    }

    #[test]
    fn large_jitter_inverts_quads() {
        let m = Synthetic { nx: 30, ny: 30, jitter: 0.45, ..Synthetic::default() }.generate();
        assert!(m.quality().inverted > 0);
    }

    #[test]
    fn grids_too_large_for_uint32_indices_are_errors_not_panics() {
        for s in [
            Synthetic { nx: u32::MAX, ny: u32::MAX, ..Synthetic::default() },
            Synthetic::with_quads(100_000_000_000),
            // 65535 x 65535 cells: 65536^2 = 2^32 grid points, one too many.
            Synthetic { nx: 65_535, ny: 65_535, ..Synthetic::default() },
        ] {
            let e = s.try_generate().unwrap_err();
            assert!(matches!(e, Error::InvalidOption { name: "grid size", .. }), "{e}");
            assert!(e.to_string().contains("more than uint32 indices can number (4294967294)"), "{e}");
        }
    }

    #[test]
    fn more_holes_than_fit_are_an_error_not_an_abort() {
        // 2^32 - 1 holes: their centres alone would take 64 GiB.
        for (s, text) in [
            (
                Synthetic { holes: u32::MAX, ..Synthetic::with_quads(1000) },
                "4294967295 holes do not fit in a 35 x 35 grid: their 65536 x 65536 lattice is finer",
            ),
            (
                Synthetic { nx: 3, ny: 50, holes: 10, ..Synthetic::default() },
                "(at most 9 holes, on a 3 x 3 lattice)",
            ),
        ] {
            let e = s.try_generate().unwrap_err();
            assert!(matches!(e, Error::InvalidOption { name: "holes", .. }), "{e}");
            assert!(e.to_string().contains(text), "{e}");
        }
        assert!(Synthetic { nx: 3, ny: 50, holes: 9, ..Synthetic::default() }.try_generate().is_ok());
    }

    /// Only the hole of a cell's own lattice cell is tested: the same cells as testing every
    /// hole.
    #[test]
    fn kept_cells_are_those_outside_every_hole() {
        for (nx, ny, holes, hole_size) in
            [(40, 40, 4, 0.5), (37, 23, 7, 0.9), (10, 10, 100, 0.999), (64, 9, 81, 0.7), (50, 50, 3, 0.3)]
        {
            let s = Synthetic { nx, ny, holes, hole_size, ..Synthetic::default() };
            let (nx, ny) = (nx as usize, ny as usize);
            let k = lattice_side(holes);
            let (w, h) = (nx as f64, ny as f64);
            let radius = hole_size * 0.5 * (w / k as f64).min(h / k as f64);
            let centres: Vec<DVec2> = (0..holes as usize)
                .map(|n| DVec2::new((n % k) as f64 + 0.5, (n / k) as f64 + 0.5) * DVec2::new(w, h) / k as f64)
                .collect();
            let every_hole: Vec<bool> = (0..nx * ny)
                .map(|c| {
                    let c = DVec2::new((c % nx) as f64 + 0.5, (c / nx) as f64 + 0.5);
                    centres.iter().all(|&o| (c - o).length() >= radius)
                })
                .collect();
            let kept = s.kept_cells(nx, ny).unwrap();
            assert_eq!(kept, every_hole, "{s:?}");
            assert!(kept.iter().any(|&k| !k), "{s:?}: no hole cut");
        }
    }

    #[test]
    fn with_quads_hits_the_requested_size() {
        for n in [1_000usize, 100_000] {
            let s = Synthetic::with_quads(n);
            let (nx, ny) = (s.nx as usize, s.ny as usize);
            let quads = s.kept_cells(nx, ny).unwrap().iter().filter(|&&k| k).count();
            assert!((quads as f64 / n as f64 - 1.0).abs() < 0.05, "{n}: got {quads}");
        }
    }
}
