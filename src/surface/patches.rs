//! Smooth patches of a surface and the reference surface of each, with its normals.
//!
//! Feature curves cut the input surface into patches (a sphere is one, a box six). A vertex
//! that is on no feature curve lies inside one patch and is projected onto that patch only:
//! projected onto the whole surface, a vertex near a sharp edge could land on the other side
//! of it and fold its faces over the edge.
//!
//! Each patch's normal field is the input's area-weighted vertex normals over that patch's
//! faces alone, interpolated linearly over each reference triangle (Phong): smooth inside a
//! patch, one-sided at its feature curves, so a square corner next to a box's edge scores 1
//! against its own face and not 0.71 against the mean of the two faces' normals.

use glam::DVec3;

use super::features::SurfaceFeatures;
use super::mesh::{SurfaceMesh, face_vector_area};
use super::reference::ReferenceSurface;
use crate::error::Result;
use crate::face::{self, Face};

/// A point of a patch: where a query landed, and the patch's normal there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OnPatch {
    /// The closest point of the patch.
    pub point: DVec3,
    /// Its triangle in the patch's reference (a hint for the next query).
    pub triangle: u32,
    /// The patch's unit normal there.
    pub normal: DVec3,
}

struct Patch {
    /// The patch's own vertices (its faces' corners; the reference is built on those alone,
    /// so a surface of many patches holds each point about once, not once per patch), by
    /// their local number in the reference.
    global: Vec<u32>,
    reference: ReferenceSurface,
    /// The patch's normal at the three corners of each of its reference's triangles.
    corner_normals: Vec<[DVec3; 3]>,
}

/// The patches of a surface mesh, each with its frozen reference surface.
pub struct Patches {
    face_patch: Vec<u32>,
    /// Each face's first triangle in its patch's reference (a quad's second follows it).
    face_triangle: Vec<u32>,
    patches: Vec<Patch>,
    /// One-sided normal of each face's patch at each of its corners, at the input positions
    /// (a triangle's third twice, as [`crate::quality3d::corners`] repeats its corner); at a
    /// corner where that normal does not describe the face (see [`Patches::is_own`]), the
    /// face's own input normal.
    input_corner_normals: Vec<[DVec3; 4]>,
    /// Per face, bit `k` set when corner `k` is measured against the face's own input normal
    /// (frozen: it does not follow the vertex).
    own_normal: Vec<u8>,
}

/// A corner is measured against its face's own input normal when the patch's normal there is
/// further than this from it (degrees): the patch's vertex normal then averages faces on two
/// sides of a crease the feature rule did not cut (a thin blade's edge, a cone's apex), and
/// describes neither side (docs/surfaces.md, "Which faces are folded").
pub const OWN_NORMAL_ANGLE_DEG: f64 = 45.0;

