//! Triangle meshes: the geometry that enters the pipeline.
//!
//! Design rule: a mesh is a structure of arrays (positions, normals, triangles) in world
//! space with unit vertex normals and no NaN anywhere; every loader (teapot patches, UV
//! sphere, OBJ) guarantees that before returning. Positions that should coincide (patch
//! seams, sphere poles) are bit-identical, so the rasterizer sees watertight edges.

pub mod obj;
pub mod sphere;
pub mod teapot;

use glam::Vec3;

/// An indexed triangle mesh. Triangles are counter-clockwise seen from the side the
/// normals point to (the outside of a closed mesh).
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    pub positions: Vec<Vec3>,
    /// Unit vertex normals, one per position.
    pub normals: Vec<Vec3>,
    pub triangles: Vec<[u32; 3]>,
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

    /// Applies `world_from_object`: positions by the affine map, normals by its inverse
    /// transpose (renormalised). Drops [`Mesh::exact_sphere`] (a general affine map does not
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
    }

    /// Appends another mesh. Drops [`Mesh::exact_sphere`] (the result is no longer one).
    pub fn append(&mut self, other: &Mesh) {
        self.exact_sphere = None;
        let base = self.positions.len() as u32;
        self.positions.extend_from_slice(&other.positions);
        self.normals.extend_from_slice(&other.normals);
        self.triangles
            .extend(other.triangles.iter().map(|t| t.map(|i| i + base)));
    }
}
