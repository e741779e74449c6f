//! The scenes `brdfkit sweep` renders without `--scene`: the default scene, and one scene
//! per material class (`--class`, [`MaterialClass`]).
//!
//! Design rule: the default scene is the render defaults (sampler, light count, material
//! lookup) on a small frame, so the sweep's default row is what `brdfkit render` does out
//! of the box. The class scenes are the three material classes `[env] method = "auto"`
//! chooses for ([`crate::scene::env_method`]: diffuse, SH glossy, analytic glossy) on one
//! sphere under one shipped probe, each with its `[env]` at
//! the render defaults, small enough that a sweep of all three takes minutes: the front of
//! each is where a class's default method is chosen ([`super::fastest_within`]).

use super::Grid;
use crate::env::schema::EnvSpec;
use crate::error::{Error, Result};
use crate::scene::{MaterialSpec, SceneFile};
use crate::sh::dataset::Lookup;
use std::path::PathBuf;

/// The shipped probe `assets/probes/<name>`, from the working directory when it is the
/// repository, else from the crate's source directory; an error when neither has it.
fn shipped_probe(name: &str) -> Result<PathBuf> {
    let rel = PathBuf::from("assets/probes").join(name);
    let probe = if rel.is_file() {
        std::env::current_dir().map(|d| d.join(&rel)).unwrap_or(rel)
    } else {
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(&rel)
    };
    if !probe.is_file() {
        return Err(Error::format(
            &probe,
            "the sweep scene's probe is missing: run from the repository or give --scene",
        ));
    }
    Ok(probe)
}

/// The probe `--probe` names: a shipped probe by name (`city`, `sky`, `studio`: the file
/// `assets/probes/<name>.exr`), else a path to an HDR file. An error names the argument when
/// neither exists.
pub fn probe_path(name_or_file: &str) -> Result<PathBuf> {
    let file = PathBuf::from(name_or_file);
    if file.is_file() {
        return Ok(file);
    }
    if matches!(name_or_file, "city" | "sky" | "studio") {
        return shipped_probe(&format!("{name_or_file}.exr"));
    }
    Err(Error::field(
        "--probe",
        format!("{name_or_file:?} is neither a shipped probe (city, sky, studio) nor a file"),
    ))
}

/// The scene a sweep renders: the default is the teapot in `blue-silk` (library SH
/// material, 8 bands, its own bilinear lookup) under `assets/probes/city.exr`, 160x120,
/// environment sampler and count at their defaults (the render defaults).
pub fn default_scene_file() -> Result<SceneFile> {
    let mut f = SceneFile {
        material: MaterialSpec::Library {
            name: "blue-silk".into(),
            lookup: None,
        },
        env: Some(EnvSpec::new(shipped_probe("city.exr")?)),
        ..SceneFile::default()
    };
    f.render.width = 160;
    f.render.height = 120;
    Ok(f)
}

/// A material class the environment method's default is chosen for (`brdfkit sweep
/// --class`, [`crate::scene::env_method`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum MaterialClass {
    /// Lambert (albedo 0.8 grey).
    Diffuse,
    /// A glossy library SH material: `teal-paint` (glossy dielectric, 8 bands).
    ShGlossy,
    /// An analytic glossy lobe: energy-normalised Blinn-Phong, exponent 200.
    Glossy,
}

/// The `[material]` table of each class (TOML).
const CLASS_MATERIALS: [(MaterialClass, &str); 3] = [
    (
        MaterialClass::Diffuse,
        "kind = \"lambert\"\nalbedo = [0.8, 0.8, 0.8]\n",
    ),
    (
        MaterialClass::ShGlossy,
        "kind = \"library\"\nname = \"teal-paint\"\n",
    ),
    (
        MaterialClass::Glossy,
        "kind = \"blinn-phong\"\nkd = [0.05, 0.05, 0.05]\nks = [0.9, 0.9, 0.9]\nexponent = 200.0\n",
    ),
];

impl MaterialClass {
    /// Every class, in docs/sweeps.md's order.
    pub const ALL: [MaterialClass; 3] = [
        MaterialClass::Diffuse,
        MaterialClass::ShGlossy,
        MaterialClass::Glossy,
    ];

    /// The name `--class` takes (`diffuse`, `sh-glossy`, `glossy`).
    pub fn name(self) -> String {
        use clap::ValueEnum;
        self.to_possible_value()
            .map(|v| v.get_name().to_string())
            .unwrap_or_default()
    }

    /// The class's default grid: [`Grid::default`] (every method, sampler, count, table
    /// grid and exact-light count) with SH orders 2, 4, 6, 8 and the bilinear lookup only
    /// (the library material's own; dropped for the classes that are not SH), so the three
    /// class sweeps take minutes. The command line's axis flags replace any of it.
    pub fn grid(self) -> Grid {
        Grid {
            orders: vec![2, 4, 6, 8],
            lookups: vec![Some(Lookup::Bilinear)],
            ..Grid::default()
        }
    }

    /// The class's scene: a sphere (64 stacks) in the class's material under
    /// `assets/probes/city.exr` (`[env]` at the render defaults), 128x96. The sphere's
    /// tessellation error is the reference's too (the same mesh), so it does not enter the
    /// sweep's errors.
    pub fn scene_file(self) -> Result<SceneFile> {
        let material = CLASS_MATERIALS
            .iter()
            .find(|(c, _)| *c == self)
            .map(|(_, m)| *m)
            .expect("every class has a material");
        let text = format!(
            "[mesh]\nsource = \"sphere\"\nsegments = 64\n\n[material]\n{material}\n[render]\nwidth = 128\nheight = 96\n"
        );
        let mut f = SceneFile::parse(&text).map_err(Error::Message)?;
        f.env = Some(EnvSpec::new(shipped_probe("city.exr")?));
        Ok(f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::Material;
    use crate::scene::Scene;

    #[test]
    fn class_scenes_resolve_to_their_materials() {
        for c in MaterialClass::ALL {
            let mut f = c.scene_file().unwrap();
            // The material only: no probe needed to check it.
            f.env = None;
            let s = Scene::resolve(&f, std::path::Path::new(".")).unwrap();
            match (c, &s.material) {
                (MaterialClass::Diffuse, Material::Lambert(_)) => {}
                (MaterialClass::ShGlossy, Material::Sh(ds)) => assert_eq!(ds.bands(), 8),
                (MaterialClass::Glossy, Material::BlinnPhong(b)) => {
                    assert_eq!(b.exponent, 200.0)
                }
                (c, m) => panic!("{c:?}: {}", m.name()),
            }
            assert_eq!((s.render.width, s.render.height), (128, 96));
        }
    }
}
