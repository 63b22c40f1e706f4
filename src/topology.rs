//! Connectivity, built once per mesh in flat (CSR) arrays: each vertex's edge-neighbours in
//! counter-clockwise order (the corners of its embedded polygon, Section 3.1), the same ring
//! with the quads' diagonal vertices interleaved (for Xu and Newman's method), and the boundary
//! loops. Everything here depends on connectivity only; which vertices may move is decided per
//! run from the geometry in [`crate::features`].

use crate::alloc::{out_of_memory, try_copy, try_filled, try_with_capacity};
use crate::error::{Error, Result};
use crate::face::{self, NO_VERTEX};
use crate::mesh::Mesh;

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

/// One-rings and boundary loops of a [`Mesh`].
#[derive(Clone, Debug)]
pub struct Topology {
    kind: Vec<VertexKind>,
    ring_offsets: Vec<u32>,
    /// Edge-neighbours, counter-clockwise. For a boundary vertex the first is the next vertex
    /// along its boundary loop and the last the previous one.
    ring: Vec<u32>,
    loop_offsets: Vec<u32>,
    /// Boundary loops, with the mesh interior on the left (outer boundaries counter-clockwise).
    loops: Vec<u32>,
    quad_offsets: Vec<u32>,
    /// Quads incident to each vertex.
    vertex_quads: Vec<u32>,
    colour_offsets: Vec<u32>,
    /// Vertices with a ring, grouped so that no two vertices of a group share a quad.
    colours: Vec<u32>,
}

/// A wedge of a face at a vertex v: the face's vertices after v, counter-clockwise (`from`,
/// the edge-neighbour after v; `diag`, the opposite vertex of a quad, [`NO_VERTEX`] for a
/// triangle; `prev`, the edge-neighbour before v). Around v the wedges chain by `prev` of one
/// = `from` of the next, whatever the kinds of the faces.
type Wedge = (u32, u32, u32);

/// Marks "no entry" in the per-vertex scratch of [`chain_wedges`] and [`trace_loops`].
const NONE: u32 = u32::MAX;

impl Topology {
    /// Builds the connectivity of `mesh`. Panics if memory runs out; [`Topology::try_new`]
    /// returns an error instead.
    pub fn new(mesh: &Mesh) -> Topology {
        Topology::try_new(mesh).unwrap_or_else(|e| panic!("{e}"))
    }

    /// Builds the connectivity of `mesh` in time linear in its size, whatever the number of
    /// quads at a vertex; [`Error::OutOfMemory`] if an array cannot be allocated (or would be
    /// too long for its 32-bit offsets).
    pub fn try_new(mesh: &Mesh) -> Result<Topology> {
        Topology::try_from_faces(mesh.points().len(), mesh.quads())
    }

