//! Surfaces in 3D for the surface tests: grids over a parametrization, the subdivided cube,
//! spheres.

use glam::DVec3;
use quadopt::face::{self, Face};
use std::collections::HashMap;
use std::f64::consts::PI;

/// An `nu` x `nv` grid of quads over `f(i, j)`, wrapping around in u and/or v.
pub fn grid(
    nu: u32,
    nv: u32,
    wrap_u: bool,
    wrap_v: bool,
    f: impl Fn(u32, u32) -> DVec3,
) -> (Vec<DVec3>, Vec<Face>) {
    let cu = if wrap_u { nu } else { nu + 1 };
    let cv = if wrap_v { nv } else { nv + 1 };
    let id = |i: u32, j: u32| (j % cv) * cu + i % cu;
    let points = (0..cu * cv).map(|k| f(k % cu, k / cu)).collect();
    let mut faces = Vec::new();
    for j in 0..nv {
        for i in 0..nu {
            faces.push([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    (points, faces)
}

/// The surface of the cube [0, n]^3 in n x n quads per side, outward, and the lattice
/// coordinates of each vertex.
pub fn cube(n: u32) -> (Vec<DVec3>, Vec<Face>, Vec<[u32; 3]>) {
    let mut index: HashMap<[u32; 3], u32> = HashMap::new();
    let mut lattice = Vec::new();
    let mut faces = Vec::new();
    for a in 0..3 {
        let (u, v) = ((a + 1) % 3, (a + 2) % 3);
        for s in [0, n] {
            for i in 0..n {
                for j in 0..n {
                    let mut quad = [[0u32; 3]; 4];
                    for (c, (di, dj)) in [(0, 0), (1, 0), (1, 1), (0, 1)].into_iter().enumerate() {
                        quad[c][a] = s;
                        quad[c][u] = i + di;
                        quad[c][v] = j + dj;
                    }
                    let mut f = quad.map(|p| {
                        *index.entry(p).or_insert_with(|| {
                            lattice.push(p);
                            lattice.len() as u32 - 1
                        })
                    });
                    if s == 0 {
                        f = face::reversed(f);
                    }
                    faces.push(f);
                }
            }
        }
    }
    let points =
        lattice.iter().map(|p| DVec3::new(p[0].into(), p[1].into(), p[2].into()) / f64::from(n)).collect();
    (points, faces, lattice)
}

/// A cube-sphere: the subdivided cube's vertices pushed onto the unit sphere.
pub fn cube_sphere(n: u32) -> (Vec<DVec3>, Vec<Face>) {
    let (points, faces, _) = cube(n);
    (points.iter().map(|p| (*p - DVec3::splat(0.5)).normalize()).collect(), faces)
}

/// A UV sphere with `nu` meridians and `nv` latitude bands: triangle fans at the poles.
pub fn uv_sphere(nu: u32, nv: u32) -> (Vec<DVec3>, Vec<Face>) {
    let rings = nv - 1;
    let mut points = vec![DVec3::Z, -DVec3::Z];
    for j in 1..=rings {
        let phi = PI * f64::from(j) / f64::from(nv);
        for i in 0..nu {
            let theta = 2.0 * PI * f64::from(i) / f64::from(nu);
            points.push(DVec3::new(phi.sin() * theta.cos(), phi.sin() * theta.sin(), phi.cos()));
        }
    }
    let id = |i: u32, j: u32| 2 + (j - 1) * nu + i % nu;
    let mut faces = Vec::new();
    for i in 0..nu {
        faces.push(face::triangle(0, id(i, 1), id(i + 1, 1)));
        faces.push(face::triangle(1, id(i + 1, rings), id(i, rings)));
        for j in 1..rings {
            faces.push([id(i, j), id(i, j + 1), id(i + 1, j + 1), id(i + 1, j)]);
        }
    }
    (points, faces)
}

/// A cone's apex shared by `n` quads: the apex near the origin, `n` vertices on the circle of
/// radius 1 at z = -0.5 (jittered by `seed`) and `n` on the circle of radius 2 at z = -1
/// between them, quad `k` being (apex, inner `k`, outer `k`, inner `k + 1`). Its boundary
/// zigzags, so every boundary vertex is a corner and only the apex (of valence `n`) moves.
pub fn cone_apex(n: u32, seed: u64) -> (Vec<DVec3>, Vec<Face>) {
    let mut state = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
    let mut jitter = || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let step = 2.0 * PI / f64::from(n);
    // The apex off the axis by a fraction of the fan's spacing at the inner circle.
    let mut points = vec![DVec3::new(0.2 * step, -0.1 * step, 0.0)];
    let at = |a: f64, r: f64| DVec3::new(r * a.cos(), r * a.sin(), -0.5 * r);
    for k in 0..n {
        points.push(at(step * (f64::from(k) + 0.02 * jitter()), 1.0));
    }
    for k in 0..n {
        points.push(at(step * (f64::from(k) + 0.5), 2.0));
    }
    let faces = (0..n).map(|k| [0, 1 + k, 1 + n + k, 1 + (k + 1) % n]).collect();
    (points, faces)
}
