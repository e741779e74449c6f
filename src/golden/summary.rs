//! The one-line configuration summary of an entry's scene, stored in the manifest so a
//! changed scene or default is noticed.

use super::*;

/// The configuration summary of an entry's scene: mesh, size, material (with its
/// representation, SH bands and lookup), lights, environment sampler, precision, AOV.
pub fn summarize(file: &SceneFile, scene: &Scene, aov: Option<Aov>) -> String {
    let mut parts = vec![format!(
        "{}/{} {}x{}",
        file.mesh.source, file.mesh.segments, scene.render.width, scene.render.height
    )];
    let representation = match scene.material.as_sh() {
        Some(ds) => format!(
            " (SH {} bands, {} lookup)",
            ds.bands(),
            match ds.coeff_lookup {
                Lookup::Nearest => "nearest",
                Lookup::Bilinear => "bilinear",
            }
        ),
        None => match &file.material {
            MaterialSpec::Library { .. } => format!(" ({})", scene.material.name()),
            MaterialSpec::Lambert { .. }
            | MaterialSpec::BlinnPhong { .. }
            | MaterialSpec::ShFile { .. }
            | MaterialSpec::DbrdfFile { .. }
            | MaterialSpec::MerlFile { .. }
            | MaterialSpec::RglFile { .. } => String::new(),
        },
    };
    let file_name = |p: &Path| {
        p.file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default()
    };
    parts.push(match &file.material {
        MaterialSpec::Lambert { .. } => "lambert".to_string(),
        MaterialSpec::BlinnPhong { .. } => "blinn-phong".to_string(),
        MaterialSpec::Library { name, .. } => format!("library {name}{representation}"),
        MaterialSpec::ShFile { path, .. } => format!("sh-file {}{representation}", file_name(path)),
        MaterialSpec::DbrdfFile { path } => format!("dbrdf-file {}", file_name(path)),
        MaterialSpec::MerlFile { path } => format!("merl-file {}", file_name(path)),
        MaterialSpec::RglFile { path } => format!("rgl-file {}", file_name(path)),
    });
    let specs = file.light_specs();
    let count = |point: bool| {
        specs
            .iter()
            .filter(|l| matches!(l, LightSpec::Point { .. }) == point)
            .count()
    };
    for (n, kind) in [(count(true), "point"), (count(false), "directional")] {
        if n > 0 {
            parts.push(format!("{n} {kind}"));
        }
    }
    if let Some(env) = &file.env {
        use clap::ValueEnum;
        let sampler = env
            .sampler
            .to_possible_value()
            .map(|v| v.get_name().to_string())
            .unwrap_or_default();
        let lights = scene.env.as_ref().map_or(0, |e| e.lights);
        let probe = file_name(&env.file);
        parts.push(format!(
            "env {probe} {}",
            scene.environment.summary(&sampler, env.sampler, lights)
        ));
        if env.rotation != 0.0 {
            parts.push(format!("env rotated {} deg", env.rotation));
        }
    }
    if scene.render.cull == crate::raster::Cull::Back {
        parts.push("back-face culling".into());
    }
    parts.push(match aov {
        Some(a) => {
            use clap::ValueEnum;
            format!(
                "aov {}",
                a.to_possible_value()
                    .map(|v| v.get_name().to_string())
                    .unwrap_or_default()
            )
        }
        None => match scene.render.precision {
            Precision::F32 => "f32".into(),
            Precision::F64 => "f64".into(),
        },
    });
    parts.join(", ")
}
