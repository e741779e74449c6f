//! Triangle meshes: the geometry that enters the pipeline.
//!
//! Design rule: a mesh is a structure of arrays (positions, normals, triangles) in world
//! space with unit vertex normals and no NaN anywhere; every loader (teapot patches, UV
//! sphere, OBJ) guarantees that before returning. Positions that should coincide (patch
//! seams, sphere poles) are bit-identical, so the rasterizer sees watertight edges.
//!
//! Tangents: a mesh may carry a per-vertex tangent, the direction of azimuth 0 of an
//! anisotropic material's shading frame (`conventions`, "Frame of anisotropic materials").
//! The teapot's is the derivative of each Bezier patch that lies in the planes through the
//! y axis (up the profile; along the spout and handle), signed to run upwards
//! ([`mod@teapot`]); an OBJ file's comes from its texture coordinates (the direction of
//! increasing u, Lengyel's per-triangle solve summed per vertex); a mesh without tangents
//! (an OBJ without texture coordinates, the UV sphere, whose parametric tangent up the
//! meridian is exactly the world-up tangent) is shaded in the world-up frame.

pub mod obj;
pub mod sphere;
pub mod teapot;

use glam::{Vec2, Vec3};

/// An indexed triangle mesh. Triangles are counter-clockwise seen from the side the
/// normals point to (the outside of a closed mesh).
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    pub positions: Vec<Vec3>,
    /// Unit vertex normals, one per position.
    pub normals: Vec<Vec3>,
    pub triangles: Vec<[u32; 3]>,
    /// Unit tangents, one per position, or empty: the mesh has none (module doc). An entry
    /// may be zero where the parameterisation is degenerate (the teapot's poles); shading
    /// then falls back to the world-up tangent at that pixel. Need not be orthogonal to the
    /// normal: shading projects it onto the tangent plane.
    pub tangents: Vec<Vec3>,
    /// Texture coordinates, one per position, or empty (an OBJ file's `vt`): what an OBJ
    /// mesh's tangents were computed from, kept so that `brdfkit export` writes them back.
    pub texcoords: Vec<Vec2>,
    /// The exact surface this mesh tessellates, when it is a sphere ([`sphere::uv_sphere`]):
    /// shading intersects each pixel's camera ray with it ([`crate::shade::surface_at`])
    /// instead of interpolating across the facets. `None` for any other mesh, and after
    /// [`Mesh::transform`] or [`Mesh::append`].
    pub exact_sphere: Option<sphere::ExactSphere>,
}

/// Axis-aligned bounds of a mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    pub min: Vec3,
    pub max: Vec3,
}

impl Bounds {
    pub fn center(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }
    /// Radius of the sphere around [`Bounds::center`] that holds the box.
    pub fn radius(&self) -> f32 {
        0.5 * (self.max - self.min).length()
    }
}

impl Mesh {
    /// Bounds of the positions; an empty mesh gives a unit box around the origin.
    pub fn bounds(&self) -> Bounds {
        if self.positions.is_empty() {
            return Bounds {
                min: Vec3::splat(-1.0),
                max: Vec3::splat(1.0),
            };
        }
        let mut b = Bounds {
            min: Vec3::splat(f32::INFINITY),
            max: Vec3::splat(f32::NEG_INFINITY),
        };
        for p in &self.positions {
            b.min = b.min.min(*p);
            b.max = b.max.max(*p);
        }
        b
    }

    /// Largest distance of a vertex from `c` (0 for an empty mesh).
    pub fn radius_about(&self, c: Vec3) -> f32 {
        self.positions
            .iter()
            .map(|p| p.distance(c))
            .fold(0.0, f32::max)
    }

    /// Replaces the normals by smooth ones: per vertex, the area-weighted sum of the
    /// normals of its triangles. A vertex with no non-degenerate triangle gets +y.
    pub fn compute_smooth_normals(&mut self) {
        let mut acc = vec![Vec3::ZERO; self.positions.len()];
        for t in &self.triangles {
            let [a, b, c] = t.map(|i| self.positions[i as usize]);
            let n = (b - a).cross(c - a); // length = 2 * area: area weighting
            for &i in t {
                acc[i as usize] += n;
            }
        }
        self.normals = acc
            .into_iter()
            .map(|n| n.try_normalize().unwrap_or(Vec3::Y))
            .collect();
    }

