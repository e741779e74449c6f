//! Wavefront OBJ files through `tobj`: all objects of the file merged into one mesh.
//!
//! Faces are triangulated by tobj; vertices are single-indexed. Files without normals (or
//! with a normal count that does not match) get smooth area-weighted normals. Files with
//! texture coordinates get tangents from them ([`Mesh::compute_tangents_from_texcoords`]),
//! the frame of anisotropic materials. Invalid
//! content (non-finite coordinates, indices out of range, no triangles) is an error that
//! names the file.

use super::Mesh;
use crate::error::{Error, Result};
use glam::{Vec2, Vec3};
use std::path::Path;

/// Largest OBJ file read (bytes): far beyond any test asset, small enough that a hostile
/// file cannot make the loader allocate without bound.
pub const MAX_OBJ_BYTES: u64 = 1 << 30;

/// Loads an OBJ file. Fails with an [`Error`] naming the file for unreadable, malformed or
/// empty files, files that are not regular files (devices), files over [`MAX_OBJ_BYTES`], face indices out of range and non-finite
/// coordinates. `mtllib` statements are ignored (no other file is opened).
pub fn load_obj(path: &Path) -> Result<Mesh> {
    // A device or FIFO (e.g. `/dev/zero`) has no length to check and may never end.
    crate::image_io::check_regular_file(path, MAX_OBJ_BYTES, "OBJ file")?;
    let opts = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ignore_points: true,
        ignore_lines: true,
    };
    // Materials are ignored: brdfkit takes its material from the scene, so `mtllib` files
    // are never opened (a hostile `mtllib /dev/zero` would otherwise be read without end).
    // The reader stops at the size limit even where metadata reports no length.
    use std::io::Read;
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, "cannot read OBJ file", e))?;
    let mut reader = std::io::BufReader::new(file.take(MAX_OBJ_BYTES));
    let (models, _materials) =
        tobj::load_obj_buf(&mut reader, &opts, |_| Ok((Vec::new(), Default::default())))
            .map_err(|e| Error::format(path, format!("malformed OBJ: {e}")))?;
    let mut mesh = Mesh::default();
    let mut any_missing_normals = false;
    let mut any_texcoords = false;
    for model in &models {
        let m = &model.mesh;
        let nverts = m.positions.len() / 3;
        let part = Mesh {
            positions: m
                .positions
                .chunks_exact(3)
                .map(|c| Vec3::new(c[0], c[1], c[2]))
                .collect(),
            normals: if m.normals.len() == m.positions.len() {
                m.normals
                    .chunks_exact(3)
                    .map(|c| Vec3::new(c[0], c[1], c[2]))
                    .collect()
            } else {
                any_missing_normals = true;
                vec![Vec3::ZERO; nverts]
            },
            triangles: m
                .indices
                .chunks_exact(3)
                .map(|c| [c[0], c[1], c[2]])
                .collect(),
            texcoords: if m.texcoords.len() == 2 * nverts && nverts > 0 {
                any_texcoords = true;
                m.texcoords
                    .chunks_exact(2)
                    .map(|c| Vec2::new(c[0], c[1]))
                    .collect()
            } else {
                Vec::new()
            },
            ..Mesh::default()
        };
        if let Some(bad) = part
            .triangles
            .iter()
            .flatten()
            .find(|&&i| i as usize >= nverts)
        {
            return Err(Error::format(
                path,
                format!(
                    "object '{}': face index {} out of range ({} vertices)",
                    model.name,
                    bad + 1,
                    nverts
                ),
            ));
        }
        mesh.append(&part);
    }
    if mesh.triangles.is_empty() {
        return Err(Error::format(
            path,
            "no faces: the OBJ file holds no triangles",
        ));
    }
    if let Some(i) = mesh.texcoords.iter().position(|t| !t.is_finite()) {
        return Err(Error::format(
            path,
            format!("texture coordinate of vertex {} is not finite", i + 1),
        ));
    }
    if let Some(i) = mesh.positions.iter().position(|p| !p.is_finite()) {
        return Err(Error::format(
            path,
            format!("vertex {} has a non-finite coordinate", i + 1),
        ));
    }
    if any_missing_normals {
        mesh.compute_smooth_normals();
    } else {
        // A normal already of unit length (within f32 rounding) is kept as written, so a
        // mesh written with its normals (`brdfkit export`) reads back bit for bit;
        // normalising again could move it by an ulp.
        for n in &mut mesh.normals {
            if (n.length_squared() - 1.0).abs() > 4.0 * f32::EPSILON {
                *n = n.try_normalize().unwrap_or(Vec3::Y);
            }
        }
    }
    if any_texcoords {
        mesh.compute_tangents_from_texcoords();
    }
    Ok(mesh)
}
