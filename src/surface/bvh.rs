//! The bounding-volume hierarchy over the reference surface's triangles: axis-aligned boxes
//! in a flat array, built by binned surface-area heuristic, queried for the closest point.

use glam::DVec3;

use super::reference::closest_point_on_triangle;
use crate::alloc::{try_push, try_with_capacity};
use crate::error::Result;

/// `v.x² + v.y² + v.z²` in this order: the box distance and the triangle distance are computed
/// by the same expression, so rounding (monotone) keeps the first no greater than the second.
#[inline]
pub(crate) fn squared_length(v: DVec3) -> f64 {
    v.x * v.x + v.y * v.y + v.z * v.z
}

/// A node: a leaf holds `count > 0` triangles, `items[first..first + count]`; an inner node
/// (`count == 0`) has its left child right after it and its right child at `first`.
#[derive(Clone, Copy, Debug)]
struct Node {
    lo: DVec3,
    hi: DVec3,
    first: u32,
    count: u32,
}

/// Leaves hold at most this many triangles, unless they cannot be split (equal centroids)
/// or the tree is at its depth limit.
const LEAF_SIZE: usize = 4;
/// Bins per axis of the surface-area heuristic.
const BINS: usize = 16;
/// The deepest a node can be (the root is at depth 0); a query's stack holds at most one
/// entry per level.
const MAX_DEPTH: usize = 60;
/// The cost of visiting a node, in units of one triangle test, for the heuristic.
const TRAVERSAL_COST: f64 = 1.0;

#[derive(Clone, Debug)]
pub(crate) struct Bvh {
    nodes: Vec<Node>,
    /// Triangle numbers in leaf order.
    items: Vec<u32>,
    /// The corners of `items[i]`, stored in the same order so a leaf reads contiguous memory.
    corners: Vec<[DVec3; 3]>,
}

#[derive(Clone, Copy)]
struct Bounds {
    lo: DVec3,
    hi: DVec3,
}

impl Bounds {
    const EMPTY: Bounds = Bounds { lo: DVec3::INFINITY, hi: DVec3::NEG_INFINITY };
    fn grow(&mut self, other: &Bounds) {
        self.lo = self.lo.min(other.lo);
        self.hi = self.hi.max(other.hi);
    }
    fn grow_point(&mut self, p: DVec3) {
        self.lo = self.lo.min(p);
        self.hi = self.hi.max(p);
    }
    /// Half the surface area (the heuristic only compares areas); 0 for an empty box.
    fn half_area(&self) -> f64 {
        let d = self.hi - self.lo;
        if d.x < 0.0 { 0.0 } else { d.x * d.y + d.y * d.z + d.z * d.x }
    }
}

/// A node still to build: the items `start..end`, at `depth`; `parent` is the inner node whose
/// right child it is (`u32::MAX` for the root and for left children).
struct Task {
    start: usize,
    end: usize,
    depth: usize,
    parent: u32,
}

