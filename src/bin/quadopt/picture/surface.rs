//! Meshes on curved surfaces in a picture: an orthographic view, faces drawn back to front
//! (the painter's algorithm) and coloured by their signed scaled Jacobian.
//!
//! The view: an open surface is seen from the side its faces face on average (the sum of
//! their vector areas), tilted towards an isometric direction so that its relief shows; a
//! closed one (whose vector areas sum to about zero) from the isometric direction (1, -1.5,
//! 1.2). Up in the picture is the z axis as seen from there (the y axis when looking along z).
//! A before/after pair shares the view of the input.

use super::Picture;
use super::layout::{Panel, before_after_panels, single_panel};
use glam::{DVec2, DVec3};
use quadopt::surface::{SurfaceMesh, face_vector_area};
use std::borrow::Cow;

/// The isometric direction towards the viewer.
const ISOMETRIC: DVec3 = DVec3::new(1.0, -1.5, 1.2);

/// The screen's right and up axes and the direction towards the viewer.
#[derive(Clone, Copy)]
struct View {
    right: DVec3,
    up: DVec3,
    towards: DVec3,
}

impl View {
    fn of(mesh: &SurfaceMesh) -> View {
        let (mut sum, mut total) = (DVec3::ZERO, 0.0);
        for f in mesh.faces() {
            let a = face_vector_area(mesh.points(), f);
            sum += a;
            total += a.length();
        }
        let iso = ISOMETRIC.normalize();
        let towards =
            if sum.length() > 0.3 * total { (sum.normalize() + 0.5 * iso).normalize() } else { iso };
        let world_up = if towards.cross(DVec3::Z).length() < 1e-6 { DVec3::Y } else { DVec3::Z };
        let right = world_up.cross(towards).normalize();
        View { right, up: towards.cross(right), towards }
    }

    fn panel<'a>(&self, mesh: &'a SurfaceMesh, values: &[f64]) -> Panel<'a> {
        let points: Vec<DVec2> =
            mesh.points().iter().map(|p| DVec2::new(p.dot(self.right), p.dot(self.up))).collect();
        // Back to front by the depth of each face's centre.
        let depth: Vec<f64> = mesh
            .faces()
            .iter()
            .map(|f| {
                let c = quadopt::face::vertices(f).iter().map(|&v| mesh.points()[v as usize]).sum::<DVec3>();
                c.dot(self.towards) / quadopt::face::corner_count(f) as f64
            })
            .collect();
        let mut order: Vec<u32> = (0..mesh.faces().len() as u32).collect();
        order.sort_by(|&a, &b| depth[a as usize].total_cmp(&depth[b as usize]).then(a.cmp(&b)));
        Panel { points: Cow::Owned(points), faces: mesh.faces(), values: values.to_vec(), order: Some(order) }
    }
}

/// One surface mesh, coloured by `values` (one per face), and its title line.
pub fn single(mesh: &SurfaceMesh, values: &[f64], title: &str) -> Picture {
    single_panel(&View::of(mesh).panel(mesh, values), title)
}

/// The input and the optimized mesh side by side, seen from the input's view, each with its
/// values, and the histogram of both.
pub fn before_after(
    (before, before_values): (&SurfaceMesh, &[f64]),
    (after, after_values): (&SurfaceMesh, &[f64]),
    title: &str,
    headings: [&str; 2],
) -> Picture {
    let view = View::of(before);
    let panels = [view.panel(before, before_values), view.panel(after, after_values)];
    before_after_panels([&panels[0], &panels[1]], title, headings)
}
