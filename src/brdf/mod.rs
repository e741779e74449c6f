//! BRDF models: the material interface every shading path calls.
//!
//! Design rule: a BRDF is evaluated in the local shading frame of
//! [`crate::conventions::ShadingFrame`] (local +z is the normal, azimuth 0 is world up
//! projected onto the tangent plane). Directions point *away* from the surface: `wi` towards
//! the light, `wo` towards the viewer. Values are RGB reflectance in 1/sr.
//!
//! Tabulated models (SH coefficient tables, D-BRDF half-vector tables, MERL data) implement
//! the same trait, so the renderer does not care where a BRDF came from.
//!
//! Layering: this module is the leaf after [`crate::conventions`]. The trait names none of
//! its consumers (no kernel, SH, shading or scene types): the renderer's closed set of
//! shadeable materials is `crate::material::Material`, which wraps these models and
//! dispatches on its own tag. A file format sits beside the type it stores
//! ([`dbrdf::file`]; MERL's reader is [`MerlBrdf::read`]).
//!
//! Layout: one file per model ([`lambert`], [`phong`], [`blinn_phong`],
//! [`ashikhmin_shirley`], [`dbrdf`] with its file format, [`merl`], [`rgl`] (RGL `.bsdf`
//! tensor files, reader and writer), [`lambert_dbrdf`] the
//! Lambert + D-BRDF lobe); [`stand_ins`] the library's source models by name; [`real`]
//! the f32/f64 operations an analytic model's one generic formula uses.

pub mod ashikhmin_shirley;
pub mod blinn_phong;
pub mod dbrdf;
pub mod lambert;
pub mod lambert_dbrdf;
pub mod merl;
pub mod phong;
pub mod real;
pub mod rgl;
pub mod stand_ins;
#[cfg(test)]
mod tests_analytic;

/// Largest magnitude (1/sr) a value read from a tabulated BRDF file may have: a D-BRDF's
/// `c p(h)`, an SH coefficient, a MERL sample. Files with larger finite values (`1e38`
/// fits in an f32) are refused at load, naming the field: such a value is no measurement
/// (the sharpest measured specular peaks are ~1e4 1/sr), and in shading it overflows to
/// Inf once multiplied by a light's power.
///
/// Why 1e10: the shaded sum is at most `MAX_BRDF_VALUE` x (SH: `L^2 max|Y| <= 100 x 1.23`
/// for 10 bands; D-BRDF: Schlick `F <= 1`, `cos/D <= 1`) x the number of lights
/// (<= 65536) x the largest light power, so light powers up to ~1e21 stay finite in f32
/// (max 3.4e38), six orders of magnitude of headroom on either side.
pub const MAX_BRDF_VALUE: f32 = 1e10;

pub use ashikhmin_shirley::AshikhminShirley;
pub use blinn_phong::BlinnPhong;
pub use dbrdf::DBrdf;
pub use lambert::Lambert;
pub use lambert_dbrdf::LambertDbrdf;
pub use merl::MerlBrdf;
pub use phong::Phong;
pub use rgl::RglBrdf;

use glam::Vec3;

/// A bidirectional reflectance distribution function in the local shading frame.
pub trait Brdf: Send + Sync {
    /// `f_r(wi, wo)` in 1/sr for unit local directions (`wi` to the light, `wo` to the
    /// viewer). Must return zero (not NaN, not negative) when `wi.z <= 0` or `wo.z <= 0`.
    ///
    /// Unless [`Brdf::includes_cosine`] says so, the value does **not** include
    /// `cos(polar_i) = wi.z`; the renderer multiplies it in.
    fn eval(&self, wi: Vec3, wo: Vec3) -> Vec3;

    /// True when [`Brdf::eval`] already returns `f_r * cos(polar_i)` (as SH data acquired
    /// under basis illumination does, thesis 2.3.3). The renderer then does not apply the
    /// cosine a second time.
    fn includes_cosine(&self) -> bool {
        false
    }

    /// A short human-readable name ("lambert", "blinn-phong", ...).
    fn name(&self) -> &str;

    /// True when the model is isotropic: [`Brdf::eval`] depends on the azimuths of `wi`
    /// and `wo` only through their difference, so the tangent frame does not matter
    /// ([`crate::conventions`], "Frame of isotropic tabulated materials"). The default is
    /// the safe answer, false.
    fn is_isotropic(&self) -> bool {
        false
    }

    /// [`Brdf::eval`] in f64, for reference renders (`render.precision = "f64"`). The
    /// default promotes the f32 result; every model of this crate overrides it with an f64
    /// evaluation (Lambert, Phong, Blinn-Phong, Ashikhmin-Shirley, the D-BRDF except its f32
    /// table lookup, MERL, SH data sets, the library's source models), so an f64 render is
    /// an f64 reference of the formula; `tests_analytic` checks each against its f32 `eval`.
    /// The analytic models (Lambert, Phong, Blinn-Phong, Ashikhmin-Shirley) write the
    /// formula once, generic over the precision ([`real`]), and both methods call it.
    fn eval_f64(&self, wi: glam::DVec3, wo: glam::DVec3) -> glam::DVec3 {
        self.eval(wi.as_vec3(), wo.as_vec3()).as_dvec3()
    }

    /// [`Brdf::eval_f64`] at one view direction `wo` for each direction of `wi`, into `out`
    /// (the same length): the same bits as one call per direction. A model with work that
    /// depends on `wo` alone does it once (an SH data set's coefficient lookup); the
    /// reference path ([`crate::shade`]'s f64 path) evaluates a pixel's lights through it.
    fn eval_f64_at_view(&self, wo: glam::DVec3, wi: &[glam::DVec3], out: &mut [glam::DVec3]) {
        for (o, &w) in out.iter_mut().zip(wi) {
            *o = self.eval_f64(w, wo);
        }
    }

    /// An upper bound `M` (RGB, 1/sr) on `|f_r(wi, wo) cos(polar_i)|` over all pairs of
    /// directions above the horizon, i.e. on the absolute value of
    /// [`eval_cosine_weighted`]. One directional light of irradiance `E` then changes any
    /// pixel by at most `E M` (thesis Def. 10: the pixel is `sum_k f cos E_k`), which is the
    /// bound of dropping negligible lights (the renderer's `kernel::skip`). `None` when the model
    /// has no derived bound; the renderer then drops no light for it.
    fn max_cosine_weighted(&self) -> Option<Vec3> {
        None
    }

    /// The Lambertian term the model adds to its lobes (RGB, 1/sr): the constant `k_d / pi`
    /// of Blinn-Phong and Phong, `albedo / pi` of Lambert, `r_d / pi` of a Lambert +
    /// D-BRDF; zero for a model without one (a D-BRDF alone, measured tables, and a model
    /// whose [`Brdf::eval`] includes the cosine). `f - lambertian_term()` is the model's
    /// lobes, which is what a reflection-space table holds
    /// (`crate::env::reflection`, "Diffuse term").
    fn lambertian_term(&self) -> Vec3 {
        Vec3::ZERO
    }
}

/// `f * cos(polar_i)` whatever the model's cosine convention: the integrand of the
/// illumination integral (thesis Def. 6) per unit incident radiance.
#[inline]
pub fn eval_cosine_weighted(brdf: &dyn Brdf, wi: Vec3, wo: Vec3) -> Vec3 {
    if brdf.includes_cosine() {
        brdf.eval(wi, wo)
    } else {
        brdf.eval(wi, wo) * wi.z.max(0.0)
    }
}
