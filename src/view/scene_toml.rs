//! The scene file of a frame, written as TOML: `brdfkit render FILE` renders exactly the
//! frame the viewer showed (the Xvfb test checks this pixel for pixel).

use crate::error::{Error, Result};
use crate::scene::SceneFile;
use std::path::Path;

/// The TOML text of `file`, with no output path (`render -o` chooses it). Paths in it are
/// as the viewer holds them: absolute.
pub fn scene_toml(file: &SceneFile) -> Result<String> {
    let mut f = file.clone();
    f.output.path = None;
    let body = toml::to_string(&f)
        .map_err(|e| Error::Message(format!("cannot write the view as a scene file: {e}")))?;
    Ok(format!(
        "# The frame `brdfkit view` showed; `brdfkit render` of this file gives the same pixels.\n{body}"
    ))
}

/// Writes [`scene_toml`] of `file` to `path` (atomically).
pub fn write_scene(path: &Path, file: &SceneFile) -> Result<()> {
    let text = scene_toml(file)?;
    crate::image_io::write_atomically(path, |tmp| {
        std::fs::write(tmp, &text).map_err(|e| Error::io(path, "cannot write scene file", e))
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::env::schema::EnvSpec;
    use crate::scene::CameraSpec;

    #[test]
    fn the_written_file_reads_back_as_the_same_scene_file() {
        let mut f = SceneFile {
            env: Some(EnvSpec::new("/probes/city.exr".into())),
            ..SceneFile::default()
        };
        f.env.as_mut().unwrap().rotation = 12.5;
        f.camera = Some(CameraSpec {
            position: Some([0.1, 1.0 / 3.0, 7.0]),
            target: Some([0.0, 0.5, 0.0]),
            up: Some([0.0, 1.0, 0.0]),
            ..CameraSpec::default()
        });
        f.render.width = 321;
        let text = scene_toml(&f).unwrap();
        let back = SceneFile::parse(&text).unwrap();
        // Every field survives (f32 values exactly: printed shortest, read back to the bit).
        assert_eq!(format!("{back:?}"), format!("{f:?}"));
    }
}
