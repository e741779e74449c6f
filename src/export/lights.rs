//! The lights of an export: `scene_lights.json` (the scene's own lights, resolved) and
//! `lights.json` (the environment's delta lights, one copy: a light set of 130k texels is
//! written once, not once per file).

use super::camera::fa;
use crate::env::lightset::file::{write_json, LightSetHeader};
use crate::env::schema::{EnvMethod, EnvSpec};
use crate::env::LightSet;
use crate::error::{Error, Result};
use crate::light::Light;
use serde_json::json;
use std::path::Path;

/// The file the environment's lights are written to.
pub(super) const ENV_LIGHTS: &str = "lights.json";

/// `scene_lights.json`: the scene's own lights (its `[[light]]` tables, or the default
/// light), resolved, in shading order, and where the environment's lights are (they are
/// shaded after these, in the order of that file).
pub(super) fn scene_lights_json(own: &[Light], env_lights: Option<usize>) -> serde_json::Value {
    let list: Vec<serde_json::Value> = own
        .iter()
        .map(|l| match l {
            Light::Directional {
                to_light,
                irradiance,
            } => json!({
                "kind": "directional",
                "to_light": fa(&to_light.to_array()),
                "irradiance": fa(&irradiance.to_array()),
            }),
            Light::Point {
                position,
                intensity,
            } => json!({
                "kind": "point",
                "position": fa(&position.to_array()),
                "intensity": fa(&intensity.to_array()),
            }),
        })
        .collect();
    json!({
        "lights": list,
        "env_lights": env_lights.map(|n| json!({
            "file": ENV_LIGHTS,
            "count": n,
            "order": "shaded after `lights`, in the file's order; each is directional \
                      (to_light = dir_*, irradiance = irradiance_*)",
        })),
    })
}

/// Directional lights as a light set (bit-exact: the inverse of
/// [`crate::env::lightset::to_scene_lights`]).
pub(super) fn light_set_of(lights: &[Light]) -> LightSet {
    let mut ls = LightSet::default();
    for l in lights {
        if let Light::Directional {
            to_light,
            irradiance,
        } = l
        {
            ls.dir_x.push(to_light.x);
            ls.dir_y.push(to_light.y);
            ls.dir_z.push(to_light.z);
            ls.irradiance_r.push(irradiance.x);
            ls.irradiance_g.push(irradiance.y);
            ls.irradiance_b.push(irradiance.z);
        }
    }
    ls
}

/// Writes the environment's lights `env_lights` (after rotation and intensity) to
/// `dir/lights.json`; `spec` and `base` name where they came from in its header. Returns
/// the path written.
pub(super) fn write_env_lights(
    dir: &Path,
    spec: &EnvSpec,
    base: &Path,
    env_lights: &[Light],
) -> Result<std::path::PathBuf> {
    let ls = light_set_of(env_lights);
    let t = ls.total_irradiance();
    let sampler = match (&spec.lights, spec.method) {
        (Some(_), _) => "file".to_string(),
        // The texels the transfer table leaves out, summed exactly as lights.
        (None, EnvMethod::Transfer) => "transfer-brightest".to_string(),
        (None, _) => spec.sampler_config().name().to_string(),
    };
    let header = LightSetHeader {
        sampler,
        n: ls.len(),
        seed: (spec.lights.is_none() && spec.method != EnvMethod::Transfer).then_some(spec.seed),
        probe_file: (!spec.file.as_os_str().is_empty())
            .then(|| base.join(&spec.file).display().to_string()),
        total_irradiance: [t.x, t.y, t.z],
    };
    let j = dir.join(ENV_LIGHTS);
    write_json(&j, &header, &ls).map_err(|e| Error::Message(e.to_string()))?;
    Ok(j)
}
