//! UV sphere: `stacks` rings of latitude, `2 * stacks` segments of longitude, y up.

use super::Mesh;
use glam::Vec3;
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
    m
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
