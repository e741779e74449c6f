//! The Utah teapot, tessellated from Martin Newell's 32 bicubic Bezier patches.
//!
//! The patch data (`assets/models/teapot_patches.json`, public domain, 1975) is embedded in
//! the binary. It is z up; we turn it to y up with `(x, y, z) -> (x, z, -y)`, a rotation,
//! so handedness and winding are kept.
//!
//! Each patch is evaluated on an `(n+1) x (n+1)` grid of `(u, v)`. In Newell's data every
//! patch's `dP/du x dP/dv` points *into* the teapot (checked per patch group: body radially
//! inwards, lid and knob downwards, bottom upwards), so the outward normal is
//! `dP/dv x dP/du` and the triangles are wound to match (counter-clockwise seen from
//! outside). At the lid knob and the bottom centre a whole row of control points
//! coincides, so one derivative vanishes there: such a vertex takes the normal of the point
//! a small step towards the patch centre instead (a documented fallback that never gives
//! NaN). Patch seams are welded: positions within 1e-5 of the model size of each other
//! become bit-identical, so the rasterizer sees watertight edges. Triangles that the weld
//! collapses to a line or a point are dropped.
//!
//! Each vertex also gets a tangent (the azimuth-0 direction of anisotropic materials,
//! `conventions`, "Frame of anisotropic materials"): the patch derivative that lies in the
//! planes through the y axis, chosen and signed once per patch (`tangent_choice`). Records
//! at a seam whose tangents differ stay apart in the weld but share one normal.

use super::Mesh;
use glam::Vec3;
use std::collections::HashMap;

const PATCH_JSON: &str = include_str!("../../assets/models/teapot_patches.json");

#[derive(serde::Deserialize)]
struct PatchFile {
    vertices: Vec<[f32; 3]>,
    patches: Vec<[usize; 16]>,
}

/// Bernstein basis of degree 3 at `t`.
fn bernstein3(t: f32) -> [f32; 4] {
    let s = 1.0 - t;
    [s * s * s, 3.0 * t * s * s, 3.0 * t * t * s, t * t * t]
}

/// Bernstein basis of degree 2 at `t`.
fn bernstein2(t: f32) -> [f32; 3] {
    let s = 1.0 - t;
    [s * s, 2.0 * t * s, t * t]
}

/// Position and the two partial derivatives of a bicubic patch. The derivatives are
/// degree-2 combinations of control-point *differences* (`3 (P[i+1] - P[i])`), so a row of
/// coincident control points gives an exactly zero derivative, not a rounding residue.
// The Bernstein sums index the basis by the control point's row and column, as written.
#[allow(clippy::needless_range_loop)]
fn eval_patch(cp: &[Vec3; 16], u: f32, v: f32) -> (Vec3, Vec3, Vec3) {
    let (bu, bv) = (bernstein3(u), bernstein3(v));
    let (du, dv) = (bernstein2(u), bernstein2(v));
    let at = |i: usize, j: usize| cp[i * 4 + j];
    let (mut p, mut pu, mut pv) = (Vec3::ZERO, Vec3::ZERO, Vec3::ZERO);
    for i in 0..4 {
        for j in 0..4 {
            p += at(i, j) * (bu[i] * bv[j]);
        }
    }
    for i in 0..3 {
        for j in 0..4 {
            pu += (at(i + 1, j) - at(i, j)) * (3.0 * du[i] * bv[j]);
        }
    }
    for i in 0..4 {
        for j in 0..3 {
            pv += (at(i, j + 1) - at(i, j)) * (3.0 * bu[i] * dv[j]);
        }
    }
    (p, pu, pv)
}

/// Outward normal from the partial derivatives, or `None` where the patch is degenerate
/// (the cross product is tiny relative to the derivatives' size).
fn patch_normal(pu: Vec3, pv: Vec3) -> Option<Vec3> {
    let n = pv.cross(pu);
    let scale = pu.length_squared() + pv.length_squared();
    (n.length() > 1e-4 * scale && scale > 0.0).then(|| n.normalize())
}

