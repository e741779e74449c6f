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
//! transfer table), renders it FRAMES times (default 50) with the default options into one
//! frame context (`render::render_into`, as the viewer draws), and prints the median frame
//! time and the minor page faults of the first frame and of each later one. The frame is what `brdfkit render` times as its frame and what
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
    // Every frame into one frame context, as the viewer draws: the first frame sizes its
    // buffers, the others reuse them.
    let mut ctx = render::FrameContext::default();
    let mut faults = Vec::with_capacity(frames);
    let mut times: Vec<f64> = pool.install(|| {
        (0..frames)
            .map(|_| {
                let f = minor_faults();
                let t = Instant::now();
                std::hint::black_box(render::render_into(&scene, &opts, &mut ctx).image);
                let ms = t.elapsed().as_secs_f64() * 1e3;
                faults.push(minor_faults() - f);
                ms
            })
            .collect()
    });
    times.sort_by(f64::total_cmp);
    // The first frame sizes the context; the others are the steady state.
    let steady = &faults[1.min(frames - 1)..];
    println!(
        "{}: {frames} frames, median {:.2} ms; minor page faults: first frame {}, then {:.1} \
         per frame",
        path.display(),
        times[frames / 2],
        faults[0],
        steady.iter().sum::<i64>() as f64 / steady.len() as f64
    );
}

/// The process's minor page faults so far (`getrusage`), every thread's.
fn minor_faults() -> i64 {
    // SAFETY: `getrusage` writes one `rusage` into the zeroed struct it is given.
    let mut u: libc::rusage = unsafe { std::mem::zeroed() };
    unsafe { libc::getrusage(libc::RUSAGE_SELF, &mut u) };
    u.ru_minflt
}