impl Bvh {
    pub(crate) fn new(points: &[DVec3], triangles: &[[u32; 3]]) -> Result<Bvh> {
        let n = triangles.len();
        let mut boxes: Vec<Bounds> = try_with_capacity(n, "reference tree boxes")?;
        let mut centroids: Vec<DVec3> = try_with_capacity(n, "reference tree centroids")?;
        for t in triangles {
            let [a, b, c] = t.map(|v| points[v as usize]);
            boxes.push(Bounds { lo: a.min(b).min(c), hi: a.max(b).max(c) });
            centroids.push((a + b + c) / 3.0);
        }
        let mut items: Vec<u32> = try_with_capacity(n, "reference tree items")?;
        items.extend(0..n as u32);
        let mut nodes: Vec<Node> = try_with_capacity(2 * n.max(1), "reference tree nodes")?;
        let mut tasks: Vec<Task> = try_with_capacity(2 * MAX_DEPTH + 2, "reference tree tasks")?;
        tasks.push(Task { start: 0, end: n, depth: 0, parent: u32::MAX });
        while let Some(task) = tasks.pop() {
            let index = nodes.len() as u32;
            if task.parent != u32::MAX {
                nodes[task.parent as usize].first = index;
            }
            let range = task.start..task.end;
            let mut bounds = Bounds::EMPTY;
            let mut centre_bounds = Bounds::EMPTY;
            for &t in &items[range.clone()] {
                bounds.grow(&boxes[t as usize]);
                centre_bounds.grow_point(centroids[t as usize]);
            }
            let split = if task.end - task.start <= LEAF_SIZE || task.depth >= MAX_DEPTH {
                None
            } else {
                split(&mut items[range], &boxes, &centroids, &bounds, &centre_bounds)
            };
            match split {
                None => {
                    let count = (task.end - task.start) as u32;
                    try_push(
                        &mut nodes,
                        Node { lo: bounds.lo, hi: bounds.hi, first: task.start as u32, count },
                        "reference tree nodes",
                    )?;
                }
                Some(left_count) => {
                    try_push(
                        &mut nodes,
                        Node { lo: bounds.lo, hi: bounds.hi, first: 0, count: 0 },
                        "reference tree nodes",
                    )?;
                    let mid = task.start + left_count;
                    let depth = task.depth + 1;
                    // Left first: it is popped next and so lands right after its parent.
                    try_push(
                        &mut tasks,
                        Task { start: mid, end: task.end, depth, parent: index },
                        "reference tree tasks",
                    )?;
                    try_push(
                        &mut tasks,
                        Task { start: task.start, end: mid, depth, parent: u32::MAX },
                        "reference tree tasks",
                    )?;
                }
            }
        }
        let mut corners: Vec<[DVec3; 3]> = try_with_capacity(n, "reference tree corners")?;
        corners.extend(items.iter().map(|&t| triangles[t as usize].map(|v| points[v as usize])));
        Ok(Bvh { nodes, items, corners })
    }

    /// The closest point to `p` of all triangles: `(squared distance, triangle, point)`, the
    /// smallest squared distance and of those the lowest triangle number. `start`, if given,
    /// is one triangle's answer, which bounds the search from the beginning.
    pub(crate) fn closest(&self, p: DVec3, start: Option<(f64, u32, DVec3)>) -> (f64, u32, DVec3) {
        let mut best = start.unwrap_or((f64::INFINITY, u32::MAX, DVec3::ZERO));
        let mut stack = [(0u32, 0f64); MAX_DEPTH + 1];
        let mut top = 0;
        let mut node = 0u32;
        let mut node_d2 = box_distance2(&self.nodes[0], p);
        loop {
            if node_d2 <= best.0 {
                let n = &self.nodes[node as usize];
                if n.count > 0 {
                    let range = n.first as usize..(n.first + n.count) as usize;
                    for (&t, &[a, b, c]) in self.items[range.clone()].iter().zip(&self.corners[range]) {
                        let (q, _) = closest_point_on_triangle(p, a, b, c);
                        let d2 = squared_length(p - q);
                        if d2 < best.0 || (d2 == best.0 && t < best.1) {
                            best = (d2, t, q);
                        }
                    }
                } else {
                    let (left, right) = (node + 1, n.first);
                    let dl = box_distance2(&self.nodes[left as usize], p);
                    let dr = box_distance2(&self.nodes[right as usize], p);
                    let ((near, dn), (far, df)) =
                        if dr < dl { ((right, dr), (left, dl)) } else { ((left, dl), (right, dr)) };
                    if df <= best.0 {
                        stack[top] = (far, df);
                        top += 1;
                    }
                    node = near;
                    node_d2 = dn;
                    continue;
                }
            }
            if top == 0 {
                break;
            }
            top -= 1;
            (node, node_d2) = stack[top];
        }
        best
    }

