//! The material of a scene: its spec in the scene file, what a `--material` value names
//! (the file's extension, then its header), and building the material a spec names.
//!
//! Design rule: every way a scene names a material (analytic model, library name, SH file,
//! D-BRDF file, MERL table, RGL file) is one [`MaterialSpec`] variant, and [`resolve_material`] is the one place
//! that turns a spec into a [`Material`] (the renderer's closed set of models), checking its
//! values once with errors naming the `material.*` field.

use super::fields::{nonneg, rgb, strip_field};
use crate::brdf::{BlinnPhong, Lambert};
use crate::error::{Error, Result};
use crate::material::Material;
use crate::sh::dataset::Lookup;
use serde::Deserialize;
use std::path::{Path, PathBuf};

#[derive(Debug, Clone, Deserialize, serde::Serialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum MaterialSpec {
    Lambert {
        #[serde(default = "default_albedo")]
        albedo: [f32; 3],
    },
    BlinnPhong {
        #[serde(default = "default_kd")]
        kd: [f32; 3],
        #[serde(default = "default_ks")]
        ks: [f32; 3],
        #[serde(default = "default_exponent")]
        exponent: f32,
    },
    /// A library material by name (`brdfkit materials`), built at load time
    /// ([`crate::library::build`]).
    Library {
        name: String,
        /// Coefficient-table filter for SH materials; `None` keeps the library's (bilinear).
        /// A D-BRDF material with a lookup is an error naming `material.lookup`.
        #[serde(default)]
        lookup: Option<Lookup>,
    },
    /// An SH data set file ([`crate::sh::read_sh_dataset`]), path relative to the scene file.
    ShFile {
        path: PathBuf,
        /// Coefficient-table filter; `None` keeps the lookup the file records
        /// (`brdfkit.lookup`, [`crate::sh::file`]; nearest when the file has none).
        #[serde(default)]
        lookup: Option<Lookup>,
    },
    /// A D-BRDF file ([`crate::brdf::dbrdf::file::read_dbrdf`]), path relative to the
    /// scene file.
    DbrdfFile { path: PathBuf },
    /// A MERL table (`.binary`, [`crate::brdf::MerlBrdf::read`]), path relative to the
    /// scene file. Under an environment it is shaded with delta lights (`[env] method =
    /// "auto"` is `lights`).
    MerlFile { path: PathBuf },
    /// An RGL material (`.bsdf` tensor file, [`crate::brdf::RglBrdf::read`]), path relative
    /// to the scene file. Under an environment it is shaded with delta lights, as MERL.
    RglFile { path: PathBuf },
}

/// The material files `--material` (and `[material] path`) take, by extension, as one
/// clause of an error message.
pub const MATERIAL_FILE_KINDS: &str = ".exr (an SH data set from `brdfkit acquire` or a \
     D-BRDF from `brdfkit fit-dbrdf`), .binary (a MERL table) or .bsdf (an RGL material)";

