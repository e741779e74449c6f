//! UV sphere: `stacks` rings of latitude, `2 * stacks` segments of longitude, y up; and the
//! exact sphere it tessellates ([`ExactSphere`]), which shading intersects per pixel.
//!
//! Why the exact sphere: interpolating vertex normals across 16 stacks shifts a
//! Blinn-Phong sphere's pixels by up to 17% (the facets' normals bend in steps of
//! `pi / stacks`). Every vertex of the UV sphere lies on the exact sphere, so its facets
//! are inside it and every camera ray that hits a facet also hits the sphere; shading at
//! that intersection makes the image independent of the tessellation except at the
//! silhouette, where the facets' outline (inscribed, up to `1 - cos(pi / (2 stacks))` of
//! the radius inside the true one, 0.5% at 16 stacks) decides which pixels are covered.

use super::Mesh;
use glam::{DVec3, Vec3};
use std::f32::consts::{PI, TAU};

/// A closed, watertight unit-radius sphere around the origin: single vertices at the poles,
/// the longitude seam shares its vertices. `stacks` is clamped to at least 2.
pub fn uv_sphere(stacks: u32) -> Mesh {
    let stacks = stacks.max(2);
    let slices = 2 * stacks;
    let mut m = Mesh::default();
    m.positions.push(Vec3::Y);
    for i in 1..stacks {
        let polar = PI * i as f32 / stacks as f32;
        let (sp, cp) = polar.sin_cos();
        for j in 0..slices {
            let az = TAU * j as f32 / slices as f32;
            let (sa, ca) = az.sin_cos();
            m.positions.push(Vec3::new(sp * sa, cp, sp * ca));
        }
    }
    m.positions.push(-Vec3::Y);
    let south = m.positions.len() as u32 - 1;
    let ring = |i: u32, j: u32| 1 + (i - 1) * slices + (j % slices);
    for j in 0..slices {
        m.triangles.push([0, ring(1, j), ring(1, j + 1)]);
    }
    for i in 1..stacks - 1 {
        for j in 0..slices {
            let (a, b, c, d) = (
                ring(i, j),
                ring(i + 1, j),
                ring(i + 1, j + 1),
                ring(i, j + 1),
            );
            m.triangles.push([a, b, c]);
            m.triangles.push([a, c, d]);
        }
    }
    for j in 0..slices {
        m.triangles
            .push([south, ring(stacks - 1, j + 1), ring(stacks - 1, j)]);
    }
    m.normals = m.positions.clone();
    m.exact_sphere = Some(ExactSphere {
        center: Vec3::ZERO,
        radius: 1.0,
    });
    m
}

/// A sphere in world space (scene units), the exact surface of a [`uv_sphere`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExactSphere {
    pub center: Vec3,
    pub radius: f32,
}

impl ExactSphere {
    /// Where the ray `eye + t d` meets the sphere: the parameter `t` of the first
    /// intersection (`far = false`, the outside seen from outside) or of the second
    /// (`far = true`, the inside, seen through a back face), in f64; `None` where the ray
    /// misses (or only grazes: a discriminant that is not positive) or `d = 0`.
    ///
    /// Solves `|o + t d - c|^2 = r^2` with `o = eye - c`:
    /// `t = (-b -+ sqrt(b^2 - a (|o|^2 - r^2))) / a`, `a = d.d`, `b = o.d`; the near root is
    /// computed as `(|o|^2 - r^2) / (-b + sqrt(...))` when that avoids cancellation.
    pub fn ray_parameter(&self, eye: DVec3, d: DVec3, far: bool) -> Option<f64> {
        let o = eye - self.center.as_dvec3();
        let a = d.length_squared();
        let b = o.dot(d);
        let c = o.length_squared() - (self.radius as f64).powi(2);
        let disc = b * b - a * c;
        if a <= 0.0 || disc <= 0.0 || !disc.is_finite() {
            return None;
        }
        let s = disc.sqrt();
        // q = -b + sign(-b) s: no cancellation; the roots are q / a and c / q.
        let q = if b <= 0.0 { -b + s } else { -b - s };
        let (r1, r2) = (q / a, c / q);
        let (near, far_t) = if r1 <= r2 { (r1, r2) } else { (r2, r1) };
        Some(if far { far_t } else { near })
    }

    /// Unit outward normal at a point on the sphere (f64).
    pub fn normal_at(&self, p: DVec3) -> DVec3 {
        (p - self.center.as_dvec3()) / self.radius as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outward_and_closed() {
        let m = uv_sphere(8);
        // Every edge is used exactly twice, once in each direction: closed and consistent.
        let mut edges = std::collections::HashMap::new();
        for t in &m.triangles {
            for k in 0..3 {
                *edges.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
            }
            let [a, b, c] = t.map(|i| m.positions[i as usize]);
            let n = (b - a).cross(c - a);
            assert!(n.dot(a + b + c) > 0.0, "triangle {t:?} faces inwards");
        }
        for (&(a, b), &n) in &edges {
            assert_eq!(n, 1);
            assert_eq!(edges.get(&(b, a)), Some(&1));
        }
    }
}
