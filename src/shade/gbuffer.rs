//! The G-buffer: the surface seen through a pixel, reconstructed from the visibility buffer.
//!
//! Design rule: geometry only, no shading. Per pixel, the perspective-correct barycentrics
//! of the source triangle give the world position and the interpolated normal; back faces
//! (two-sided mode) get the normal flipped, so the inside of the teapot is lit as a surface
//! facing the viewer. Where the mesh tessellates an exact sphere
//! ([`crate::mesh::Mesh::exact_sphere`]) and the visibility buffer knows the camera
//! ([`crate::raster::PixelRays`]), the camera ray through the pixel centre is intersected
//! with that sphere in f64 instead: position, normal and view depth are the sphere's, first
//! intersection for front faces and second for back faces; a ray that misses (at the
//! silhouette: a facet pixel just outside the true outline, by rounding) keeps the facet's
//! values. Every shading path (the tile loop, the scalar oracle, the f64 path, the
//! environment terms, through the one traversal of `traverse.rs`) and the AOVs
//! ([`crate::aov`]) read surfaces through here, so they all see the same one.

use crate::mesh::Mesh;
use crate::raster::{VisBuffer, NO_TRIANGLE};
use glam::Vec3;

/// What shading needs to know about the surface seen through one pixel.
#[derive(Clone, Copy, Debug)]
pub struct Surface {
    /// World position.
    pub position: Vec3,
    /// Unit shading normal, flipped towards the viewer for back faces.
    pub normal: Vec3,
    /// Whether the triangle faces the camera.
    pub front_facing: bool,
    /// Distance along the view axis (the clip w).
    pub view_depth: f32,
    /// The mesh's tangent interpolated at the pixel ([`Mesh::tangents`]; not normalised,
    /// not orthogonal to the normal), or zero where the mesh has none: the azimuth-0
    /// direction of an anisotropic material's frame ([`crate::conventions::FrameRule`]).
    pub tangent: Vec3,
}

/// The surface seen through pixel `(x, y)`, if any.
#[inline]
pub fn surface_at(mesh: &Mesh, vis: &VisBuffer, x: u32, y: u32) -> Option<Surface> {
    surface_at_index(mesh, vis, vis.index(x, y), x, y)
}

/// [`surface_at`] for a pixel whose tile-major index `i` the caller already knows.
#[inline]
pub fn surface_at_index(mesh: &Mesh, vis: &VisBuffer, i: usize, x: u32, y: u32) -> Option<Surface> {
    let id = vis.visible[i];
    if id == NO_TRIANGLE {
        return None;
    }
    let t = &vis.triangles[id as usize];
    // The exact sphere first: where its ray hits, the facet's values would be replaced, so
    // they are computed only where it misses (or the mesh has no exact sphere).
    if let (Some(sphere), Some(rays)) = (mesh.exact_sphere, vis.rays) {
        let dir = rays.dir(x, y);
        if let Some(s) = sphere.ray_parameter(rays.eye, dir, !t.front_facing) {
            let hit = rays.eye + s * dir;
            let normal = sphere.normal_at(hit).normalize().as_vec3();
            return Some(Surface {
                position: hit.as_vec3(),
                normal: if t.front_facing { normal } else { -normal },
                front_facing: t.front_facing,
                // dir has view-space z = -1: s is the depth along the view axis.
                view_depth: s as f32,
                // The UV sphere has no tangents: its parametric tangent up the meridian is
                // the world-up tangent (`mesh` module doc).
                tangent: Vec3::ZERO,
            });
        }
    }
    let b = t.source_bary(x, y);
    let tri = mesh.triangles[t.source as usize];
    let [p0, p1, p2] = tri.map(|k| mesh.positions[k as usize]);
    let [n0, n1, n2] = tri.map(|k| mesh.normals[k as usize]);
    let position = p0 * b[0] + p1 * b[1] + p2 * b[2];
    let normal = (n0 * b[0] + n1 * b[1] + n2 * b[2])
        .try_normalize()
        .or_else(|| (p1 - p0).cross(p2 - p0).try_normalize())
        .unwrap_or(Vec3::Y);
    let tangent = if mesh.tangents.is_empty() {
        Vec3::ZERO
    } else {
        let [t0, t1, t2] = tri.map(|k| mesh.tangents[k as usize]);
        t0 * b[0] + t1 * b[1] + t2 * b[2]
    };
    Some(Surface {
        position,
        normal: if t.front_facing { normal } else { -normal },
        front_facing: t.front_facing,
        view_depth: 1.0 / vis.depth[i],
        tangent,
    })
}