    /// [`Topology::try_new`] from the connectivity alone: `n` vertices and consistently
    /// oriented `quads` (triangles with [`NO_VERTEX`] fourth), whatever the coordinates
    /// (a surface in 3D uses it too; "counter-clockwise" is then the faces' winding).
    pub fn try_from_faces(n: usize, quads: &[[u32; 4]]) -> Result<Topology> {
        // Longest array: the rings, one entry per wedge plus one per boundary vertex.
        let ring_len = (quads.len() as u64 * 4).saturating_add(n as u64);
        if ring_len > u32::MAX as u64 {
            return Err(Error::OutOfMemory {
                what: "the topology (more entries than 32-bit offsets can address)",
                bytes: ring_len as u128 * size_of::<u32>() as u128,
            });
        }
        let mut quad_offsets = try_filled(n + 1, 0u32, "topology: quad offsets")?;
        for q in quads {
            for &v in face::vertices(q) {
                quad_offsets[v as usize + 1] += 1;
            }
        }
        let mut max_quads = 0;
        for v in 0..n {
            max_quads = max_quads.max(quad_offsets[v + 1]);
            quad_offsets[v + 1] += quad_offsets[v];
        }
        let mut fill = try_copy(&quad_offsets, "topology: scratch")?;
        let mut vertex_quads = try_filled(quads.len() * 4, 0u32, "topology: vertex quads")?;
        // Sized for quads; a triangle leaves its fourth entry unused at the end.
        for (qi, q) in quads.iter().enumerate() {
            for &v in face::vertices(q) {
                vertex_quads[fill[v as usize] as usize] = qi as u32;
                fill[v as usize] += 1;
            }
        }
        drop(fill);
        vertex_quads.truncate(quad_offsets[n] as usize);

        let mut kind = try_filled(n, VertexKind::Unused, "topology: vertex kinds")?;
        let mut ring_offsets = try_with_capacity(n + 1, "topology: ring offsets")?;
        let mut ring = try_with_capacity(quads.len() * 4 + n, "topology: rings")?;
        // Boundary successor of each boundary vertex (for loop tracing), and scratch wedges.
        let mut boundary_next = try_filled(n, NONE, "topology: boundary successors")?;
        let mut scratch = ChainScratch::new(n, max_quads as usize)?;
        let mut wedges: Vec<Wedge> = try_with_capacity(max_quads as usize, "topology: scratch")?;
        ring_offsets.push(0);
        for v in 0..n {
            let incident = &vertex_quads[quad_offsets[v] as usize..quad_offsets[v + 1] as usize];
            wedges.clear();
            wedges.extend(incident.iter().map(|&qi| wedge(&quads[qi as usize], v)));
            kind[v] = chain_wedges(&wedges, &mut scratch);
            match kind[v] {
                VertexKind::Interior | VertexKind::Boundary => {
                    let chain = &scratch.chain;
                    ring.extend(chain.iter().map(|&(from, _, _)| from));
                    if kind[v] == VertexKind::Boundary {
                        ring.push(chain[chain.len() - 1].2);
                        boundary_next[v] = chain[0].0;
                    }
                }
                // Several fans: no ring, the vertex never moves.
                VertexKind::NonManifold | VertexKind::Unused => {}
            }
            ring_offsets.push(ring.len() as u32);
        }
        drop(wedges);

        let (loop_offsets, loops) =
            trace_loops(quads, &kind, &boundary_next, &quad_offsets, &vertex_quads, &mut scratch.slot)?;
        drop(scratch);
        let (colour_offsets, colours) = colour_classes(&kind, quads, &quad_offsets, &vertex_quads)?;
        Ok(Topology {
            kind,
            ring_offsets,
            ring,
            loop_offsets,
            loops,
            quad_offsets,
            vertex_quads,
            colour_offsets,
            colours,
        })
    }

    /// Number of colour classes.
    pub fn colour_count(&self) -> usize {
        self.colour_offsets.len() - 1
    }

    /// Colour class `c`: vertices (ascending) no two of which share a quad, so they can be
    /// moved at the same time without one reading a position another is changing.
    pub fn colour_class(&self, c: usize) -> &[u32] {
        &self.colours[self.colour_offsets[c] as usize..self.colour_offsets[c + 1] as usize]
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
        (self.quad_offsets[v + 1] - self.quad_offsets[v]) as usize
    }

    /// Edge-neighbours of `v`, counter-clockwise (the corners of its embedded polygon).
    pub fn ring(&self, v: usize) -> &[u32] {
        &self.ring[self.ring_offsets[v] as usize..self.ring_offsets[v + 1] as usize]
    }

    /// Every other vertex of the faces of `v` (its edge-neighbours twice, its quads' diagonal
    /// vertices once), in no particular order;
    /// none for a vertex without a ring. `quads` must be the mesh's. Computed from the faces
    /// rather than stored: 36 bytes a vertex less.
    pub fn star_vertices<'a>(&'a self, quads: &'a [[u32; 4]], v: usize) -> impl Iterator<Item = u32> + 'a {
        let with_ring = matches!(self.kind[v], VertexKind::Interior | VertexKind::Boundary);
        let star = if with_ring { self.vertex_quads(v) } else { &[] };
        star.iter()
            .flat_map(move |&qi| {
                let (from, diag, prev) = wedge(&quads[qi as usize], v);
                [from, diag, prev]
            })
            .filter(|&u| u != NO_VERTEX)
    }

