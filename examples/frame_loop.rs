//! Renders one scene file's frame over and over, for profilers: the frame alone, without
//! the scene's preparation or any image writing in the profile.
//!
//! ```sh
//! cargo build --release --example frame_loop
//! perf record -o frame.data target/release/examples/frame_loop SCENE.toml [FRAMES]
//! perf report -i frame.data --no-children
//! ```
//!
//! Prepares the scene once (`Scene::resolve`: mesh, material, probe and light set or
//! transfer table), renders it FRAMES times (default 50) with the default options, and prints
//! the median frame time. The frame is what `brdfkit render` times as its frame and what
//! the `frame-640x480` benches measure (criterion remains the measure of speed; this is a
//! harness for `perf`).

use brdfkit::render::{self, RenderOptions};
use brdfkit::scene::{Scene, SceneFile};
use std::path::Path;
use std::time::Instant;

/// The allocator of the `brdfkit` binary and the benches (see src/main.rs).
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(path) = args.first() else {
        eprintln!("usage: frame_loop SCENE.toml [FRAMES]");
        std::process::exit(2);
    };
    let frames: usize = match args.get(1).map(|s| s.parse()) {
        None => 50,
        Some(Ok(n)) if n > 0 => n,
        Some(_) => {
            eprintln!(
                "error: FRAMES must be a positive integer, not '{}'",
                args[1]
            );
            std::process::exit(2);
        }
    };
    let path = Path::new(path);
    let scene = SceneFile::load(path)
        .and_then(|f| Scene::resolve(&f, path.parent().unwrap_or(Path::new("."))))
        .unwrap_or_else(|e| {
            eprintln!("error: {e}");
            std::process::exit(2);
        });
    // On the scene's `[render] threads`, as `brdfkit render` runs it, in one pool for
    // every frame (`RenderOptions::threads` would build a pool per frame).
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(scene.render.threads)
        .build()
        .expect("thread pool");
    let opts = RenderOptions::default();
    let counted = pool.install(|| {
        render::render(
            &scene,
            &RenderOptions {
                stats: true,
                ..RenderOptions::default()
            },
        )
    });
    if let Some(stats) = counted.stats {
        println!("{stats}");
    }
    let mut times: Vec<f64> = pool.install(|| {
        (0..frames)
            .map(|_| {
                let t = Instant::now();
                std::hint::black_box(render::render(&scene, &opts).image);
                t.elapsed().as_secs_f64() * 1e3
            })
            .collect()
    });
    times.sort_by(f64::total_cmp);
    println!(
        "{}: {frames} frames, median {:.2} ms",
        path.display(),
        times[frames / 2]
    );
}
