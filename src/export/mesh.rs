//! `mesh.obj` of an export: the world-space triangles with their per-vertex normals, in a
//! form every OBJ reader takes and that reads back bit for bit (shortest round-trip
//! decimals); with the mesh's texture coordinates (`vt`, an OBJ mesh's: brdfkit derives
//! the same tangents from them) and, for a mesh with tangents, one `# vtan x y z` comment
//! per `v` (the tangent of anisotropic materials' frames; other readers skip comments).

use crate::scene::Scene;
use std::fmt::Write as _;

/// The mesh as OBJ text: one `vn` per `v` (same index), faces `f a//a b//b c//c`; with
/// texture coordinates one `vt` per `v` too and faces `f a/a/a ...`; with tangents one
/// `# vtan x y z` comment per `v` (module doc).
pub fn mesh_obj(scene: &Scene) -> String {
    let m = &scene.mesh;
    let mut s = String::with_capacity(64 * (m.positions.len() * 2 + m.triangles.len()));
    s.push_str(
        "# brdfkit export: world-space triangles with unit per-vertex normals (vn i belongs \
         to v i).\n# Winding: counter-clockwise seen from the side the normals point to \
         (right-handed world, +y up).\n",
    );
    if let Some(sp) = &m.exact_sphere {
        let _ = writeln!(
            s,
            "# Shading intersects the exact sphere (centre {:?}, radius {}) per pixel, not these facets.",
            sp.center.to_array(),
            sp.radius
        );
    }
    for p in &m.positions {
        let _ = writeln!(s, "v {} {} {}", p.x, p.y, p.z);
    }
    for n in &m.normals {
        let _ = writeln!(s, "vn {} {} {}", n.x, n.y, n.z);
    }
    for t in &m.texcoords {
        let _ = writeln!(s, "vt {} {}", t.x, t.y);
    }
    if !m.tangents.is_empty() {
        s.push_str(
            "# vtan: the unit tangent of v i (azimuth 0 of anisotropic materials; zero where \
             undefined: the world-up tangent applies there).\n",
        );
    }
    for t in &m.tangents {
        let _ = writeln!(s, "# vtan {} {} {}", t.x, t.y, t.z);
    }
    let with_texcoords = !m.texcoords.is_empty();
    for t in &m.triangles {
        let [a, b, c] = t.map(|i| i + 1);
        if with_texcoords {
            let _ = writeln!(s, "f {a}/{a}/{a} {b}/{b}/{b} {c}/{c}/{c}");
        } else {
            let _ = writeln!(s, "f {a}//{a} {b}//{b} {c}//{c}");
        }
    }
    s
}