    /// Edge-neighbours and quad diagonals of `v`, counter-clockwise, alternating (for a
    /// boundary vertex the ring's last vertex ends it), into `out`. `quads` must be the mesh's.
    pub fn full_ring_into(&self, quads: &[[u32; 4]], v: usize, out: &mut Vec<u32>) {
        out.clear();
        let ring = self.ring(v);
        let closed = self.kind[v] == VertexKind::Interior;
        // Each quad's corner after v and its diagonal vertex, sorted by that corner (one quad
        // per ring entry in a fan), so that a vertex of many quads takes k log k, not k^2.
        let mut diagonals: Vec<(u32, u32)> = self
            .vertex_quads(v)
            .iter()
            .filter_map(|&qi| {
                let (from, diag, _) = wedge(&quads[qi as usize], v);
                // A triangle has no diagonal vertex: its ring entries are adjacent.
                (diag != NO_VERTEX).then_some((from, diag))
            })
            .collect();
        diagonals.sort_unstable();
        for (i, &from) in ring.iter().enumerate() {
            out.push(from);
            if !closed && i + 1 == ring.len() {
                break;
            }
            if let Ok(at) = diagonals.binary_search_by_key(&from, |&(corner, _)| corner) {
                out.push(diagonals[at].1);
            }
        }
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

/// The wedge of face `q` at its vertex `v`.
fn wedge(q: &[u32; 4], v: usize) -> Wedge {
    face::after(q, face::position(q, v as u32).unwrap_or(0))
}

/// Greedy colouring of the vertices that have a ring, over the "shares a quad" graph (edge
/// and diagonal neighbours), in vertex order so the result is deterministic. A vertex with d
/// neighbours takes a colour <= d, so only colours up to d are looked at: linear time.
fn colour_classes(
    kind: &[VertexKind],
    quads: &[[u32; 4]],
    quad_offsets: &[u32],
    vertex_quads: &[u32],
) -> Result<(Vec<u32>, Vec<u32>)> {
    let n = kind.len();
    let mut colour = try_filled(n, NONE, "topology: colours")?;
    // A vertex of k quads has at most 2k + 1 neighbours (k + 1 edge-neighbours on the
    // boundary, k diagonals): it takes a colour <= 2k + 1.
    let widest = quad_offsets.windows(2).map(|w| 2 * (w[1] - w[0]) as usize + 1).max().unwrap_or(0);
    let mut taken: Vec<bool> = try_with_capacity(widest + 1, "topology: scratch")?;
    let mut count = 0u32;
    for v in 0..n {
        if !matches!(kind[v], VertexKind::Interior | VertexKind::Boundary) {
            continue;
        }
        let star = &vertex_quads[quad_offsets[v] as usize..quad_offsets[v + 1] as usize];
        let bound = 2 * star.len() + 1;
        taken.clear();
        taken.resize(bound + 1, false);
        for &qi in star {
            for &u in face::vertices(&quads[qi as usize]) {
                if u as usize != v {
                    if let Some(t) = taken.get_mut(colour[u as usize] as usize) {
                        *t = true;
                    }
                }
            }
        }
        let c = taken.iter().position(|&t| !t).unwrap_or(bound) as u32;
        colour[v] = c;
        count = count.max(c + 1);
    }
    let mut offsets = try_filled(count as usize + 1, 0u32, "topology: colour offsets")?;
    for &c in &colour {
        if c != NONE {
            offsets[c as usize + 1] += 1;
        }
    }
    for c in 0..count as usize {
        offsets[c + 1] += offsets[c];
    }
    let mut fill = try_copy(&offsets, "topology: scratch")?;
    let mut members = try_filled(offsets[count as usize] as usize, 0u32, "topology: colour classes")?;
    for (v, &c) in colour.iter().enumerate() {
        if c != NONE {
            members[fill[c as usize] as usize] = v as u32;
            fill[c as usize] += 1;
        }
    }
    Ok((offsets, members))
}

/// Scratch space of [`chain_wedges`], allocated once for all vertices.
struct ChainScratch {
    /// Per mesh vertex: index of the wedge whose `from` it is, [`NONE`] between calls.
    slot: Vec<u32>,
    /// Per wedge: index of the wedge after it (whose `from` is its `prev`), or [`NONE`].
    next: Vec<u32>,
    /// Per wedge: whether some wedge comes before it.
    has_prev: Vec<bool>,
    /// The wedges in counter-clockwise order.
    chain: Vec<Wedge>,
}

impl ChainScratch {
    fn new(vertices: usize, max_wedges: usize) -> Result<ChainScratch> {
        Ok(ChainScratch {
            slot: try_filled(vertices, NONE, "topology: scratch")?,
            next: try_with_capacity(max_wedges, "topology: scratch")?,
            has_prev: try_with_capacity(max_wedges, "topology: scratch")?,
            chain: try_with_capacity(max_wedges, "topology: scratch")?,
        })
    }
}

/// Orders the wedges around a vertex counter-clockwise into `scratch.chain` (each wedge's
/// `prev` is the next wedge's `from`). Returns `Interior` for one closed fan, `Boundary` for
/// one open fan (then the chain starts at the first wedge, in the given order, that nothing
/// precedes: the boundary), `NonManifold` when they form several fans. Linear in the number
/// of wedges: successors are looked up through `scratch.slot`.
fn chain_wedges(wedges: &[Wedge], scratch: &mut ChainScratch) -> VertexKind {
    let ChainScratch { slot, next, has_prev, chain } = scratch;
    chain.clear();
    let k = wedges.len();
    if k == 0 {
        return VertexKind::Unused;
    }
    // In a consistently oriented mesh each directed edge is in one quad, so no two wedges
    // share a `from` (nor a `prev`); a repeat is treated as several fans.
    let mut repeated = false;
    for (i, w) in wedges.iter().enumerate() {
        let s = &mut slot[w.0 as usize];
        repeated |= *s != NONE;
        *s = i as u32;
    }
    next.clear();
    next.extend(wedges.iter().map(|w| slot[w.2 as usize]));
    has_prev.clear();
    has_prev.resize(k, false);
    for &j in next.iter().filter(|&&j| j != NONE) {
        repeated |= has_prev[j as usize];
        has_prev[j as usize] = true;
    }
    for w in wedges {
        slot[w.0 as usize] = NONE;
    }
    if repeated {
        return VertexKind::NonManifold;
    }
    let start = has_prev.iter().position(|&p| !p);
    let open = start.is_some();
    let start = start.unwrap_or(0) as u32;
    let mut at = start;
    loop {
        chain.push(wedges[at as usize]);
        if chain.len() == k {
            break;
        }
        at = next[at as usize];
        if at == NONE || at == start {
            return VertexKind::NonManifold;
        }
    }
    match (open, chain[k - 1].2 == chain[0].0) {
        (false, true) => VertexKind::Interior,
        (true, _) => VertexKind::Boundary,
        (false, false) => VertexKind::NonManifold,
    }
}

/// Follows boundary edges into closed loops. A boundary edge runs v -> `boundary_next[v]`; a
/// non-manifold vertex has several outgoing boundary edges, taken in turn. `slot` is per-vertex
/// scratch holding [`NONE`] on entry and on return.
fn trace_loops(
    quads: &[[u32; 4]],
    kind: &[VertexKind],
    boundary_next: &[u32],
    quad_offsets: &[u32],
    vertex_quads: &[u32],
    slot: &mut [u32],
) -> Result<(Vec<u32>, Vec<u32>)> {
    let n = kind.len();
    // Outgoing boundary edges of the non-manifold vertices, in CSR form: the wedges' `from`s
    // that are no wedge's `prev`, in incident order.
    let mut out_offsets: Vec<u32> = Vec::new();
    let mut out_edges: Vec<u32> = Vec::new();
    let mut out_used: Vec<u32> = Vec::new();
    let boundary_vertices = kind.iter().filter(|&&k| k == VertexKind::Boundary).count();
    let mut boundary_edges = boundary_vertices;
    if kind.contains(&VertexKind::NonManifold) {
        out_offsets = try_filled(n + 1, 0u32, "topology: boundary edges")?;
        out_used = try_filled(n, 0u32, "topology: boundary edges")?;
        for v in 0..n {
            out_offsets[v + 1] = out_offsets[v];
            if kind[v] != VertexKind::NonManifold {
                continue;
            }
            let incident = &vertex_quads[quad_offsets[v] as usize..quad_offsets[v + 1] as usize];
            let wedges = || incident.iter().map(|&qi| wedge(&quads[qi as usize], v));
            for (_, _, prev) in wedges() {
                slot[prev as usize] = 0;
            }
            let count = wedges().filter(|&(from, _, _)| slot[from as usize] == NONE).count();
            out_edges
                .try_reserve(count)
                .map_err(|_| out_of_memory::<u32>("topology: boundary edges", count))?;
            out_edges.extend(wedges().map(|w| w.0).filter(|&from| slot[from as usize] == NONE));
            for (_, _, prev) in wedges() {
                slot[prev as usize] = NONE;
            }
            out_offsets[v + 1] = out_edges.len() as u32;
        }
        boundary_edges += out_edges.len();
    }
    let mut visited = try_filled(n, false, "topology: scratch")?;
    // Every loop starts at a boundary vertex (never at a non-manifold one).
    let mut offsets = try_with_capacity(boundary_vertices + 1, "topology: boundary loops")?;
    offsets.push(0u32);
    let mut loops = try_with_capacity(boundary_edges, "topology: boundary loops")?;
    for start in 0..n {
        if kind[start] != VertexKind::Boundary || visited[start] {
            continue;
        }
        let mut v = start;
        loop {
            loops.push(v as u32);
            visited[v] = true;
            let next = if kind[v] == VertexKind::NonManifold {
                // The next unused outgoing edge (they are used in order).
                let used = &mut out_used[v];
                if out_offsets[v] + *used == out_offsets[v + 1] {
                    break;
                }
                *used += 1;
                out_edges[(out_offsets[v] + *used - 1) as usize]
            } else {
                boundary_next[v]
            };
            if next == NONE || next as usize == start {
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
    Ok((offsets, loops))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    use crate::test_meshes::grid;

    #[test]
    fn grid_rings_are_counter_clockwise() {
        let m = grid(2, 2);
        let t = Topology::new(&m);
        // Centre vertex 4: neighbours 5 (east), 7 (north), 3 (west), 1 (south), some rotation.
        assert_eq!(t.kind(4), VertexKind::Interior);
        let r = t.ring(4);
        let s = r.iter().position(|&x| x == 5).unwrap();
        let rotated: Vec<u32> = (0..4).map(|k| r[(s + k) % 4]).collect();
        assert_eq!(rotated, vec![5, 7, 3, 1]);
        // The full ring puts each quad's diagonal vertex between its two edge-neighbours.
        let mut f = Vec::new();
        t.full_ring_into(m.quads(), 4, &mut f);
        let rotated: Vec<u32> = (0..8).map(|k| f[(2 * s + k) % 8]).collect();
        assert_eq!(rotated, vec![5, 8, 7, 6, 3, 0, 1, 2]);
        // Bottom edge middle vertex 1: boundary, next along the loop first (east, 2), previous last (0).
        assert_eq!(t.kind(1), VertexKind::Boundary);
        assert_eq!(t.ring(1), &[2, 4, 0]);
        t.full_ring_into(m.quads(), 1, &mut f);
        assert_eq!(f, vec![2, 5, 4, 3, 0]);
        // Every other vertex of its quads: the edge-neighbours twice, the diagonals once.
        let mut star: Vec<u32> = t.star_vertices(m.quads(), 1).collect();
        star.sort();
        assert_eq!(star, vec![0, 2, 3, 4, 4, 5]);
        assert_eq!(t.quad_count(0), 1);
    }

    #[test]
    fn colour_classes_never_share_a_quad_and_cover_every_vertex() {
        let m = grid(5, 4);
        let t = Topology::new(&m);
        let mut seen = vec![0; t.vertex_count()];
        for c in 0..t.colour_count() {
            for &v in t.colour_class(c) {
                seen[v as usize] += 1;
                for u in t.star_vertices(m.quads(), v as usize) {
                    assert!(!t.colour_class(c).contains(&u), "{v} and {u} share colour {c}");
                }
            }
        }
        assert!(seen.iter().all(|&s| s == 1));
        // A structured grid needs exactly four colours.
        assert_eq!(t.colour_count(), 4);
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
        let m = Mesh::new(g.points().to_vec(), quads, None).unwrap();
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
        let m = Mesh::new(p, vec![[0, 1, 2, 3], [2, 4, 5, 6]], None).unwrap();
        let t = Topology::new(&m);
        assert_eq!(t.kind(2), VertexKind::NonManifold);
        assert_eq!(t.kind(0), VertexKind::Boundary);
        let total: usize = t.boundary_loops().map(|l| l.len()).sum();
        assert_eq!(total, 8);
    }
}
