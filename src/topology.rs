//! Connectivity, built once per mesh in flat (CSR) arrays: each vertex's edge-neighbours in
//! counter-clockwise order (the corners of its embedded polygon, Section 3.1), the same ring
//! with the quads' diagonal vertices interleaved (for Xu and Newman's method), and the boundary
//! loops. Everything here depends on connectivity only; which vertices may move is decided per
//! run from the geometry in [`crate::features`].

use crate::mesh::QuadMesh;

/// How a vertex sits in the mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VertexKind {
    /// Used by no quad; never moved.
    Unused,
    /// A closed fan of quads around it.
    Interior,
    /// On the boundary, with a single open fan of quads.
    Boundary,
    /// Several fans meet here (a "bowtie"); never moved.
    NonManifold,
}

/// One-rings and boundary loops of a [`QuadMesh`].
#[derive(Clone, Debug)]
pub struct Topology {
    kind: Vec<VertexKind>,
    /// Number of quads incident to each vertex.
    quad_count: Vec<u32>,
    ring_offsets: Vec<u32>,
    /// Edge-neighbours, counter-clockwise. For a boundary vertex the first is the next vertex
    /// along its boundary loop and the last the previous one.
    ring: Vec<u32>,
    full_offsets: Vec<u32>,
    /// Edge-neighbours with each quad's diagonal vertex between its two edge-neighbours.
    full_ring: Vec<u32>,
    loop_offsets: Vec<u32>,
    /// Boundary loops, with the mesh interior on the left (outer boundaries counter-clockwise).
    loops: Vec<u32>,
    quad_offsets: Vec<u32>,
    /// Quads incident to each vertex.
    vertex_quads: Vec<u32>,
}

impl Topology {
    /// Builds the connectivity of `mesh`.
    pub fn new(mesh: &QuadMesh) -> Topology {
        let n = mesh.points().len();
        let quads = mesh.quads();
        let mut quad_offsets = vec![0u32; n + 1];
        for q in quads {
            for &v in q {
                quad_offsets[v as usize + 1] += 1;
            }
        }
        for v in 0..n {
            quad_offsets[v + 1] += quad_offsets[v];
        }
        let mut fill = quad_offsets.clone();
        let mut vertex_quads = vec![0u32; quads.len() * 4];
        for (qi, q) in quads.iter().enumerate() {
            for &v in q {
                vertex_quads[fill[v as usize] as usize] = qi as u32;
                fill[v as usize] += 1;
            }
        }

        let mut kind = vec![VertexKind::Unused; n];
        let mut quad_count = vec![0u32; n];
        let mut ring_offsets = Vec::with_capacity(n + 1);
        let mut ring = Vec::with_capacity(quads.len() * 5);
        let mut full_offsets = Vec::with_capacity(n + 1);
        let mut full_ring = Vec::with_capacity(quads.len() * 9);
        // Boundary successor of each boundary vertex (for loop tracing), and scratch wedges.
        let mut boundary_next = vec![u32::MAX; n];
        let mut wedges: Vec<(u32, u32, u32)> = Vec::new();
        ring_offsets.push(0);
        full_offsets.push(0);
        for v in 0..n {
            let incident = &vertex_quads[quad_offsets[v] as usize..quad_offsets[v + 1] as usize];
            quad_count[v] = incident.len() as u32;
            // Each quad is a wedge at v swept counter-clockwise from `next` to `prev`.
            wedges.clear();
            for &qi in incident {
                let q = &quads[qi as usize];
                let i = q.iter().position(|&x| x as usize == v).unwrap_or(0);
                wedges.push((q[(i + 1) % 4], q[(i + 2) % 4], q[(i + 3) % 4]));
            }
            kind[v] = chain_wedges(&mut wedges);
            match kind[v] {
                VertexKind::Interior | VertexKind::Boundary => {
                    for &(from, diag, _) in wedges.iter() {
                        ring.push(from);
                        full_ring.push(from);
                        full_ring.push(diag);
                    }
                    if kind[v] == VertexKind::Boundary {
                        let last = wedges[wedges.len() - 1].2;
                        ring.push(last);
                        full_ring.push(last);
                        boundary_next[v] = wedges[0].0;
                    }
                }
                // Several fans: no ring, the vertex never moves.
                VertexKind::NonManifold | VertexKind::Unused => {}
            }
            ring_offsets.push(ring.len() as u32);
            full_offsets.push(full_ring.len() as u32);
        }

        let (loop_offsets, loops) = trace_loops(quads, &kind, &boundary_next, &quad_offsets, &vertex_quads);
        Topology {
            kind,
            quad_count,
            ring_offsets,
            ring,
            full_offsets,
            full_ring,
            loop_offsets,
            loops,
            quad_offsets,
            vertex_quads,
        }
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.kind.len()
    }

