//! The material a scene is shaded with: a closed set of BRDF models, dispatched by tag.
//!
//! Design rule: the renderer shades exactly the models listed in [`Material`], one variant
//! per model, and every consumer that needs to know *which* model it has (the lane kernels'
//! [`crate::kernel::models::LaneModel::of`], the SH kernel's [`Material::as_sh`], the
//! golden summary) matches on the tag here instead of asking a trait object about itself.
//! This is the way pbrt-v4 dispatches materials and BRDFs (a closed set of types behind a
//! tagged pointer, Pharr, Jakob & Humphreys, *Physically Based Rendering*, 4th ed., 1.5.7):
//! the models in [`crate::brdf`] know nothing of their consumers, and adding a model means
//! adding a variant, which the compiler then asks every `match` to handle.
//!
//! A [`Material`] is built once per scene, by [`crate::scene::Scene::resolve`] (from
//! [`crate::scene::MaterialSpec`]), and is cheap to clone (tables are shared through
//! [`Arc`]). [`Material::as_brdf`] gives the [`Brdf`] view for the paths that evaluate
//! any model per light (the scalar oracle, the f64 path, the per-light fallback of the
//! lane kernels). Units and conventions are those of [`crate::brdf`]: local shading frame,
//! directions away from the surface, values in 1/sr.
//!
//! [`cone_bound`]: per model, an upper bound of `f cos` over a cone of incident directions
//! (what adaptive light cuts need), a function of this enum.

use crate::brdf::{
    AshikhminShirley, BlinnPhong, Brdf, DBrdf, Lambert, LambertDbrdf, MerlBrdf, Phong, RglBrdf,
};
use crate::conventions::{texel_center, FrameRule};
use crate::sh::dataset::ShDataset;
use glam::{DVec3, Vec3};
use std::sync::Arc;

pub mod cone_bound;

/// Every BRDF model the renderer can shade (module doc). Tabulated models are shared
/// ([`Arc`]), so cloning a scene copies no table.
#[derive(Clone, Debug)]
pub enum Material {
    /// [`Lambert`] (thesis 2.2.1).
    Lambert(Lambert),
    /// Normalised [`Phong`].
    Phong(Phong),
    /// Normalised [`BlinnPhong`].
    BlinnPhong(BlinnPhong),
    /// [`AshikhminShirley`] (anisotropic Phong with Fresnel).
    AshikhminShirley(AshikhminShirley),
    /// A [`DBrdf`] (thesis 2.3.6): a D-BRDF file or a library fit.
    DBrdf(Arc<DBrdf>),
    /// [`LambertDbrdf`], Lambert base plus a D-BRDF lobe (the library's stand-in for
    /// plastic, fabric and velvet).
    LambertDbrdf(Arc<LambertDbrdf>),
    /// A MERL table ([`MerlBrdf`]).
    Merl(Arc<MerlBrdf>),
    /// An RGL `.bsdf` material ([`RglBrdf`]): measured, isotropic or anisotropic.
    Rgl(Arc<RglBrdf>),
    /// An SH data set (thesis 2.3.3-2.3.4): an SH file or a library acquisition; shaded by
    /// the SH kernel.
    Sh(Arc<ShDataset>),
}

