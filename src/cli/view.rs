//! `brdfkit view`: the command line of the interactive viewer ([`crate::view`]).

use super::ViewArgs;
use crate::env::lightset::prepare::CacheDir;
use crate::error::{Error, Result};
use crate::image_io;
use crate::scene::{MaterialSpec, SceneFile};
use crate::view::{self, script::Script, ViewConfig};
use std::path::{Path, PathBuf};

/// The probes shipped in `assets/probes` (from the working directory, else the source
/// tree this binary was built from), in the order P shows them.
fn shipped_probes() -> Vec<PathBuf> {
    ["city.exr", "sky.exr", "studio.exr"]
        .iter()
        .filter_map(|name| {
            let rel = Path::new("assets/probes").join(name);
            let here = std::env::current_dir().ok()?.join(&rel);
            let built = Path::new(env!("CARGO_MANIFEST_DIR")).join(&rel);
            [here, built].into_iter().find(|p| p.is_file())
        })
        .collect()
}

/// Makes every path of `file` absolute (relative ones are relative to `base`), so the
/// viewer's scene files can be written anywhere.
fn absolute_paths(file: &mut SceneFile, base: &Path) {
    let base = std::env::current_dir()
        .map(|d| d.join(base))
        .unwrap_or_else(|_| base.to_path_buf());
    if !matches!(file.mesh.source.as_str(), "teapot" | "sphere") {
        file.mesh.source = base.join(&file.mesh.source).to_string_lossy().into_owned();
    }
    match &mut file.material {
        MaterialSpec::ShFile { path, .. }
        | MaterialSpec::DbrdfFile { path }
        | MaterialSpec::MerlFile { path }
        | MaterialSpec::RglFile { path } => *path = base.join(&*path),
        _ => {}
    }
    if let Some(env) = file.env.as_mut() {
        env.file = base.join(&env.file);
    }
}

pub fn run(a: ViewArgs) -> Result<()> {
    // `render`'s own options (-o, --turntable, --reference, ...) are not in SceneArgs:
    // clap refuses them, and `view --help` does not list them.
    let r = &a.scene;
    if let Some(p) = &a.screenshot {
        image_io::check_output(p, &["png"], "--screenshot")?;
    }
    if let Some(p) = &a.window_shot {
        image_io::check_output(p, &["png"], "--window-shot")?;
    }
    if let Some(p) = &a.write_scene {
        image_io::check_output(p, &["toml"], "--write-scene")?;
    }
    let script = a.script.as_deref().map(Script::load).transpose()?;
    let (mut file, base) = super::render::scene_file(r, false)?;
    absolute_paths(&mut file, &base);
    let cwd = std::env::current_dir().unwrap_or_default();
    let mut probes: Vec<PathBuf> = a.probe.iter().map(|p| cwd.join(p)).collect();
    for p in &probes {
        if !p.is_file() {
            return Err(Error::format(p, "--probe: no such probe file"));
        }
    }
    probes.extend(shipped_probes());
    view::run(ViewConfig {
        file,
        probes,
        aov: r.aov,
        script,
        screenshot: a.screenshot,
        write_scene: a.write_scene,
        window_shot: a.window_shot,
        background: a.background,
        stats: r.stats,
        refine_steps: a.refine_steps,
        cache: if r.no_cache {
            CacheDir::None
        } else {
            CacheDir::user()?
        },
    })
}