    /// How vertex `v` sits in the mesh.
    pub fn kind(&self, v: usize) -> VertexKind {
        self.kind[v]
    }

    /// Number of quads incident to vertex `v`.
    pub fn quad_count(&self, v: usize) -> usize {
        self.quad_count[v] as usize
    }

    /// Edge-neighbours of `v`, counter-clockwise (the corners of its embedded polygon).
    pub fn ring(&self, v: usize) -> &[u32] {
        &self.ring[self.ring_offsets[v] as usize..self.ring_offsets[v + 1] as usize]
    }

    /// Edge-neighbours and quad diagonals of `v`, counter-clockwise, alternating.
    pub fn full_ring(&self, v: usize) -> &[u32] {
        &self.full_ring[self.full_offsets[v] as usize..self.full_offsets[v + 1] as usize]
    }

    /// Quads incident to `v`.
    pub fn vertex_quads(&self, v: usize) -> &[u32] {
        &self.vertex_quads[self.quad_offsets[v] as usize..self.quad_offsets[v + 1] as usize]
    }

    /// Number of boundary loops.
    pub fn loop_count(&self) -> usize {
        self.loop_offsets.len() - 1
    }

    /// Vertices of boundary loop `i`, interior on the left.
    pub fn boundary_loop(&self, i: usize) -> &[u32] {
        &self.loops[self.loop_offsets[i] as usize..self.loop_offsets[i + 1] as usize]
    }

    /// Iterates over the boundary loops.
    pub fn boundary_loops(&self) -> impl Iterator<Item = &[u32]> {
        (0..self.loop_count()).map(|i| self.boundary_loop(i))
    }
}

fn incident_wedges(quads: &[[u32; 4]], incident: &[u32], v: usize) -> Vec<(u32, u32, u32)> {
    incident
        .iter()
        .map(|&qi| {
            let q = &quads[qi as usize];
            let i = q.iter().position(|&x| x as usize == v).unwrap_or(0);
            (q[(i + 1) % 4], q[(i + 2) % 4], q[(i + 3) % 4])
        })
        .collect()
}

/// Orders the wedges around a vertex counter-clockwise (each wedge's `prev` is the next
/// wedge's `from`). Returns `Interior` for one closed fan, `Boundary` for one open fan (then
/// the first wedge starts at the boundary), `NonManifold` when they form several fans.
fn chain_wedges(wedges: &mut [(u32, u32, u32)]) -> VertexKind {
    let k = wedges.len();
    if k == 0 {
        return VertexKind::Unused;
    }
    // Start at a wedge whose `from` edge is not the `prev` edge of any other wedge.
    let start = (0..k).find(|&i| !wedges.iter().any(|w| w.2 == wedges[i].0));
    let open = start.is_some();
    wedges.swap(0, start.unwrap_or(0));
    for i in 1..k {
        let want = wedges[i - 1].2;
        match (i..k).find(|&j| wedges[j].0 == want) {
            Some(j) => wedges.swap(i, j),
            None => return VertexKind::NonManifold,
        }
    }
    match (open, wedges[k - 1].2 == wedges[0].0) {
        (false, true) => VertexKind::Interior,
        (true, _) => VertexKind::Boundary,
        (false, false) => VertexKind::NonManifold,
    }
}