/// Which patch derivative is the mesh's tangent ([`Mesh::tangents`]) on patch `cp`, and
/// its sign, decided once per patch from a 6 x 6 grid of interior samples.
///
/// The derivative is the one that lies closer to the planes through the y axis (the smaller
/// mean `|d . a|` of the unit derivative `d` with the unit direction `a` around the axis at
/// the sample): on the body, rim, lid, knob and bottom (surfaces of revolution) that is the
/// profile, continuous across patches, and on the spout and handle (tubes about the plane
/// z = 0) the direction along the tube. In Newell's data it is `dP/du` on every patch, with
/// a margin of at least 0.2 in that mean (0.27 against 0.47 on the spout's lip, 0 against 1
/// on the surfaces of revolution). A single sample at the patch centre does not do: the
/// rim's four patches have the normal exactly +y there, whose world-up tangent is the
/// fallback -z, and picked the derivative around the rim on some quadrants (a bright
/// quarter of the rim).
///
/// The sign makes the mean dot product with the world-up tangent of the sample's normal
/// positive (the profile runs upwards); where that mean is below 0.25 in size (the rim and
/// the spout's lip, where the profile turns over the top) the patch keeps the parameter's
/// own direction. The sign only turns the frame by pi, which a material symmetric under
/// that turn (every library material) does not see. The tangent is zero at the poles,
/// where a row of control points coincides (knob, bottom centre).
fn tangent_choice(cp: &[Vec3; 16]) -> impl Fn(Vec3, Vec3) -> Vec3 {
    const GRID: usize = 6;
    let (mut around_u, mut around_v, mut up_u, mut up_v) = (0.0f32, 0.0f32, 0.0f32, 0.0f32);
    for i in 0..GRID {
        for j in 0..GRID {
            let (u, v) = (
                (i as f32 + 0.5) / GRID as f32,
                (j as f32 + 0.5) / GRID as f32,
            );
            let (p, pu, pv) = eval_patch(cp, u, v);
            let (du, dv) = (pu.normalize_or_zero(), pv.normalize_or_zero());
            let around = Vec3::new(-p.z, 0.0, p.x).normalize_or_zero();
            around_u += du.dot(around).abs();
            around_v += dv.dot(around).abs();
            if let Some(n) = patch_normal(pu, pv) {
                let up = crate::conventions::ShadingFrame::from_normal(n).t;
                up_u += du.dot(up);
                up_v += dv.dot(up);
            }
        }
    }
    let use_u = around_u <= around_v;
    let up_mean = if use_u { up_u } else { up_v } / (GRID * GRID) as f32;
    let sign = if up_mean.abs() < 0.25 {
        1.0
    } else {
        up_mean.signum()
    };
    move |pu: Vec3, pv: Vec3| (if use_u { pu } else { pv }) * sign
}

/// The teapot with `segments` quads along each patch edge (clamped to 1..=256), y up,
/// resting on y = 0 with the lid knob at y = 3.15 (the patch data's units).
pub fn teapot(segments: u32) -> Mesh {
    let n = segments.clamp(1, 256) as usize;
    let data: PatchFile = serde_json::from_str(PATCH_JSON).expect("embedded teapot data is valid");
    let verts: Vec<Vec3> = data
        .vertices
        .iter()
        .map(|&[x, y, z]| Vec3::new(x, z, -y))
        .collect();
    let mut mesh = Mesh::default();
    for patch in &data.patches {
        let cp: [Vec3; 16] = std::array::from_fn(|k| verts[patch[k]]);
        let tangent_of = tangent_choice(&cp);
        let base = mesh.positions.len() as u32;
        for i in 0..=n {
            for j in 0..=n {
                let (u, v) = (i as f32 / n as f32, j as f32 / n as f32);
                let (p, pu, pv) = eval_patch(&cp, u, v);
                // Degenerate row: step towards the patch centre and use that normal.
                let normal = patch_normal(pu, pv)
                    .or_else(|| {
                        let step = 1e-3;
                        let (_, pu2, pv2) = eval_patch(
                            &cp,
                            u + step * (0.5 - u).signum(),
                            v + step * (0.5 - v).signum(),
                        );
                        patch_normal(pu2, pv2)
                    })
                    .unwrap_or(Vec3::Y);
                mesh.positions.push(p);
                mesh.normals.push(normal);
                mesh.tangents.push(tangent_of(pu, pv).normalize_or_zero());
            }
        }
        let idx = |i: usize, j: usize| base + (i * (n + 1) + j) as u32;
        for i in 0..n {
            for j in 0..n {
                let (a, b, c, d) = (idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1));
                mesh.triangles.push([a, c, b]);
                mesh.triangles.push([a, d, c]);
            }
        }
    }
    weld(&mut mesh, 1e-5);
    mesh
}

