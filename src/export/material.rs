//! `material.json` of an export and the material's data file (`material.exr` or
//! `material-lobe.exr`): the model's parameters, and its table in its own format.

use super::camera::{fa, fj};
use crate::error::{Error, Result};
use crate::material::Material;
use crate::scene::{MaterialSpec, Scene};
use serde_json::json;
use std::path::{Path, PathBuf};

/// A D-BRDF's constants and table size (thesis 2.3.6; the table itself is in the file).
fn dbrdf_json(d: &crate::brdf::dbrdf::DBrdf) -> serde_json::Value {
    json!({ "c": fj(d.c), "rs": fa(&d.rs.to_array()), "half_vector_texels": d.grid() })
}

/// The material's model and parameters (`material.json`); `file` names the written data
/// file, if any.
pub(super) fn material_json(m: &Material, file: Option<&str>) -> serde_json::Value {
    let mut v = match m {
        Material::Lambert(l) => json!({ "albedo": fa(&l.albedo.to_array()) }),
        Material::Phong(p) => json!({
            "kd": fa(&p.kd.to_array()), "ks": fa(&p.ks.to_array()), "exponent": fj(p.exponent),
        }),
        Material::BlinnPhong(p) => json!({
            "kd": fa(&p.kd.to_array()), "ks": fa(&p.ks.to_array()), "exponent": fj(p.exponent),
        }),
        Material::AshikhminShirley(a) => json!({
            "nu": fj(a.nu), "nv": fj(a.nv), "rs": fa(&a.rs.to_array()), "rd": fa(&a.rd.to_array()),
        }),
        Material::LambertDbrdf(l) => json!({
            "rd": fa(&l.rd.to_array()),
            "lobe": dbrdf_json(&l.lobe),
        }),
        Material::DBrdf(d) => dbrdf_json(d),
        Material::Sh(ds) => json!({
            "bands": ds.bands(),
            "view_texels": ds.grid(),
            "coeff_lookup": ds.coeff_lookup,
            "cosine_included": ds.cosine_included(),
        }),
        Material::Merl(_) | Material::Rgl(_) => json!({}),
    };
    v["model"] = json!(m.name());
    v["file"] = json!(file);
    if matches!(m, Material::Merl(_)) {
        v["note"] = json!("MERL tables are not exported: use the scene's table file");
    }
    if matches!(m, Material::Rgl(_)) {
        v["note"] = json!("RGL tables are not exported: use the scene's .bsdf file");
    }
    v
}

/// Writes the material's data file into `dir`, if it has one: a file material's file
/// copied as it is (`material.exr`), a library SH data set or D-BRDF written in its format
/// (`material.exr`), a Lambert + D-BRDF material's lobe (`material-lobe.exr`). Returns
/// the path written.
pub(super) fn write_data_file(
    spec: &MaterialSpec,
    scene: &Scene,
    base: &Path,
    scene_path: &Path,
    dir: &Path,
) -> Result<Option<PathBuf>> {
    let source_file = match spec {
        MaterialSpec::ShFile { path, .. } | MaterialSpec::DbrdfFile { path } => {
            Some(base.join(path))
        }
        MaterialSpec::Lambert { .. }
        | MaterialSpec::BlinnPhong { .. }
        | MaterialSpec::Library { .. }
        | MaterialSpec::MerlFile { .. }
        | MaterialSpec::RglFile { .. } => None,
    };
    let p = dir.join("material.exr");
    if let Some(src) = source_file {
        let bytes = crate::image_io::read_regular_file(
            &src,
            crate::image_io::MAX_EXR_FILE_BYTES,
            "material file",
        )?;
        crate::image_io::write_atomic(&p, &bytes).map_err(|e| Error::io(&p, "cannot write", e))?;
        return Ok(Some(p));
    }
    let provenance = format!("brdfkit export of {}", scene_path.display());
    match &scene.material {
        Material::Sh(ds) => {
            crate::sh::file::write_sh_dataset(&p, ds).map_err(|e| Error::Message(e.to_string()))?;
            Ok(Some(p))
        }
        Material::DBrdf(d) => {
            crate::brdf::dbrdf::file::write_dbrdf(&p, d, &provenance)
                .map_err(|e| Error::Message(e.to_string()))?;
            Ok(Some(p))
        }
        Material::LambertDbrdf(l) => {
            let p = dir.join("material-lobe.exr");
            crate::brdf::dbrdf::file::write_dbrdf(&p, &l.lobe, &format!("{provenance} (lobe)"))
                .map_err(|e| Error::Message(e.to_string()))?;
            Ok(Some(p))
        }
        Material::Lambert(_)
        | Material::Phong(_)
        | Material::BlinnPhong(_)
        | Material::AshikhminShirley(_)
        | Material::Merl(_)
        | Material::Rgl(_) => Ok(None),
    }
}