/// Follows boundary edges into closed loops. A boundary edge runs v -> boundary_next[v]; at a
/// non-manifold vertex the successor is found by matching the incoming edge's quad fan.
fn trace_loops(
    quads: &[[u32; 4]],
    kind: &[VertexKind],
    boundary_next: &[u32],
    quad_offsets: &[u32],
    vertex_quads: &[u32],
) -> (Vec<u32>, Vec<u32>) {
    // Directed boundary edges out of every vertex (a bowtie vertex has several).
    let n = kind.len();
    let mut out_edges: Vec<Vec<u32>> = Vec::new();
    let needs_general = kind.contains(&VertexKind::NonManifold);
    if needs_general {
        out_edges = vec![Vec::new(); n];
        for v in 0..n {
            if kind[v] != VertexKind::NonManifold {
                continue;
            }
            let incident = &vertex_quads[quad_offsets[v] as usize..quad_offsets[v + 1] as usize];
            let w = incident_wedges(quads, incident, v);
            for &(from, _, _) in &w {
                if !w.iter().any(|x| x.2 == from) {
                    out_edges[v].push(from);
                }
            }
        }
    }
    let mut used_out: Vec<Vec<bool>> = out_edges.iter().map(|e| vec![false; e.len()]).collect();
    let mut visited = vec![false; n];
    let mut offsets = vec![0u32];
    let mut loops = Vec::new();
    for start in 0..n {
        let starts_here = match kind[start] {
            VertexKind::Boundary => !visited[start],
            _ => false,
        };
        if !starts_here {
            continue;
        }
        let mut v = start;
        loop {
            loops.push(v as u32);
            visited[v] = true;
            let next = if kind[v] == VertexKind::NonManifold {
                match used_out[v].iter().position(|&u| !u) {
                    Some(i) => {
                        used_out[v][i] = true;
                        out_edges[v][i]
                    }
                    None => break,
                }
            } else {
                boundary_next[v]
            };
            if next == u32::MAX || next as usize == start {
                break;
            }
            v = next as usize;
            if kind[v] != VertexKind::NonManifold && visited[v] {
                break;
            }
            if loops.len() - *offsets.last().unwrap() as usize > n {
                break;
            }
        }
        offsets.push(loops.len() as u32);
    }
    (offsets, loops)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    /// An `nx` by `ny` grid of unit squares, vertex (i, j) at index j * (nx + 1) + i.
    pub(crate) fn grid(nx: u32, ny: u32) -> QuadMesh {
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
        QuadMesh::new(p, q, None).unwrap()
    }

    #[test]
    fn grid_rings_are_counter_clockwise() {
        let t = Topology::new(&grid(2, 2));
        // Centre vertex 4: neighbours 5 (east), 7 (north), 3 (west), 1 (south), some rotation.
        assert_eq!(t.kind(4), VertexKind::Interior);
        let r = t.ring(4);
        let s = r.iter().position(|&x| x == 5).unwrap();
        let rotated: Vec<u32> = (0..4).map(|k| r[(s + k) % 4]).collect();
        assert_eq!(rotated, vec![5, 7, 3, 1]);
        let f = t.full_ring(4);
        assert_eq!(f.len(), 8);
        // Bottom edge middle vertex 1: boundary, next along the loop first (east, 2), previous last (0).
        assert_eq!(t.kind(1), VertexKind::Boundary);
        assert_eq!(t.ring(1), &[2, 4, 0]);
        assert_eq!(t.quad_count(0), 1);
    }

    #[test]
    fn outer_loop_is_counter_clockwise_and_complete() {
        let t = Topology::new(&grid(3, 2));
        assert_eq!(t.loop_count(), 1);
        let l = t.boundary_loop(0);
        assert_eq!(l.len(), 10);
        for w in 0..l.len() {
            // Interior is on the left: consecutive loop vertices are boundary-ring first neighbours.
            assert_eq!(t.ring(l[w] as usize)[0], l[(w + 1) % l.len()]);
        }
    }

    #[test]
    fn hole_gives_second_loop() {
        // 3x3 grid without its centre quad.
        let g = grid(3, 3);
        let quads: Vec<[u32; 4]> =
            g.quads().iter().enumerate().filter(|(i, _)| *i != 4).map(|(_, q)| *q).collect();
        let m = QuadMesh::new(g.points().to_vec(), quads, None).unwrap();
        let t = Topology::new(&m);
        assert_eq!(t.loop_count(), 2);
        let mut lens: Vec<usize> = t.boundary_loops().map(|l| l.len()).collect();
        lens.sort();
        assert_eq!(lens, vec![4, 12]);
    }

    #[test]
    fn bowtie_vertex_is_non_manifold() {
        // Two squares touching at one vertex (2).
        let p = [(0., 0.), (1., 0.), (1., 1.), (0., 1.), (2., 1.), (2., 2.), (1., 2.)];
        let p = p.iter().map(|&(x, y)| DVec2::new(x, y)).collect();
        let m = QuadMesh::new(p, vec![[0, 1, 2, 3], [2, 4, 5, 6]], None).unwrap();
        let t = Topology::new(&m);
        assert_eq!(t.kind(2), VertexKind::NonManifold);
        assert_eq!(t.kind(0), VertexKind::Boundary);
        let total: usize = t.boundary_loops().map(|l| l.len()).sum();
        assert_eq!(total, 8);
    }
}