    /// Node count, leaf count, depth.
    pub(crate) fn shape(&self) -> (usize, usize, usize) {
        let leaves = self.nodes.iter().filter(|n| n.count > 0).count();
        let mut depth = 0;
        let mut stack = vec![(0usize, 0usize)];
        while let Some((i, d)) = stack.pop() {
            depth = depth.max(d);
            let n = &self.nodes[i];
            if n.count == 0 {
                stack.push((i + 1, d + 1));
                stack.push((n.first as usize, d + 1));
            }
        }
        (self.nodes.len(), leaves, depth)
    }
}

/// The squared distance from `p` to the node's box, 0 inside: per axis the same subtraction
/// as the triangle distance's, so it is never greater than the computed distance to any
/// point in the box.
#[inline]
fn box_distance2(n: &Node, p: DVec3) -> f64 {
    let below = n.lo - p;
    let above = p - n.hi;
    let gap = below.max(above).max(DVec3::ZERO);
    squared_length(gap)
}

/// Splits `items` (reordering them) by the binned surface-area heuristic: the number of items
/// that go left, or `None` to make a leaf (no split is cheaper than testing them all, and
/// there are no more than 4 x LEAF_SIZE of them). Items with equal centroids are split in
/// halves when there are too many for a leaf.
fn split(
    items: &mut [u32],
    boxes: &[Bounds],
    centroids: &[DVec3],
    bounds: &Bounds,
    centre: &Bounds,
) -> Option<usize> {
    let count = items.len();
    let extent = centre.hi - centre.lo;
    let mut best: Option<(f64, usize, usize)> = None; // (cost, axis, last bin on the left)
    for axis in 0..3 {
        if extent[axis] <= 0.0 {
            continue;
        }
        let scale = BINS as f64 / extent[axis];
        let bin_of =
            |t: u32| (((centroids[t as usize][axis] - centre.lo[axis]) * scale) as usize).min(BINS - 1);
        let mut bin_bounds = [Bounds::EMPTY; BINS];
        let mut bin_count = [0usize; BINS];
        for &t in items.iter() {
            let b = bin_of(t);
            bin_bounds[b].grow(&boxes[t as usize]);
            bin_count[b] += 1;
        }
        // Areas and counts of the left sides (bins 0..=i) and right sides (bins i+1..).
        let mut left_area = [0.0; BINS];
        let mut left_count = [0usize; BINS];
        let mut acc = Bounds::EMPTY;
        let mut acc_count = 0;
        for i in 0..BINS - 1 {
            acc.grow(&bin_bounds[i]);
            acc_count += bin_count[i];
            left_area[i] = acc.half_area();
            left_count[i] = acc_count;
        }
        let mut acc = Bounds::EMPTY;
        let mut acc_count = 0;
        for i in (0..BINS - 1).rev() {
            acc.grow(&bin_bounds[i + 1]);
            acc_count += bin_count[i + 1];
            if left_count[i] == 0 || acc_count == 0 {
                continue;
            }
            let cost = left_area[i] * left_count[i] as f64 + acc.half_area() * acc_count as f64;
            if best.is_none_or(|(c, _, _)| cost < c) {
                best = Some((cost, axis, i));
            }
        }
    }
    let Some((cost, axis, last)) = best else {
        // All centroids equal: halves, if too many for one leaf.
        return (count > LEAF_SIZE).then_some(count / 2);
    };
    let area = bounds.half_area();
    let leaf_cost = count as f64;
    let split_cost = TRAVERSAL_COST + if area > 0.0 { cost / area } else { count as f64 };
    if split_cost >= leaf_cost && count <= 4 * LEAF_SIZE {
        return None;
    }
    let scale = BINS as f64 / extent[axis];
    let goes_left =
        |t: u32| (((centroids[t as usize][axis] - centre.lo[axis]) * scale) as usize).min(BINS - 1) <= last;
    // In-place partition, stable enough for determinism (it depends only on the input).
    let mut i = 0;
    let mut j = count;
    while i < j {
        if goes_left(items[i]) {
            i += 1;
        } else {
            j -= 1;
            items.swap(i, j);
        }
    }
    Some(i)
}