/// The models a transfer table can shade ([`Material::transfer_model`]): the table holds
/// the environment projected onto the SH basis of a data set, or the irradiance for
/// Lambert.
#[derive(Clone, Copy, Debug)]
pub enum TransferModel<'a> {
    /// An SH data set: `L_o = sum_k c_k(wo) T_k(n)`, `c` its coefficients at the view.
    Sh(&'a ShDataset),
    /// Lambert: `L_o = albedo / pi x E(n)`.
    Lambert(&'a Lambert),
}

/// Calls `$body` with `$m` bound to the model inside `$self`, statically per variant.
macro_rules! dispatch {
    ($self:expr, $m:ident => $body:expr) => {
        match $self {
            Material::Lambert($m) => $body,
            Material::Phong($m) => $body,
            Material::BlinnPhong($m) => $body,
            Material::AshikhminShirley($m) => $body,
            Material::DBrdf($m) => $body,
            Material::LambertDbrdf($m) => $body,
            Material::Merl($m) => $body,
            Material::Rgl($m) => $body,
            Material::Sh($m) => $body,
        }
    };
}

impl Material {
    /// The model as a [`Brdf`], for the paths that evaluate any model per light.
    pub fn as_brdf(&self) -> &dyn Brdf {
        match self {
            Material::Lambert(m) => m,
            Material::Phong(m) => m,
            Material::BlinnPhong(m) => m,
            Material::AshikhminShirley(m) => m,
            Material::DBrdf(m) => m.as_ref(),
            Material::LambertDbrdf(m) => m.as_ref(),
            Material::Merl(m) => m.as_ref(),
            Material::Rgl(m) => m.as_ref(),
            Material::Sh(m) => m.as_ref(),
        }
    }

    /// [`Brdf::eval`] of the model: `f_r(wi, wo)` in 1/sr (times `cos(polar_i)` when
    /// [`Material::includes_cosine`]).
    #[inline]
    pub fn eval(&self, wi: Vec3, wo: Vec3) -> Vec3 {
        dispatch!(self, m => m.eval(wi, wo))
    }

    /// [`Brdf::eval_f64`] of the model.
    #[inline]
    pub fn eval_f64(&self, wi: DVec3, wo: DVec3) -> DVec3 {
        dispatch!(self, m => m.eval_f64(wi, wo))
    }

    /// [`Brdf::includes_cosine`] of the model (true for SH data sets acquired under basis
    /// illumination).
    pub fn includes_cosine(&self) -> bool {
        dispatch!(self, m => m.includes_cosine())
    }

    /// [`Brdf::name`] of the model ("lambert", "sh-dataset", ...).
    pub fn name(&self) -> &str {
        dispatch!(self, m => m.name())
    }

    /// [`Brdf::lambertian_term`] of the model (RGB, 1/sr).
    pub fn lambertian_term(&self) -> Vec3 {
        dispatch!(self, m => m.lambertian_term())
    }

    /// [`Brdf::is_isotropic`] of the model.
    pub fn is_isotropic(&self) -> bool {
        dispatch!(self, m => m.is_isotropic())
    }

    /// [`Brdf::max_cosine_weighted`] of the model: a bound on `|f_r cos(polar_i)|`, RGB,
    /// 1/sr, or `None` when the model has none.
    pub fn max_cosine_weighted(&self) -> Option<Vec3> {
        dispatch!(self, m => m.max_cosine_weighted())
    }

    /// The shading frame the material is evaluated in ([`crate::conventions`], "Frame of
    /// isotropic tabulated materials" and "Frame of anisotropic materials"): the
    /// view-aligned frame for the isotropic tabulated models (an isotropic SH data set with
    /// the view at azimuth texel 0's centre, an isotropic D-BRDF or Lambert + D-BRDF with the
    /// view at azimuth 0), the mesh's tangent for anisotropic models
    /// ([`FrameRule::MESH_TANGENT`]), and the world-up frame for the analytic isotropic
    /// models, MERL and RGL, which are exact functions of the angles.
    pub fn frame_rule(&self) -> FrameRule {
        let view_azimuth = match self {
            Material::Sh(ds) => ds
                .isotropic
                .then(|| texel_center(0, ds.grid().0) * std::f32::consts::TAU),
            Material::DBrdf(d) => d.is_isotropic_table().then_some(0.0),
            Material::LambertDbrdf(d) => d.lobe.is_isotropic_table().then_some(0.0),
            Material::Lambert(_)
            | Material::Phong(_)
            | Material::BlinnPhong(_)
            | Material::AshikhminShirley(_)
            | Material::Merl(_)
            | Material::Rgl(_) => None,
        };
        match view_azimuth {
            Some(a) => FrameRule::view_at(a),
            None if self.is_isotropic() => FrameRule::UP,
            None => FrameRule::MESH_TANGENT,
        }
    }

    /// What a transfer table ([`crate::env::transfer`]) shades of this material: its SH data
    /// set or its Lambert albedo; `None` for every other model, which a transfer table
    /// cannot shade (the lights or the light cuts shade them). The one place that says which
    /// models have a transfer basis: the table's basis, whether a table fits, and the
    /// transfer term's coefficients all match on its answer.
    pub fn transfer_model(&self) -> Option<TransferModel<'_>> {
        match self {
            Material::Sh(ds) => Some(TransferModel::Sh(ds)),
            Material::Lambert(m) => Some(TransferModel::Lambert(m)),
            Material::Phong(_)
            | Material::BlinnPhong(_)
            | Material::AshikhminShirley(_)
            | Material::DBrdf(_)
            | Material::LambertDbrdf(_)
            | Material::Merl(_)
            | Material::Rgl(_) => None,
        }
    }

    /// The SH data set, when the material is one (the renderer then uses the SH kernel).
    pub fn as_sh(&self) -> Option<&ShDataset> {
        match self {
            Material::Sh(ds) => Some(ds),
            Material::Lambert(_)
            | Material::Phong(_)
            | Material::BlinnPhong(_)
            | Material::AshikhminShirley(_)
            | Material::DBrdf(_)
            | Material::LambertDbrdf(_)
            | Material::Merl(_)
            | Material::Rgl(_) => None,
        }
    }
}