impl Patches {
    /// Cuts `mesh` (at its current, input positions) along the feature edges of `features`.
    pub fn new(mesh: &SurfaceMesh, features: &SurfaceFeatures) -> Result<Patches> {
        let faces = mesh.faces();
        let points = mesh.points();
        // Union-find over faces across the edges that are not features.
        let mut parent: Vec<u32> = (0..faces.len() as u32).collect();
        fn root(parent: &mut [u32], mut f: u32) -> u32 {
            while parent[f as usize] != f {
                parent[f as usize] = parent[parent[f as usize] as usize];
                f = parent[f as usize];
            }
            f
        }
        for (e, kind) in mesh.edges().iter().zip(features.edge_kinds()) {
            if kind.any() || e.is_boundary() {
                continue;
            }
            let (a, b) = (root(&mut parent, e.faces[0]), root(&mut parent, e.faces[1]));
            if a != b {
                parent[a.max(b) as usize] = a.min(b);
            }
        }
        // Patches numbered by their first face.
        let mut face_patch = vec![u32::MAX; faces.len()];
        let mut number = vec![u32::MAX; faces.len()];
        let mut members: Vec<Vec<u32>> = Vec::new();
        for (f, patch) in face_patch.iter_mut().enumerate() {
            let r = root(&mut parent, f as u32) as usize;
            if number[r] == u32::MAX {
                number[r] = members.len() as u32;
                members.push(Vec::new());
            }
            *patch = number[r];
            members[number[r] as usize].push(f as u32);
        }
        // Per face corner, the sum of the vector areas of the same patch's faces at the vertex.
        let mut at_vertex: Vec<Vec<(u32, DVec3)>> = vec![Vec::new(); points.len()];
        for (f, face) in faces.iter().enumerate() {
            let area = face_vector_area(points, face);
            for &v in face::vertices(face) {
                let list = &mut at_vertex[v as usize];
                match list.iter_mut().find(|(p, _)| *p == face_patch[f]) {
                    Some((_, sum)) => *sum += area,
                    None => list.push((face_patch[f], area)),
                }
            }
        }
        let normal_of = |v: u32, patch: u32, fallback: DVec3| {
            let sum = at_vertex[v as usize].iter().find(|(p, _)| *p == patch).map_or(DVec3::ZERO, |e| e.1);
            let n = sum.normalize_or_zero();
            if n == DVec3::ZERO { fallback } else { n }
        };
        let mut input_corner_normals = Vec::with_capacity(faces.len());
        let mut own_normal = Vec::with_capacity(faces.len());
        let trusted = OWN_NORMAL_ANGLE_DEG.to_radians().cos();
        // The face's own normal: Verdict's centre normal for a quad (its diagonals' cross
        // product), the plane's normal for a triangle.
        let own: Vec<DVec3> = faces.iter().map(|f| face_vector_area(points, f).normalize_or_zero()).collect();
        // The sum of the own normals of each face's neighbours across its edges: a face turned
        // against it is folded over, and keeps the patch's normals that say so.
        let mut around = vec![DVec3::ZERO; faces.len()];
        for e in mesh.edges() {
            if !e.is_boundary() {
                let (f, g) = (e.faces[0] as usize, e.faces[1] as usize);
                around[f] += own[g];
                around[g] += own[f];
            }
        }
        for (f, face) in faces.iter().enumerate() {
            let c = corner_vertices(face);
            let fallback = if own[f] == DVec3::ZERO { DVec3::Z } else { own[f] };
            let mut normals = c.map(|v| normal_of(v, face_patch[f], fallback));
            let mut bits = 0u8;
            let folded = !(own[f].dot(around[f]) > 0.0);
            for (k, n) in normals.iter_mut().enumerate() {
                if !folded && !(n.dot(own[f]) >= trusted) {
                    *n = own[f];
                    bits |= 1 << k;
                }
            }
            input_corner_normals.push(normals);
            own_normal.push(bits);
        }
        let mut patches = Vec::with_capacity(members.len());
        let mut face_triangle = vec![0u32; faces.len()];
        // Each vertex's local number in the patch being built (u32::MAX: not in it).
        let mut local = vec![u32::MAX; points.len()];
        for (p, list) in members.iter().enumerate() {
            // The reference numbers its triangles in face order, a quad's two together.
            let mut next = 0u32;
            for &f in list {
                face_triangle[f as usize] = next;
                next += if face::is_triangle(&faces[f as usize]) { 1 } else { 2 };
            }
            let mut global: Vec<u32> =
                list.iter().flat_map(|&f| face::vertices(&faces[f as usize]).iter().copied()).collect();
            global.sort_unstable();
            global.dedup();
            for (l, &v) in global.iter().enumerate() {
                local[v as usize] = l as u32;
            }
            let patch_points: Vec<DVec3> = global.iter().map(|&v| points[v as usize]).collect();
            let patch_faces: Vec<Face> = list
                .iter()
                .map(|&f| faces[f as usize].map(|v| if v == face::NO_VERTEX { v } else { local[v as usize] }))
                .collect();
            for &v in &global {
                local[v as usize] = u32::MAX;
            }
            let reference = ReferenceSurface::new(&patch_points, &patch_faces)?;
            let corner_normals = reference
                .triangles()
                .iter()
                .map(|t| {
                    let at = |k: usize| patch_points[t[k] as usize];
                    let fallback = (at(1) - at(0)).cross(at(2) - at(0)).normalize_or(DVec3::Z);
                    t.map(|v| normal_of(global[v as usize], p as u32, fallback))
                })
                .collect();
            patches.push(Patch { global, reference, corner_normals });
        }
        Ok(Patches { face_patch, face_triangle, patches, input_corner_normals, own_normal })
    }

    /// Number of patches.
    pub fn count(&self) -> usize {
        self.patches.len()
    }

    /// The patch of face `f`.
    pub fn of_face(&self, f: usize) -> u32 {
        self.face_patch[f]
    }

    /// The one-sided normals at the corners of every face, at the input positions.
    pub fn input_corner_normals(&self) -> &[[DVec3; 4]] {
        &self.input_corner_normals
    }

    /// Whether corner `k` of face `f` is measured against the face's own input normal, which
    /// stays as it is when the vertex moves, rather than against the patch's normal where the
    /// vertex is.
    #[inline]
    pub fn is_own(&self, f: usize, k: usize) -> bool {
        self.own_normal[f] >> k & 1 == 1
    }

    /// The triangle of face `f`'s patch reference that has vertex `v` of `f` as a corner (a
    /// hint for projecting `v` from where it is), or the face's first if `v` is not its vertex.
    pub fn triangle_at(&self, f: usize, v: u32) -> u32 {
        let first = self.face_triangle[f];
        let patch = &self.patches[self.face_patch[f] as usize];
        let reference = &patch.reference;
        let second = first + 1;
        let own = |t: u32| {
            (t as usize) < reference.triangle_count()
                && reference.triangle_face(t) == reference.triangle_face(first)
                && reference.triangles()[t as usize].iter().any(|&l| patch.global[l as usize] == v)
        };
        if !own(first) && own(second) { second } else { first }
    }