/// Makes positions closer than about `tol` times the model size bit-identical (the first
/// one seen wins) and re-indexes triangles onto one shared vertex per position where the
/// normals agree too; drops triangles that become degenerate (two equal corners).
fn weld(mesh: &mut Mesh, tol: f32) {
    let b = mesh.bounds();
    let scale = (b.max - b.min).max_element().max(f32::MIN_POSITIVE);
    let q = 1.0 / (tol * scale);
    let key = |p: Vec3| {
        let k = (p * q).round();
        (k.x as i64, k.y as i64, k.z as i64)
    };
    let mut canon: HashMap<(i64, i64, i64), Vec3> = HashMap::new();
    for p in &mut mesh.positions {
        *p = *canon.entry(key(*p)).or_insert(*p);
    }
    // Share vertex records with equal position and (nearly) equal normal, the first normal
    // seen standing for all; records whose tangents differ stay apart (at a seam between
    // patches that run the other way) but take that same normal, so the split changes no
    // interpolated normal.
    type PositionNormalKey = ((i64, i64, i64), (i32, i32, i32));
    let mut canonical_normal: HashMap<PositionNormalKey, Vec3> = HashMap::new();
    let mut first: HashMap<(PositionNormalKey, (i32, i32, i32)), u32> = HashMap::new();
    let mut remap = vec![0u32; mesh.positions.len()];
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    let mut tangents = Vec::new();
    for (i, (p, nrm)) in mesh.positions.iter().zip(&mesh.normals).enumerate() {
        let nk = (*nrm * 1e3).round();
        let pn = (key(*p), (nk.x as i32, nk.y as i32, nk.z as i32));
        let normal = *canonical_normal.entry(pn).or_insert(*nrm);
        let tan = mesh.tangents[i];
        let tk = (tan * 8.0).round();
        remap[i] = *first
            .entry((pn, (tk.x as i32, tk.y as i32, tk.z as i32)))
            .or_insert_with(|| {
                positions.push(*p);
                normals.push(normal);
                tangents.push(tan);
                positions.len() as u32 - 1
            });
    }
    let triangles = mesh
        .triangles
        .iter()
        .map(|t| t.map(|i| remap[i as usize]))
        .filter(|t| {
            let [a, b, c] = t.map(|i| positions[i as usize]);
            a != b && b != c && a != c
        })
        .collect();
    *mesh = Mesh {
        positions,
        normals,
        triangles,
        tangents,
        ..Mesh::default()
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tangents_run_up_the_profile() {
        // On the body (a surface of revolution about +y, away from the poles) the profile
        // tangent lies in the meridian plane, upwards: the world-up tangent of the same
        // normal. The other patch derivative (around the body) fails this.
        let m = teapot(8);
        assert_eq!(m.tangents.len(), m.positions.len());
        let mut body = 0;
        let mut bad = 0;
        for ((p, n), t) in m.positions.iter().zip(&m.normals).zip(&m.tangents) {
            let r = (p.x * p.x + p.z * p.z).sqrt();
            // The body: between the bottom and the rim, outside the spout and handle.
            if !(0.3..2.3).contains(&p.y) || r < 1.2 || (p.x.abs() > 1.3 && p.z.abs() < 0.75) {
                continue;
            }
            body += 1;
            let up = crate::conventions::ShadingFrame::from_normal(*n).t;
            let along = (*t - *n * n.dot(*t)).normalize();
            if along.dot(up) <= 0.98 {
                eprintln!("at {p:?}: tangent {t:?}, world-up {up:?}");
                bad += 1;
            }
        }
        assert!(body > 50, "{body} body vertices");
        assert_eq!(bad, 0, "{bad} of {body}");
        // Tangents are unit or zero (poles).
        for t in &m.tangents {
            assert!(
                t.length() < 1e-6 || (t.length() - 1.0).abs() < 1e-5,
                "{t:?}"
            );
        }
    }

    #[test]
    fn tangents_lie_in_the_meridian_planes() {
        // On the surfaces of revolution (body, rim, lid, knob, bottom; away from the axis,
        // the spout and the handle) the tangent is the profile: it has no component around
        // the y axis. The rim, where the normal is +y along the top of the curl, is the
        // case a choice made at the patch centre got wrong (the derivative around the rim).
        let m = teapot(8);
        let mut checked = 0;
        for (p, t) in m.positions.iter().zip(&m.tangents) {
            let r = (p.x * p.x + p.z * p.z).sqrt();
            if r < 0.05 || (p.x.abs() > 1.3 && p.z.abs() < 0.75) || *t == Vec3::ZERO {
                continue;
            }
            checked += 1;
            let around = Vec3::new(-p.z, 0.0, p.x) / r;
            assert!(
                t.dot(around).abs() < 0.01,
                "at {p:?}: tangent {t:?} turns around the axis"
            );
        }
        assert!(checked > 500, "{checked} vertices");
        // The rim (y above 2.3, outside the lid) is among them.
        let rim = m
            .positions
            .iter()
            .filter(|p| p.y > 2.3 && (p.x * p.x + p.z * p.z).sqrt() > 1.3)
            .count();
        assert!(rim > 20, "{rim} rim vertices");
    }

    #[test]
    fn no_nan_and_unit_normals() {
        let m = teapot(8);
        assert!(!m.triangles.is_empty());
        for (p, n) in m.positions.iter().zip(&m.normals) {
            assert!(p.is_finite() && n.is_finite());
            assert!((n.length() - 1.0).abs() < 1e-4);
        }
        let b = m.bounds();
        assert!(b.min.y.abs() < 1e-4, "rests on y = 0: {b:?}");
        assert!((b.max.y - 3.15).abs() < 0.01, "lid knob top at 3.15: {b:?}");
    }

    #[test]
    fn faces_point_outwards() {
        // Signed volume about the body's centre: positive when triangles wind
        // counter-clockwise seen from outside (the mesh is open, but the body dominates).
        let m = teapot(8);
        let c = Vec3::new(0.0, 1.2, 0.0);
        let vol: f32 = m
            .triangles
            .iter()
            .map(|t| {
                let [a, b, d] = t.map(|i| m.positions[i as usize] - c);
                a.dot(b.cross(d)) / 6.0
            })
            .sum();
        assert!(vol > 10.0, "signed volume {vol}: the teapot is inside out");
        // Every vertex record at the knob apex and the bottom centre (degenerate patch
        // rows) points straight up or down.
        for (p, n) in m.positions.iter().zip(&m.normals) {
            if p.y > 3.1499 {
                assert!(n.y > 0.99, "knob apex normal {n:?}");
            }
            if p.y < 1e-4 && p.x.abs() < 1e-4 && p.z.abs() < 1e-4 {
                assert!(n.y < -0.99, "bottom centre normal {n:?}");
            }
        }
    }

    #[test]
    fn normals_agree_with_winding() {
        // Vertex normals of each triangle point to the side its winding faces.
        let m = teapot(8);
        let mut bad = 0;
        for t in &m.triangles {
            let [a, b, c] = t.map(|i| m.positions[i as usize]);
            let face = (b - a).cross(c - a);
            let avg: Vec3 = t.iter().map(|&i| m.normals[i as usize]).sum();
            if face.dot(avg) < 0.0 {
                bad += 1;
            }
        }
        assert_eq!(bad, 0);
    }
}
