//! The picture of the material library in the README and docs/rendering.md
//! (`assets/readme/materials.png`): every library material on the teapot under the default
//! scene's directional light, in `brdfkit materials` order, four to a row.
//!
//! ```sh
//! cargo run --release --example library_sheet -- [OUT.png] [PROBE...]
//! ```
//!
//! Each cell is `brdfkit render --material NAME --width 240 --height 180`, shown with the
//! scene's default exposure and tone map; OUT defaults to `assets/readme/materials.png`.
//! With probe names (`city`, `studio`, `sky`: files in `assets/probes/`) the sheet is the
//! library under each probe instead, one row per probe and one column per material, each
//! cell `--env assets/probes/PROBE.exr` at 160x120 through the `[env] method` `auto`
//! chooses: the grid a person looks at for stripes, streaks and negative radiance (black).

use brdfkit::image_io::display::display_u8;
use brdfkit::library::LIBRARY;
use brdfkit::render::{render, RenderOptions};
use brdfkit::scene::{MaterialSpec, Scene, SceneFile};
use std::path::{Path, PathBuf};

/// A cell of the sheet, in row-major order: the material and the probe (none: the
/// default scene's directional light).
type Cell<'a> = (&'a str, Option<&'a str>);

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let out = args
        .first()
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("assets/readme/materials.png"));
    let probes: Vec<&str> = args.iter().skip(1).map(String::as_str).collect();
    let (cell, per_row, cells): ((u32, u32), u32, Vec<Cell>) = if probes.is_empty() {
        (
            (240, 180),
            4,
            LIBRARY.iter().map(|m| (m.name, None)).collect(),
        )
    } else {
        let cells = probes
            .iter()
            .flat_map(|p| LIBRARY.iter().map(move |m| (m.name, Some(*p))))
            .collect();
        ((160, 120), LIBRARY.len() as u32, cells)
    };
    let rows = (cells.len() as u32).div_ceil(per_row);
    let (w, h) = (cell.0 * per_row, cell.1 * rows);
    let mut rgb = vec![0u8; (w * h * 3) as usize];
    for (k, (name, probe)) in cells.iter().enumerate() {
        let mut f = SceneFile::default();
        f.render.width = cell.0;
        f.render.height = cell.1;
        f.material = MaterialSpec::from_cli(name).expect("library names parse");
        if let Some(p) = probe {
            f.env = Some(brdfkit::env::schema::EnvSpec::new(PathBuf::from(format!(
                "assets/probes/{p}.exr"
            ))));
        }
        let scene = Scene::resolve(&f, Path::new(".")).expect("the scene resolves");
        let img = render(&scene, &RenderOptions::default()).image;
        let (cx, cy) = ((k as u32 % per_row) * cell.0, (k as u32 / per_row) * cell.1);
        for y in 0..cell.1 {
            for x in 0..cell.0 {
                let p = img.get(x, y);
                let at = (((cy + y) * w + cx + x) * 3) as usize;
                for (c, v) in p.to_array().into_iter().enumerate() {
                    rgb[at + c] = display_u8(v, scene.output.exposure, scene.output.tonemap);
                }
            }
        }
        eprintln!("{name} {}", probe.unwrap_or(""));
    }
    brdfkit::image_io::write_png_bytes(&out, w, h, rgb).expect("the picture is written");
    eprintln!("wrote {}", out.display());
}
