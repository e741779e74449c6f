//! `[env] method = "auto"`, the default: the environment method chosen per material.
//!
//! Design rule: the choice is a function of the scene's material spec alone (no file is
//! read), so the command line, the sweep and [`super::Scene::resolve`] make the same choice
//! before anything is prepared. The choice comes from the sweep (`brdfkit sweep --class
//! diffuse|sh-glossy|glossy --probe city|studio|sky`; the numbers are in the README's
//! "Per material class" section): the fastest method whose error against the converged
//! reference is at most 1% relative RMSE *and* at most 5% at the 99th percentile of the
//! per-pixel relative error, under every shipped probe:
//! - Lambert and SH data sets: `transfer` (a table over normals from the full probe plus
//!   the 16 brightest texels): the per-pixel cost does not grow with the probe.
//! - Analytic lobes (Blinn-Phong) and D-BRDFs: `lightcuts` at `cut_error = 0.01`. A delta
//!   light set that meets 1% RMSE for a narrow lobe (Lloyd, 1024 lights) is faster, but
//!   its 99th percentile is tens of percent: the highlight shows the lights as spots. The
//!   cuts bound every pixel's error instead.
//!
//! A table that states `sampler` or `count` and no `method` asks for a delta light set:
//! its method is then `lights` ([`super::SceneFile::parse`]; a stated `method = "auto"`
//! stays auto); so do `--sampler` and `--lights` on the command line.

use super::MaterialSpec;
use crate::env::prepare::{EnvMethod, EnvSpec};
use crate::library::{self, Representation};

/// The method `auto` stands for under `material` (module doc).
pub fn auto_method(material: &MaterialSpec) -> EnvMethod {
    match material {
        MaterialSpec::Lambert { .. } | MaterialSpec::ShFile { .. } => EnvMethod::Transfer,
        MaterialSpec::BlinnPhong { .. } | MaterialSpec::DbrdfFile { .. } => EnvMethod::Lightcuts,
        MaterialSpec::Library { name, .. } => match library::find(name).map(|e| e.representation) {
            Some(Representation::Sh { .. }) => EnvMethod::Transfer,
            Some(Representation::Dbrdf) => EnvMethod::Lightcuts,
            // An unknown name is reported when the material is resolved.
            None => EnvMethod::Lights,
        },
    }
}

/// The `[env]` table's method, with `auto` replaced by [`auto_method`] of `material`, or by
/// `lights` when the table reads a light set file (`lights = "set.json"`: delta lights).
pub fn concrete_method(env: &EnvSpec, material: &MaterialSpec) -> EnvMethod {
    match env.method {
        EnvMethod::Auto if env.lights.is_some() => EnvMethod::Lights,
        EnvMethod::Auto => auto_method(material),
        m => m,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::SceneFile;

    fn method_of(toml: &str) -> EnvMethod {
        let f = SceneFile::parse(toml).unwrap();
        concrete_method(f.env.as_ref().unwrap(), &f.material)
    }

    #[test]
    fn auto_chooses_per_material_class() {
        let env = "[env]\nfile = \"p.exr\"\n";
        for (material, want) in [
            ("kind = \"lambert\"", EnvMethod::Transfer),
            (
                "kind = \"library\"\nname = \"teal-paint\"",
                EnvMethod::Transfer,
            ),
            (
                "kind = \"library\"\nname = \"lindt-paper\"",
                EnvMethod::Lightcuts,
            ),
            ("kind = \"blinn-phong\"", EnvMethod::Lightcuts),
            ("kind = \"sh-file\"\npath = \"m.exr\"", EnvMethod::Transfer),
            (
                "kind = \"dbrdf-file\"\npath = \"m.exr\"",
                EnvMethod::Lightcuts,
            ),
        ] {
            let text = format!("[material]\n{material}\n{env}");
            assert_eq!(method_of(&text), want, "{material}");
        }
        // No [material]: the default Blinn-Phong.
        assert_eq!(method_of(env), EnvMethod::Lightcuts);
    }

    #[test]
    fn a_stated_sampler_or_count_asks_for_lights() {
        for stated in ["sampler = \"median-cut\"", "count = 64"] {
            let text =
                format!("[material]\nkind = \"lambert\"\n[env]\nfile = \"p.exr\"\n{stated}\n");
            assert_eq!(method_of(&text), EnvMethod::Lights, "{stated}");
        }
        // An explicit method wins over the rule.
        let text = "[material]\nkind = \"lambert\"\n[env]\nfile = \"p.exr\"\ncount = 64\nmethod = \"transfer\"\n";
        assert_eq!(method_of(text), EnvMethod::Transfer);
        // A stated `auto` stays auto (a written-out scene file states every field).
        let text = "[env]\nfile = \"p.exr\"\nmethod = \"auto\"\ncount = 64\n";
        assert_eq!(method_of(text), EnvMethod::Lightcuts);
        // A light set file is delta lights.
        let text = "[material]\nkind = \"lambert\"\n[env]\nlights = \"set.json\"\n";
        assert_eq!(method_of(text), EnvMethod::Lights);
    }
}