macro_rules! from_value {
    ($($ty:ident => $variant:ident),*) => {$(
        impl From<$ty> for Material {
            fn from(m: $ty) -> Material {
                Material::$variant(m)
            }
        }
    )*};
}
from_value!(Lambert => Lambert, Phong => Phong, BlinnPhong => BlinnPhong,
    AshikhminShirley => AshikhminShirley);

macro_rules! from_shared {
    ($($ty:ident => $variant:ident),*) => {$(
        impl From<$ty> for Material {
            fn from(m: $ty) -> Material {
                Material::$variant(Arc::new(m))
            }
        }
        impl From<Arc<$ty>> for Material {
            fn from(m: Arc<$ty>) -> Material {
                Material::$variant(m)
            }
        }
    )*};
}
from_shared!(DBrdf => DBrdf, LambertDbrdf => LambertDbrdf, MerlBrdf => Merl,
    RglBrdf => Rgl, ShDataset => Sh);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::conventions::local_direction;

    /// Every variant answers exactly what its model answers (same bits): the dispatch adds
    /// nothing and picks the right model. A variant wired to another model of the list
    /// fails on the names, and on the values at these directions.
    #[test]
    fn dispatch_is_the_model() {
        let rd = Vec3::new(0.5, 0.3, 0.2);
        let dbrdf = DBrdf::from_fn(8, 4, Vec3::splat(0.1), |h| h.z.powi(4));
        let sh = crate::sh::ShDataset::zeros(2, 4, 2, true, "test").unwrap();
        let merl = MerlBrdf::tabulate(&BlinnPhong {
            kd: Vec3::splat(0.1),
            ks: Vec3::splat(0.5),
            exponent: 5.0,
        });
        let models: Vec<(Material, Box<dyn Brdf>)> = vec![
            (
                Lambert { albedo: rd }.into(),
                Box::new(Lambert { albedo: rd }),
            ),
            (
                Phong {
                    kd: rd,
                    ks: Vec3::splat(0.2),
                    exponent: 20.0,
                }
                .into(),
                Box::new(Phong {
                    kd: rd,
                    ks: Vec3::splat(0.2),
                    exponent: 20.0,
                }),
            ),
            (
                BlinnPhong {
                    kd: rd,
                    ks: Vec3::splat(0.2),
                    exponent: 20.0,
                }
                .into(),
                Box::new(BlinnPhong {
                    kd: rd,
                    ks: Vec3::splat(0.2),
                    exponent: 20.0,
                }),
            ),
            (
                AshikhminShirley {
                    nu: 10.0,
                    nv: 50.0,
                    rs: Vec3::splat(0.1),
                    rd,
                }
                .into(),
                Box::new(AshikhminShirley {
                    nu: 10.0,
                    nv: 50.0,
                    rs: Vec3::splat(0.1),
                    rd,
                }),
            ),
            (dbrdf.clone().into(), Box::new(dbrdf.clone())),
            (
                LambertDbrdf::velvet(rd, Vec3::splat(0.9)).into(),
                Box::new(LambertDbrdf::velvet(rd, Vec3::splat(0.9))),
            ),
            (merl.clone().into(), Box::new(merl.clone())),
            (sh.clone().into(), Box::new(sh.clone())),
        ];
        let wi = local_direction(0.4, 0.7);
        let wo = local_direction(0.3, 2.0);
        for (m, b) in &models {
            assert_eq!(m.name(), b.name());
            assert_eq!(m.as_brdf().name(), b.name());
            assert_eq!(m.eval(wi, wo), b.eval(wi, wo), "{}", b.name());
            assert_eq!(
                m.eval_f64(wi.as_dvec3(), wo.as_dvec3()),
                b.eval_f64(wi.as_dvec3(), wo.as_dvec3())
            );
            assert_eq!(m.includes_cosine(), b.includes_cosine());
            assert_eq!(m.max_cosine_weighted(), b.max_cosine_weighted());
            assert_eq!(m.as_sh().is_some(), b.name() == "sh-dataset");
        }
        // The models (all but the zero SH set) differ from each other here, so a variant wired
        // to another model would show.
        let values: Vec<Vec3> = models[..7].iter().map(|(m, _)| m.eval(wi, wo)).collect();
        for i in 0..values.len() {
            for j in 0..i {
                assert_ne!(
                    values[i],
                    values[j],
                    "{} vs {}",
                    models[i].1.name(),
                    models[j].1.name()
                );
            }
        }
    }
}
