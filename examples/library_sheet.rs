//! The picture of the material library in the README and docs/rendering.md
//! (`assets/readme/materials.png`): every library material on the teapot under the default
//! scene's directional light, in `brdfkit materials` order, four to a row.
//!
//! ```sh
//! cargo run --release --example library_sheet -- [OUT.png]
//! ```
//!
//! Each cell is `brdfkit render --material NAME --width 240 --height 180`, shown with the
//! scene's default exposure and tone map; OUT defaults to `assets/readme/materials.png`.

use brdfkit::image_io::display::display_u8;
use brdfkit::library::LIBRARY;
use brdfkit::render::{render, RenderOptions};
use brdfkit::scene::{MaterialSpec, Scene, SceneFile};
use std::path::{Path, PathBuf};

const CELL: (u32, u32) = (240, 180);
const PER_ROW: u32 = 4;

fn main() {
    let out = std::env::args()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("assets/readme/materials.png"));
    let rows = (LIBRARY.len() as u32).div_ceil(PER_ROW);
    let (w, h) = (CELL.0 * PER_ROW, CELL.1 * rows);
    let mut rgb = vec![0u8; (w * h * 3) as usize];
    for (k, m) in LIBRARY.iter().enumerate() {
        let mut f = SceneFile::default();
        f.render.width = CELL.0;
        f.render.height = CELL.1;
        f.material = MaterialSpec::from_cli(m.name).expect("library names parse");
        let scene = Scene::resolve(&f, Path::new(".")).expect("the default scene resolves");
        let img = render(&scene, &RenderOptions::default()).image;
        let (cx, cy) = ((k as u32 % PER_ROW) * CELL.0, (k as u32 / PER_ROW) * CELL.1);
        for y in 0..CELL.1 {
            for x in 0..CELL.0 {
                let p = img.get(x, y);
                let at = (((cy + y) * w + cx + x) * 3) as usize;
                for (c, v) in p.to_array().into_iter().enumerate() {
                    rgb[at + c] = display_u8(v, scene.output.exposure, scene.output.tonemap);
                }
            }
        }
        eprintln!("{}", m.name);
    }
    brdfkit::image_io::write_png_bytes(&out, w, h, rgb).expect("the picture is written");
    eprintln!("wrote {}", out.display());
}
