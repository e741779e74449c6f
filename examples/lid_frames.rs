//! The teapot's lid in the world-up shading frame and in the view-aligned frame that
//! isotropic tabulated materials are shaded in (`brdfkit::conventions`, "Frame of
//! isotropic tabulated materials"): one PNG per material, the two renders side by side,
//! cropped to the lid and knob, and their difference times 10 on the right.
//!
//! `cargo run --release --example lid_frames -- OUT_DIR [MATERIAL...]`

use brdfkit::image_io::{write_png, Image};
use brdfkit::render::{render, RenderOptions};
use brdfkit::scene::{Scene, SceneFile};
use brdfkit::shade::FrameCheck;
use std::path::Path;

fn main() {
    let mut args = std::env::args().skip(1);
    let out = args
        .next()
        .expect("usage: lid_frames OUT_DIR [MATERIAL...]");
    let mut materials: Vec<String> = args.collect();
    if materials.is_empty() {
        materials = [
            "teal-paint",
            "gold-dust-paint",
            "magenta-plastic",
            "red-velvet",
        ]
        .map(String::from)
        .to_vec();
    }
    std::fs::create_dir_all(&out).unwrap();
    for m in &materials {
        let text = format!(
            "[mesh]\nsegments = 8\n[material]\nkind = \"library\"\nname = \"{m}\"\n\
             [env]\nfile = \"assets/probes/studio.exr\"\n\
             [render]\nwidth = 960\nheight = 720\n"
        );
        let file = SceneFile::parse(&text).unwrap();
        let scene = Scene::resolve(&file, Path::new(env!("CARGO_MANIFEST_DIR"))).unwrap();
        let crop = |check: FrameCheck| {
            let mut opts = RenderOptions::default();
            opts.shading.frame_check = check;
            let img = render(&scene, &opts).image;
            // The lid and knob: the upper middle of the auto-framed teapot.
            let (x0, y0, w, h) = (330u32, 150u32, 300u32, 150u32);
            let mut c = Image::new(w, h);
            for y in 0..h {
                for x in 0..w {
                    c.pixels[(y * w + x) as usize] =
                        img.pixels[((y0 + y) * img.width + x0 + x) as usize];
                }
            }
            c
        };
        let (before, after) = (crop(FrameCheck::Unaligned), crop(FrameCheck::None));
        let w = before.width;
        let mut pair = Image::new(3 * w + 16, before.height);
        for y in 0..before.height {
            for x in 0..w {
                let i = (y * w + x) as usize;
                let row = (y * pair.width) as usize;
                pair.pixels[row + x as usize] = before.pixels[i];
                pair.pixels[row + (w + 8 + x) as usize] = after.pixels[i];
                pair.pixels[row + (2 * w + 16 + x) as usize] =
                    (before.pixels[i] - after.pixels[i]).abs() * 10.0;
            }
        }
        let path = Path::new(&out).join(format!("{m}.png"));
        write_png(&path, &pair, scene.output.exposure, scene.output.tonemap).unwrap();
        println!(
            "{}: world-up frame | view-aligned | difference x 10",
            path.display()
        );
    }
}
