//! The source models of the material library: the analytic BRDFs standing in for the
//! measurements behind the thesis's figures 3.9-3.15, which we do not have. The parameters
//! are the documentation.
//!
//! Design rule: a stand-in is a BRDF like any other (Ashikhmin-Shirley for the specular
//! materials, [`LambertDbrdf`] for plastic, synthetic fabric and velvet), keyed by the
//! library name; which *representation* the renderer uses for each (an SH data set acquired
//! from it, or a D-BRDF fitted to it) is the library's business (`crate::library`), not
//! this module's. Anisotropic exponents follow [`AshikhminShirley`]: `nu` along the tangent
//! (world up projected onto the surface), `nv` along the bitangent.

use super::{AshikhminShirley, Brdf, LambertDbrdf};
use glam::Vec3;
use std::sync::Arc;

fn lambert_dbrdf(nu: f32, nv: f32, rs: [f32; 3], rd: [f32; 3]) -> Arc<dyn Brdf> {
    Arc::new(LambertDbrdf::anisotropic_phong(
        nu,
        nv,
        Vec3::from(rs),
        Vec3::from(rd),
    ))
}

fn asx(nu: f32, nv: f32, rs: [f32; 3], rd: [f32; 3]) -> Arc<dyn Brdf> {
    Arc::new(AshikhminShirley {
        nu,
        nv,
        rs: Vec3::from(rs),
        rd: Vec3::from(rd),
    })
}

/// The source model of library material `name` (the stand-in for its measured data), or
/// `None` for a name that is not in the library.
pub fn source_model(name: &str) -> Option<Arc<dyn Brdf>> {
    Some(match name {
        // Woven synthetic: broad lobe, a little stretched across the weave. Changed from
        // A-S with the same parameters to Lambert + D-BRDF lobe: A-S's grazing spike made
        // the "broad sheen" a grazing mirror (weighted ringing -8.3 % at 5 bands, flagged),
        // unlike the thesis's Fig. 3.9; now -1.9 %, weighted rel L2 0.055.
        "blue-synthetic-fabric" => lambert_dbrdf(6.0, 24.0, [0.04, 0.05, 0.08], [0.06, 0.12, 0.5]),
        // Silk: very different exponents along and across the threads.
        "blue-silk" => asx(4.0, 160.0, [0.3, 0.35, 0.6], [0.02, 0.04, 0.22]),
        // Crinkled gold foil: sharp, slightly anisotropic metallic lobe, little diffuse.
        "lindt-paper" => asx(30.0, 90.0, [0.85, 0.62, 0.25], [0.3, 0.2, 0.05]),
        // Metallic flakes in a gold base: sharp coloured highlight over a gold diffuse.
        "gold-dust-paint" => asx(250.0, 250.0, [0.7, 0.5, 0.15], [0.3, 0.2, 0.04]),
        // Glossy dielectric paint: white highlight over teal.
        "teal-paint" => asx(200.0, 200.0, [0.06, 0.06, 0.06], [0.02, 0.35, 0.3]),
        // Plastic: broad weak highlight over a strong magenta diffuse. Changed from A-S with
        // the same parameters to Lambert + D-BRDF lobe: as A-S the 84.4 deg view row peaked
        // at f_r cos = 3.1 (12x the normal view) and the material was flagged for ringing
        // at every order >= 2, unlike the thesis's "diffuse" Fig. 3.14 (module doc of
        // `crate::acquire`); now weighted rel L2 0.033 / ringing -1.2 % at 5 bands.
        "magenta-plastic" => lambert_dbrdf(12.0, 12.0, [0.04, 0.04, 0.04], [0.7, 0.04, 0.45]),
        "red-velvet" => Arc::new(LambertDbrdf::velvet(
            Vec3::new(0.3, 0.015, 0.02),
            Vec3::new(0.9, 0.2, 0.2),
        )),
        _ => return None,
    })
}