    /// Sets [`Mesh::tangents`] from [`Mesh::texcoords`]: per triangle, the surface direction
    /// of increasing u (the solve of Lengyel, "Computing Tangent Space Basis Vectors for an
    /// Arbitrary Mesh", 2001: `T = (dv2 e1 - dv1 e2) / (du1 dv2 - du2 dv1)` for the edges
    /// `e1, e2` and their texture-coordinate differences), summed per vertex weighted by
    /// the triangle's texture-space orientation only (each triangle's `T` is normalised,
    /// then flipped where its texture map is mirrored), normalised. A vertex whose sum
    /// vanishes (no triangle with a non-degenerate texture map) gets zero. Does nothing
    /// when the mesh has no texture coordinates.
    pub fn compute_tangents_from_texcoords(&mut self) {
        if self.texcoords.len() != self.positions.len() {
            return;
        }
        let mut acc = vec![Vec3::ZERO; self.positions.len()];
        for t in &self.triangles {
            let [a, b, c] = t.map(|i| self.positions[i as usize]);
            let [ta, tb, tc] = t.map(|i| self.texcoords[i as usize]);
            let (e1, e2) = (b - a, c - a);
            let (d1, d2) = (tb - ta, tc - ta);
            let det = d1.x * d2.y - d2.x * d1.y;
            if det == 0.0 || !det.is_finite() {
                continue;
            }
            let tangent = ((e1 * d2.y - e2 * d1.y) * det.signum()).normalize_or_zero();
            for &i in t {
                acc[i as usize] += tangent;
            }
        }
        self.tangents = acc.into_iter().map(Vec3::normalize_or_zero).collect();
    }

    /// Applies `world_from_object`: positions by the affine map, normals by its inverse
    /// transpose (renormalised), tangents by its linear part (renormalised). Drops [`Mesh::exact_sphere`] (a general affine map does not
    /// keep a sphere).
    pub fn transform(&mut self, world_from_object: glam::Affine3A) {
        self.exact_sphere = None;
        let normal_matrix = glam::Mat3::from(world_from_object.matrix3)
            .inverse()
            .transpose();
        for p in &mut self.positions {
            *p = world_from_object.transform_point3(*p);
        }
        for n in &mut self.normals {
            *n = (normal_matrix * *n).try_normalize().unwrap_or(Vec3::Y);
        }
        let linear = glam::Mat3::from(world_from_object.matrix3);
        for t in &mut self.tangents {
            *t = (linear * *t).normalize_or_zero();
        }
    }

    /// Appends another mesh. Drops [`Mesh::exact_sphere`] (the result is no longer one).
    /// Tangents and texture coordinates are kept where either mesh has them (zeros stand
    /// for the other's).
    pub fn append(&mut self, other: &Mesh) {
        self.exact_sphere = None;
        let base = self.positions.len() as u32;
        let (n_self, n_other) = (self.positions.len(), other.positions.len());
        if !self.tangents.is_empty() || !other.tangents.is_empty() {
            self.tangents.resize(n_self, Vec3::ZERO);
            if other.tangents.is_empty() {
                self.tangents.resize(n_self + n_other, Vec3::ZERO);
            } else {
                self.tangents.extend_from_slice(&other.tangents);
            }
        }
        if !self.texcoords.is_empty() || !other.texcoords.is_empty() {
            self.texcoords.resize(n_self, Vec2::ZERO);
            if other.texcoords.is_empty() {
                self.texcoords.resize(n_self + n_other, Vec2::ZERO);
            } else {
                self.texcoords.extend_from_slice(&other.texcoords);
            }
        }
        self.positions.extend_from_slice(&other.positions);
        self.normals.extend_from_slice(&other.normals);
        self.triangles
            .extend(other.triangles.iter().map(|t| t.map(|i| i + base)));
    }
}