    /// The closest point of patch `patch` to `p` around triangle `hint` (the local walk of
    /// [`ReferenceSurface::closest_point_near`]: a vertex stays on its own sheet), the global
    /// closest point if `hint` is [`NO_TRIANGLE`](super::reference::NO_TRIANGLE); and the
    /// patch's normal there.
    pub fn project(&self, patch: u32, p: DVec3, hint: u32) -> OnPatch {
        let patch = &self.patches[patch as usize];
        let c = patch.reference.closest_point_near(p, hint);
        let [a, b, d] = patch.reference.triangle_corners(c.triangle);
        let w = barycentric(c.point, a, b, d);
        let [na, nb, nd] = patch.corner_normals[c.triangle as usize];
        let mut normal = (na * w[0] + nb * w[1] + nd * w[2]).normalize_or_zero();
        if normal == DVec3::ZERO {
            normal = patch.reference.triangle_normal(c.triangle);
        }
        OnPatch { point: c.point, triangle: c.triangle, normal }
    }
}

/// The four corner vertices of a face as [`crate::quality3d::corners`] takes them: a
/// triangle's third twice.
pub fn corner_vertices(f: &Face) -> [u32; 4] {
    [f[0], f[1], f[2], face::fourth_corner(f)]
}

/// Barycentric coordinates of `p` (on or near the triangle's plane) in triangle `abc`,
/// clamped to the triangle; the centroid's for a triangle without area.
fn barycentric(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> [f64; 3] {
    let (e0, e1, ep) = (b - a, c - a, p - a);
    let (d00, d01, d11) = (e0.dot(e0), e0.dot(e1), e1.dot(e1));
    let (d20, d21) = (ep.dot(e0), ep.dot(e1));
    let den = d00 * d11 - d01 * d01;
    if den.is_nan() || den <= 0.0 || !den.is_finite() {
        return [1.0 / 3.0; 3];
    }
    let v = ((d11 * d20 - d01 * d21) / den).clamp(0.0, 1.0);
    let w = ((d00 * d21 - d01 * d20) / den).clamp(0.0, 1.0 - v);
    [1.0 - v - w, v, w]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit cube of 6 quads, outward.
    pub(crate) fn cube() -> SurfaceMesh {
        let p: Vec<DVec3> = (0..8)
            .map(|k| DVec3::new((k & 1) as f64, ((k >> 1) & 1) as f64, ((k >> 2) & 1) as f64))
            .collect();
        let f = vec![[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
        SurfaceMesh::new(p, f, None).unwrap()
    }

    #[test]
    fn a_cube_has_six_patches_with_one_sided_normals() {
        let mesh = cube();
        let features = SurfaceFeatures::detect_default(&mesh);
        let patches = Patches::new(&mesh, &features).unwrap();
        assert_eq!(patches.count(), 6);
        for (f, normals) in patches.input_corner_normals().iter().enumerate() {
            let own = face_vector_area(mesh.points(), &mesh.faces()[f]).normalize();
            for n in normals {
                assert!((*n - own).length() < 1e-15, "face {f}: {n} against {own}");
            }
        }
        // A point above the top face's centre lands on it, with its normal.
        let top = (0..6).find(|&f| mesh.faces()[f].iter().all(|&v| v >= 4)).unwrap();
        let on = patches.project(patches.of_face(top), DVec3::new(0.5, 0.5, 3.0), 0);
        assert_eq!(on.point, DVec3::new(0.5, 0.5, 1.0));
        assert_eq!(on.normal, DVec3::Z);
    }

    #[test]
    fn each_patch_holds_its_own_vertices_only() {
        // The cube's six patches: four corners each, where a copy of every point per patch
        // would be eight.
        let mesh = cube();
        let features = SurfaceFeatures::detect_default(&mesh);
        let patches = Patches::new(&mesh, &features).unwrap();
        for (f, face) in mesh.faces().iter().enumerate() {
            let patch = &patches.patches[patches.of_face(f) as usize];
            assert_eq!(patch.reference.points().len(), 4);
            let mut own = face.to_vec();
            own.sort_unstable();
            assert_eq!(patch.global, own);
            for (l, &v) in patch.global.iter().enumerate() {
                assert_eq!(patch.reference.points()[l], mesh.points()[v as usize]);
            }
            // Each corner's hint triangle has that corner.
            for &v in face {
                let t = patches.triangle_at(f, v);
                assert!(
                    patch.reference.triangles()[t as usize].iter().any(|&l| patch.global[l as usize] == v)
                );
            }
        }
    }

    #[test]
    fn barycentric_coordinates_reproduce_the_point() {
        let (a, b, c) = (DVec3::ZERO, DVec3::new(2.0, 0.0, 0.0), DVec3::new(0.0, 1.0, 1.0));
        let p = a * 0.2 + b * 0.5 + c * 0.3;
        let w = barycentric(p, a, b, c);
        assert!((w[0] - 0.2).abs() < 1e-15 && (w[1] - 0.5).abs() < 1e-15 && (w[2] - 0.3).abs() < 1e-15);
    }
}