impl MaterialSpec {
    /// The spec for a `--material` value: a library name, else a file path: a MERL table by
    /// its `.binary` extension, an RGL material by `.bsdf`, an SH data set or D-BRDF by the `brdfkit.format` attribute
    /// of its EXR header (`MATERIAL_FILE_KINDS`). Fails with a field error naming
    /// `--material` when the value is none of these (one line saying which kinds it takes).
    pub fn from_cli(value: &str) -> Result<MaterialSpec> {
        if crate::library::find(value).is_some() {
            return Ok(MaterialSpec::Library {
                name: value.to_string(),
                lookup: None,
            });
        }
        let path = PathBuf::from(value);
        let path = if path.is_absolute() {
            path
        } else {
            std::env::current_dir()
                .map(|d| d.join(&path))
                .unwrap_or(path)
        };
        if !path.exists() {
            return Err(Error::field(
                "--material",
                format!(
                    "{value:?} is neither a library material (see `brdfkit materials`) nor an existing file"
                ),
            ));
        }
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            // Read (and its size checked) when the scene is resolved.
            Some("binary") => return Ok(MaterialSpec::MerlFile { path }),
            Some("bsdf") => return Ok(MaterialSpec::RglFile { path }),
            Some("exr") => {}
            _ => {
                return Err(Error::field(
                    "--material",
                    format!(
                    "{}: not a material file brdfkit reads (by extension: {MATERIAL_FILE_KINDS})",
                    path.display()
                ),
                ))
            }
        }
        // The kind is the `brdfkit.format` header attribute: only the headers are read here
        // (after the regular-file and size checks); the file is read whole, once, when the
        // scene is resolved.
        use crate::image_io::exr_guard::{read_headers, Attributes, MAX_EXR_FILE_BYTES};
        let headers = read_headers(&path, MAX_EXR_FILE_BYTES, "material file")
            .map_err(|e| Error::field("--material", format!("{}: {e}", path.display())))?;
        let format = headers
            .headers()
            .first()
            .and_then(|h| Attributes(&h.own_attributes.other).string("brdfkit.format"));
        let (dbrdf, sh) = (
            crate::brdf::dbrdf::file::FORMAT_NAME,
            crate::sh::file::FORMAT_NAME,
        );
        match format.as_deref() {
            Some(f) if f == dbrdf => Ok(MaterialSpec::DbrdfFile { path }),
            Some(f) if f == sh => Ok(MaterialSpec::ShFile { path, lookup: None }),
            found => Err(Error::field(
                "--material",
                format!(
                    "{}: not a brdfkit material file (brdfkit.format is {}; expected '{sh}' \
                     from `brdfkit acquire` or '{dbrdf}' from `brdfkit fit-dbrdf`; a MERL \
                     table is a .binary file, an RGL material a .bsdf file)",
                    path.display(),
                    found.map_or("missing".to_string(), |f| format!("'{f}'"))
                ),
            )),
        }
    }
}

fn default_albedo() -> [f32; 3] {
    [0.8, 0.8, 0.8]
}
fn default_kd() -> [f32; 3] {
    [0.55, 0.22, 0.12]
}
fn default_ks() -> [f32; 3] {
    [0.25, 0.25, 0.25]
}
fn default_exponent() -> f32 {
    60.0
}

impl Default for MaterialSpec {
    fn default() -> Self {
        MaterialSpec::BlinnPhong {
            kd: default_kd(),
            ks: default_ks(),
            exponent: default_exponent(),
        }
    }
}

/// Builds the material a [`MaterialSpec`] names, its file paths relative to `base`. Field
/// errors name the field (`material.kd`, `material.path`, ...).
pub(super) fn resolve_material(spec: &MaterialSpec, base: &Path) -> Result<Material> {
    Ok(match spec {
        MaterialSpec::Lambert { albedo } => Material::from(Lambert {
            albedo: rgb("material.albedo", *albedo)?,
        }),
        MaterialSpec::BlinnPhong { kd, ks, exponent } => Material::from(BlinnPhong {
            kd: rgb("material.kd", *kd)?,
            ks: rgb("material.ks", *ks)?,
            exponent: nonneg("material.exponent", *exponent)?,
        }),
        MaterialSpec::Library { name, lookup } => {
            let m = crate::library::build(name)
                .map_err(|e| Error::field("material.name", strip_field(e)))?;
            match lookup {
                None => m,
                Some(mode) => {
                    let mut ds = m.as_sh().cloned().ok_or_else(|| {
                        Error::field(
                            "material.lookup",
                            format!(
                                "{name:?} is not an SH data set (it is a {}); only SH \
                                 materials have a coefficient lookup",
                                m.name()
                            ),
                        )
                    })?;
                    ds.coeff_lookup = *mode;
                    Material::from(ds)
                }
            }
        }
        MaterialSpec::ShFile { path, lookup } => {
            let mut ds = crate::sh::read_sh_dataset(&base.join(path))
                .map_err(|e| Error::field("material.path", e.to_string()))?;
            if let Some(mode) = lookup {
                ds.coeff_lookup = *mode;
            }
            Material::from(ds)
        }
        MaterialSpec::DbrdfFile { path } => Material::from(
            crate::brdf::dbrdf::file::read_dbrdf(&base.join(path))
                .map_err(|e| Error::field("material.path", e.to_string()))?
                .0,
        ),
        MaterialSpec::MerlFile { path } => Material::from(
            crate::brdf::MerlBrdf::read(&base.join(path))
                .map_err(|e| Error::field("material.path", e.to_string()))?,
        ),
        MaterialSpec::RglFile { path } => Material::from(
            crate::brdf::RglBrdf::read(&base.join(path))
                .map_err(|e| Error::field("material.path", e.to_string()))?,
        ),
    })
}
