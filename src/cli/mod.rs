//! The `brdfkit` command line. Every subcommand is a thin layer over the library: parse,
//! load and check input, call the pipeline, write output atomically. One file per
//! subcommand; this file holds the argument definitions and the dispatch, and stays whole
//! past 400 lines so that the arguments (and so the help text) of every subcommand read
//! in one place. `render` and `view` share `SceneArgs`; what only `render` takes is in
//! `RenderArgs`, so `view --help` lists only what `view` accepts.

mod acquire;
pub mod cache;
pub mod compare;
pub mod device;
pub mod export;
mod golden;
pub mod lights;
pub mod lights_overlay;
pub mod lights_report;
pub mod parse;
mod render;
mod render_shard;
pub mod source;
mod sweep;
mod turntable;
mod view;

pub use cache::{CacheAction, CacheArgs};
pub use compare::CompareArgs;
pub use export::ExportArgs;
pub use lights::LightsArgs;

use crate::aov::Aov;
use crate::error::Result;
use crate::image_io::Tonemap;
use clap::{Parser, Subcommand};
use std::path::PathBuf;

#[derive(Parser, Debug)]
#[command(
    name = "brdfkit",
    version,
    about = "Render acquired (measured) BRDF data on the CPU, and check GPU renders against it",
    long_about = "brdfkit renders measured BRDFs (spherical-harmonic coefficient tables, D-BRDF fits) \
under point, directional and environment lights on the CPU alone. It is a renderer for machines \
without a GPU, the oracle GPU builds are compared against, and a benchmark of the shading kernel.\n\n\
Start with `brdfkit render`: it writes out.png and out.exr of the built-in teapot scene."
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Render a scene (the built-in default scene when no file is given).
    #[command(
        after_help = "Examples:\n  brdfkit render                       # default scene -> out.png + out.exr\n  brdfkit render scene.toml -o a.exr   # linear float EXR\n  brdfkit render --mesh sphere --aov view-polar -o polar.png\n  brdfkit render --env city.exr --material blue-silk --turntable 60 -o spin.png   # spin_0000.png ... spin.gif\n  brdfkit render --env city.exr --env-method lights --turntable 60 --turntable-env -o env.png   # the environment turns instead\n  brdfkit render --turntable 60 --shard 0/2 -o spin.png; ... --shard 1/2 ...; brdfkit render --turntable 60 --assemble -o spin.png\n\nThe output format follows the extension (.png: exposure, tone map, sRGB, 8 bits; .exr: linear f32).\nCommand-line options override the scene file.\n\nLight-set cache (environment lights only): $BRDFKIT_CACHE_DIR, else $XDG_CACHE_HOME/brdfkit, else\n~/.cache/brdfkit; one file lights-KEY.json per probe bytes x loader options x sampler settings x\nbrdfkit version x light-set algorithm version, checked (checksum, versions) on every read.\n[env] method = \"transfer\" keeps its tables there too (transfer-KEY.bin: probe bytes x table\nsettings x versions). --no-cache neither reads nor writes it. `render` and `view` use this cache."
    )]
    Render(RenderArgs),
    /// Collapse a light probe into directional lights; write them and draw them over the probe.
    #[command(
        after_help = "Examples:\n  brdfkit lights city.exr --sampler median-cut -n 64 --overlay cut.png\n  brdfkit lights studio.exr --sampler lloyd -n 128 -o lights.json --report\n\nEvery light set carries exactly the probe's total power. --report prints the irradiance\nerror against the full probe (every texel a light)."
    )]
    Lights(LightsArgs),
    /// Compare two images (EXR with EXR, PNG with PNG): error metrics, FLIP, pass or fail.
    #[command(
        after_help = "Exit status: 0 pass, 1 fail, 2 unusable input (missing file, different sizes or colour layouts).\nEvery measure is over the covered pixels: those non-black in either image (the renderer's background is exactly 0), not the whole frame; the report says how many pixels were covered and measured. A NaN or infinite pixel fails first, listed with its coordinates.\nOn failure the FAIL line names each failed bound with its value and limit, an expected | FLIP heatmap | actual image is written (see --diff; one that cannot be written is a warning, the status stays 1) and the error histogram printed. --json prints one JSON object instead.\nRGBA images (EXR or PNG) compare with RGB ones on colour; --alpha compare compares alpha too.\n\nExample (a GPU build's CI):\n  brdfkit compare golden/default-160x120.exr gpu-out.exr --max-flip-mean 0.01\n  brdfkit compare golden/fig3-13-teal-paint.exr gpu-out.exr --bounds golden/gpu-bounds.toml --entry fig3-13-teal-paint"
    )]
    Compare(CompareArgs),
    /// Check, list or update the golden reference images in golden/.
    Golden {
        #[command(subcommand)]
        action: GoldenAction,
    },
    /// Acquire a BRDF as an SH data set (f_r cos per view texel) and print its error table.
    #[command(
        after_help = "SOURCE is a library material (`brdfkit materials`), a MERL .binary or RGL .bsdf path, or an analytic spec:\n  lambert:albedo=0.8/0.2/0.1\n  blinn-phong:kd=0.5,ks=0.2,exponent=60   (also phong)\n  ashikhmin-shirley:nu=10,nv=200,rs=0.05,rd=0.5/0.1/0.1\n\nExample:\n  brdfkit acquire teal-paint --bands 8 --method lsq --grid 16x8 -o teal.exr\n\nThe table lists bands 1..N for every method: relative L2 error of f_r cos over the hemisphere,\nthe most negative value relative to the peak, and the share of samples below zero."
    )]
    Acquire(AcquireArgs),
    /// Fit a D-BRDF (p(h) table, c, R_s) to a BRDF, print its error and write it.
    #[command(
        after_help = "Example:\n  brdfkit fit-dbrdf lindt-paper -o lindt.exr\n\nSOURCE as for `brdfkit acquire`. The file is a single-channel EXR (see brdf::dbrdf::file)."
    )]
    FitDbrdf(FitDbrdfArgs),
    /// List the material library (name, representation, description).
    Materials,
    /// Show where the caches are and how much they hold, or empty them (`cache clean`).
    #[command(
        after_help = "Examples:\n  brdfkit cache          # every cache: directory, files, size, cap\n  brdfkit cache clean    # delete their entries (only lights-*.json, transfer-*.bin and reference-*.exr[.xxh3|.fnv1a])\n\nLight sets and transfer tables (brdfkit render, view): $BRDFKIT_CACHE_DIR, else $XDG_CACHE_HOME/brdfkit, else ~/.cache/brdfkit; capped at $BRDFKIT_CACHE_MAX_MB megabytes (default 500), the least recently used entries evicted.\nSweep references (brdfkit sweep): target/brdfkit-cache, or the sweep's --cache DIR (here: --sweep-cache DIR); not capped.\nTests and golden check|bless use none of them."
    )]
    Cache(CacheArgs),
    /// Run time against error: render a scene over a grid of configurations, write CSV and a plot.
    #[command(
        long_about = "Renders a scene over a grid of configurations (environment method and its parameters \
x SH order x lookup x precision) and measures for each the error against the converged reference \
(every probe texel a light, f64, no culling: `render --reference`) and the time taken. Writes one CSV \
row per configuration and, with --plot, a PNG of frame time against relative RMSE (log axes, one \
colour per method and sampler, the Pareto front drawn, the 1% line, the default configuration and \
the fastest configuration within 1% marked). Prints the fastest configuration on the Pareto front \
at <= 1% relative RMSE.\n\n\
Methods ([env] method): lights (sampler x light count), transfer (table grid azimuth x polar x \
exact lights; SH data sets and Lambert only, left out for other materials), lightcuts (cut error x \
largest cut; left out for SH data sets, MERL and RGL tables), reflection (reflection-table grid \
x exact lights; isotropic materials that are not SH data sets).\n\n\
Default scene: the teapot in blue-silk (library SH material, 8 bands) under assets/probes/city.exr, \
160x120. --class diffuse|sh-glossy|glossy: a sphere in Lambert, teal-paint (SH, 8 bands) or \
Blinn-Phong exponent 200 under the same probe, 128x96, with SH orders 2, 4, 6, 8 and the bilinear \
lookup only (the flags below replace that). Default grid: methods lights, transfer, lightcuts, \
reflection; \
samplers uniform, importance, stratified, median-cut, lloyd x counts 1, 2, 4, ..., 1024; transfer \
grids 32x17, 64x33, 128x65 x exact lights 0, 16, 64; cut errors 0.005, 0.01, 0.02, 0.05 x largest \
cut 1000; reflection grids 32, 64 x the same exact lights; x orders 1..8 x lookups nearest, bilinear x \
precision f32: 1024 rows for an 8-band SH material.\n\n\
CSV columns: index, method, sampler, lights, transfer_azimuth, transfer_polar, exact_lights, \
cut_error, cut_max, reflection_grid (the method's parameters, - where not the row's method's), \
order, lookup, \
precision, rel_rmse (relative RMSE over covered pixels), p99_rel (99th percentile of the \
per-pixel relative error over covered pixels), max_err (largest absolute channel error, \
linear radiance), flip_mean (FLIP of the tone-mapped images), default (1 for the scene's own \
configuration): deterministic, the same on every machine; then prep_ms (the method's preparation: \
light set or transfer table), frame_ms (median frame time), pareto (1 if no other row is both \
faster and more accurate, over frame_ms and rel_rmse): measured, they vary run to run. A CSV \
written before the method, the p99_rel or the reflection_grid column is refused (regenerate it).\n\n\
The reference is rendered once (minutes for the default scene) and cached as EXR in --cache, keyed \
by a hash of the scene, its input files, the brdfkit version and the reference algorithm version, \
and checked on read (size, finite pixels, a checksum file beside it); --no-cache \
renders it without the cache. The sweep reads no other cache (light sets and tables are computed).",
        after_help = "Examples:\n  brdfkit sweep -o sweep.csv --plot sweep.png            # the default sweep (1024 rows)\n  brdfkit sweep --class sh-glossy -o sh.csv --plot sh.png # one material class\n  brdfkit sweep --methods lights --samplers median-cut,lloyd --counts 16,64,256 --orders 5,8 -o small.csv\n  brdfkit sweep --methods transfer --transfer-grids 64x33 --exact-lights 0,16 -o t.csv\n  brdfkit sweep --precisions f32,f64 --lookups bilinear -o prec.csv\n  brdfkit sweep --scene my.toml --plot my.png             # any scene with an [env]\n\nMany machines (shards are 0-based: I/N with 0 <= I < N; row k goes to shard k % N):\n  brdfkit sweep --shard 0/2 -o s0.csv      # on one machine\n  brdfkit sweep --shard 1/2 -o s1.csv      # on another\n  brdfkit sweep --merge s0.csv s1.csv -o sweep.csv --plot sweep.png\nThe merged CSV is what one run writes (rows by index, the pareto column recomputed over all rows).\n\nChecking a stored CSV against this build (deterministic columns, exactly; CI does this for the README's):\n  brdfkit sweep --check assets/readme/sweep.csv --shard 11/41\nIn a Slurm array job (#SBATCH --array=0-3): --shard \"$SLURM_ARRAY_TASK_ID/4\"."
    )]
    Sweep(SweepArgs),
    /// Write what a GPU build needs to draw a scene's frame: camera matrices, mesh, lights, material, resolved scene.
    #[command(
        after_help = "Example:\n  brdfkit export golden/default-160x120.toml -o gpu-scene\n\nWrites camera.json (eye, target, up, fov, near, viewport, view/projection matrices, conventions),\nmesh.obj (triangles, per-vertex normals), scene_lights.json (the scene's own lights; env_lights\nnames lights.json), lights.json (an [env]'s delta lights, once, after rotation and intensity),\ntransfer.json + transfer.bin (a transfer table), material.json (+ material.exr for SH data sets\nand D-BRDFs), scene.toml (renders the same bits: `brdfkit render scene.toml`, with --aov NAME\nfor an AOV export) and export.json. Light cuts are not exported. See docs/file-formats.md."
    )]
    Export(ExportArgs),
    /// Open a window on a scene: orbit, zoom, swap material and probe, watch it refine (X11).
    #[command(
        after_help = "Examples:\n  brdfkit view                                  # the default scene\n  brdfkit view --env assets/probes/city.exr --material teal-paint\n  brdfkit view --script s.txt --screenshot shot.png --write-scene shot.toml   # driven, then `brdfkit render shot.toml` gives the same pixels\n\nControls: drag orbit, wheel zoom, shift+drag turn the environment, m/n material, p probe, e method,\n]/[ lights x2 / /2, b SH band skip, l SH lookup, +/- exposure, a AOV, g probe background, h status line,\nr reset, q/Esc quit.\nScript lines (--script): `MS drag DX DY`, `MS shift-drag DX`, `MS wheel N`, `MS key K`, `MS resize W H`, `MS await-refined`, `MS quit`\n(MS: milliseconds from the first frame request; see src/view/script.rs). --stats prints frames per second\nand refinement times at the end. Render options set the scene as for `render`; --width/--height size the window."
    )]
    View(ViewArgs),
}

#[derive(clap::Args, Debug)]
pub struct ViewArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Drive the viewer from a file of timed input events (see below); it quits after the last.
    #[arg(long, value_name = "FILE")]
    pub script: Option<PathBuf>,
    /// At the end, write the last frame (without the status line) as a PNG, as `render` writes it.
    #[arg(long, value_name = "PNG")]
    pub screenshot: Option<PathBuf>,
    /// At the end, write the last frame's scene file: `brdfkit render FILE` gives the same pixels.
    #[arg(long, value_name = "TOML")]
    pub write_scene: Option<PathBuf>,
    /// At the end, write the window as shown (frame, probe background, status line) as a PNG.
    #[arg(long, value_name = "PNG")]
    pub window_shot: Option<PathBuf>,
    /// Show the probe behind the object from the start (key g; display only, never in --screenshot).
    #[arg(long)]
    pub background: bool,
    /// Another probe for P to cycle through (repeatable).
    #[arg(long, value_name = "PROBE")]
    pub probe: Vec<PathBuf>,
    /// Refinement steps while the view is still (0: none): 4x the lights each, the last with nothing dropped and every SH band.
    #[arg(long, default_value_t = crate::view::refine::DEFAULT_STEPS)]
    pub refine_steps: usize,
}

#[derive(clap::Args, Debug)]
pub struct SweepArgs {
    /// Output CSV. Default sweep.csv.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Also draw the plot (PNG): frame time against relative RMSE.
    #[arg(long, value_name = "PNG")]
    pub plot: Option<PathBuf>,
    /// Scene file (TOML) with an [env] to sweep. Default: blue-silk teapot, city probe, 160x120.
    #[arg(long, value_name = "FILE", conflicts_with = "class")]
    pub scene: Option<PathBuf>,
    /// A material class's built-in scene instead: a sphere under the city probe, 128x96, in Lambert (diffuse), teal-paint (sh-glossy, SH 8 bands) or Blinn-Phong exponent 200 (glossy).
    #[arg(long, value_enum)]
    pub class: Option<crate::sweep::MaterialClass>,
    /// Also require the 99th percentile of the per-pixel relative error (p99_rel) to be at most this fraction when choosing the fastest configuration within 1% (the rule behind `[env] method = "auto"` uses 0.1).
    #[arg(long, value_name = "FRACTION")]
    pub max_p99: Option<f64>,
    /// The probe lighting the swept scene instead of its own: a shipped probe by name (city, sky, studio) or an HDR file (lat-long EXR). The reference and every method use it.
    #[arg(long, value_name = "NAME|FILE")]
    pub probe: Option<String>,
    /// Environment methods, comma-separated: lights, transfer, lightcuts, reflection. Default all four (transfer only for SH data sets and Lambert; lightcuts for every material but SH data sets, MERL and RGL tables; reflection for isotropic materials but SH data sets).
    #[arg(long, value_enum, value_delimiter = ',')]
    pub methods: Vec<crate::sweep::MethodKind>,
    /// Lightcuts: cut error bounds (relative to the pixel), comma-separated. Default 0.005,0.01,0.02,0.05.
    #[arg(long, value_delimiter = ',')]
    pub cut_errors: Vec<f32>,
    /// Lightcuts: largest cuts (clusters per pixel), comma-separated. Default 1000.
    #[arg(long, value_delimiter = ',')]
    pub cut_maxes: Vec<usize>,
    /// Transfer-table grids AZIMUTHxPOLAR (azimuth nodes dividing the probe's width), comma-separated. Default 32x17,64x33,128x65.
    #[arg(long, value_delimiter = ',', value_name = "AxP")]
    pub transfer_grids: Vec<String>,
    /// Transfer and reflection: numbers of brightest texels summed exactly beside the table, comma-separated. Default 0,16,64.
    #[arg(long, value_delimiter = ',')]
    pub exact_lights: Vec<usize>,
    /// Reflection: table grids (cells per side of the octahedral grid of reflected directions, 2 to 1024), comma-separated. Default 32,64.
    #[arg(long, value_delimiter = ',', value_name = "CELLS")]
    pub reflection_grids: Vec<usize>,
    /// Lights: samplers, comma-separated. Default: uniform,importance,stratified,median-cut,lloyd.
    #[arg(long, value_enum, value_delimiter = ',')]
    pub samplers: Vec<crate::env::schema::SamplerKind>,
    /// Lights: light counts, comma-separated. Default: 1,2,4,...,1024.
    #[arg(long, value_delimiter = ',')]
    pub counts: Vec<usize>,
    /// SH orders (bands), comma-separated; orders above the data set's are dropped. Default 1..8.
    #[arg(long, value_delimiter = ',')]
    pub orders: Vec<usize>,
    /// Coefficient lookups, comma-separated: nearest, bilinear. Default both.
    #[arg(long, value_delimiter = ',')]
    pub lookups: Vec<String>,
    /// Precisions, comma-separated: f32 (default), f64 (several times slower).
    #[arg(long, value_delimiter = ',')]
    pub precisions: Vec<String>,
    /// Renders per row; frame_ms is their median.
    #[arg(long, default_value_t = 3)]
    pub frames: usize,
    /// Image width (overrides the scene).
    #[arg(long)]
    pub width: Option<u32>,
    /// Image height (overrides the scene).
    #[arg(long)]
    pub height: Option<u32>,
    /// Worker threads (0: every core).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Only rows with index % N == I (0-based I/N), for array jobs; merge with --merge.
    #[arg(long, value_name = "I/N")]
    pub shard: Option<String>,
    /// Directory of the cached reference renders (reference-KEY.exr, KEY a hash of the scene, its input files, the brdfkit version and the reference algorithm version; checked on read). Default target/brdfkit-cache.
    #[arg(long, value_name = "DIR", conflicts_with = "no_cache")]
    pub cache: Option<PathBuf>,
    /// Neither read nor write the reference cache: render the reference now and keep it only in memory.
    #[arg(long)]
    pub no_cache: bool,
    /// Merge these shard CSVs into -o (and --plot) instead of rendering.
    #[arg(long, num_args = 1.., value_name = "CSV")]
    pub merge: Vec<PathBuf>,
    /// Check a stored CSV instead of writing one: re-render its rows (the grid and options given, one frame each; --shard for a subset) and compare the deterministic columns (index .. default) exactly. Exit 1 naming each differing row, 0 when all match.
    #[arg(long, value_name = "CSV", conflicts_with_all = ["merge", "output", "plot"])]
    pub check: Option<PathBuf>,
}

#[derive(clap::Args, Debug)]
pub struct AcquireArgs {
    /// Library material name, MERL .binary or RGL .bsdf path, or analytic spec (see below).
    pub source: String,
    /// Number of SH bands (orders), 1 to 10.
    #[arg(long, default_value_t = 8)]
    pub bands: usize,
    /// Hemisphere fit: `zero` (zero extension, exact projection), `lsq` (regularised least squares on the hemisphere), `even` (mirror extension), `positive` (zero extension windowed by a non-negative kernel: never rings below zero, blurs sharp lobes; the table shows the cost), `nonneg` (lsq held to f_r cos >= 0 on a dense set of directions, what the library uses).
    #[arg(long, value_enum, default_value = "lsq")]
    pub method: MethodArg,
    /// Tikhonov weight for `--method lsq` and `nonneg` (default 1e-6).
    #[arg(long)]
    pub lambda: Option<f64>,
    /// View grid NUxNV (azimuth x polar texels, each 1 to 1024).
    #[arg(long, default_value = "16x8", value_parser = parse::grid)]
    pub grid: (usize, usize),
    /// Output SH data set (.exr).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Skip the bands x method table (only the chosen order and method are measured).
    #[arg(long)]
    pub no_table: bool,
    /// Declare the band energy threshold in the file (brdfkit.band_threshold, 0 <= F < 1): renderers may shade only the first bands while the dropped bands hold at most this fraction of the coefficient energy. Default: none (every band is shaded).
    #[arg(long, value_name = "F", allow_hyphen_values = true)]
    pub band_threshold: Option<f32>,
}

#[derive(clap::Args, Debug)]
pub struct FitDbrdfArgs {
    /// Library material name, MERL .binary or RGL .bsdf path, or analytic spec (as for `acquire`).
    pub source: String,
    /// Half-vector table NUxNV (each 1 to 1024).
    #[arg(long, default_value = "64x32", value_parser = parse::grid)]
    pub grid: (usize, usize),
    /// Output D-BRDF file (.exr).
    #[arg(short, long)]
    pub output: PathBuf,
}

/// What `render` and `view` both take: the scene file and the options that change it
/// (`render::scene_file` applies them); `render`'s own options are in `RenderArgs`.
#[derive(clap::Args, Debug)]
pub struct SceneArgs {
    /// Scene file (TOML). Every field has a default; the format (every field, its default,
    /// examples) is docs/scene-format.md in the brdfkit repository.
    pub scene: Option<PathBuf>,
    /// Image width in pixels (1 to 16384). Default 640.
    #[arg(long)]
    pub width: Option<u32>,
    /// Image height in pixels (1 to 16384). Default 480.
    #[arg(long)]
    pub height: Option<u32>,
    /// Worker threads; 0 uses every core. The image is bit-identical for any value.
    #[arg(long)]
    pub threads: Option<usize>,
    /// Mesh: `teapot` (Newell's patches, built in), `sphere`, or a path to an OBJ file.
    #[arg(long)]
    pub mesh: Option<String>,
    /// Face culling: `none` renders both sides (the teapot's inside shows through the lid gap), `back` drops back faces.
    #[arg(long, value_enum)]
    pub cull: Option<CullArg>,
    /// Write a debug output instead of the shaded image.
    #[arg(long, value_enum)]
    pub aov: Option<Aov>,
    /// Tile edge in pixels (1 to 1024). Default 32. Does not change the image.
    #[arg(long)]
    pub tile_size: Option<u32>,
    /// Exposure in stops applied before the tone map (PNG only).
    #[arg(long, allow_hyphen_values = true)]
    pub exposure: Option<f32>,
    /// Tone map for PNG output.
    #[arg(long, value_enum)]
    pub tonemap: Option<Tonemap>,
    /// Light the scene with an equirectangular probe (.exr or .hdr), collapsed into directional lights.
    #[arg(long, value_name = "PROBE")]
    pub env: Option<PathBuf>,
    /// How the probe becomes lights (with --env or a scene's [env]). Default lloyd (on the sweep's Pareto front; see `brdfkit sweep`).
    #[arg(long, value_enum)]
    pub sampler: Option<crate::env::schema::SamplerKind>,
    /// Number of environment lights (with --env or a scene's [env]). Default 128.
    #[arg(long, value_name = "N")]
    pub lights: Option<usize>,
    /// How the environment is shaded (with --env or a scene's [env]); overrides the scene's `[env] method`. `transfer`: SH data sets and Lambert only. `render --reference` always shades the full probe.
    #[arg(long, value_enum, value_name = "METHOD")]
    pub env_method: Option<crate::env::schema::EnvMethod>,
    /// Material: a library name (`brdfkit materials`) or a file: .exr (an SH data set from `brdfkit acquire` or a D-BRDF from `brdfkit fit-dbrdf`) or .binary (a MERL table) or .bsdf (an RGL material). Overrides the scene's `[material]`.
    #[arg(long)]
    pub material: Option<String>,
    /// Coefficient lookup of an SH material (library or file): nearest (GL_NEAREST) or bilinear (GL_LINEAR). Overrides the scene's `material.lookup` and the lookup the file records (acquired files record bilinear; files without one use nearest). An error for a material that is not an SH data set.
    #[arg(long, value_enum)]
    pub lookup: Option<crate::sh::Lookup>,
    /// Drop the weakest directional lights while their summed irradiance stays at most this fraction of the total (0 <= F < 1; 0: off). Each pixel changes by at most the dropped irradiance times the material's largest f*cos. Default 0.001.
    #[arg(long, value_name = "F", allow_hyphen_values = true)]
    pub drop_lights: Option<f32>,
    /// Shade SH data sets with every stored band, ignoring the band energy threshold the data set declares (brdfkit.band_threshold).
    #[arg(long)]
    pub no_band_skip: bool,
    /// Kernel path of the f32 shading: auto (the widest this CPU runs), portable, avx2 (an error where the CPU lacks AVX2+FMA) or avx512 (an error without AVX-512F+VL). Every path gives the same bits; only speed differs.
    #[arg(long, value_enum)]
    pub kernel: Option<crate::lanes::KernelPath>,
    /// Print statistics to stderr: `render` the work counters (tiles shaded/skipped, pixels, pixel x light pairs, the kernels' lane use, lights dropped, SH bands used), `view` frames per second and refinement times at the end.
    #[arg(long)]
    pub stats: bool,
    /// Neither read nor write the light-set cache: compute the environment's light set (or transfer table) every time.
    #[arg(long)]
    pub no_cache: bool,
}

/// `brdfkit render`: the scene options (`SceneArgs`, shared with `view`) and what only
/// `render` takes (an output path, the reference, a turntable, the device).
#[derive(clap::Args, Debug)]
pub struct RenderArgs {
    /// Output image: .png (tone-mapped sRGB) or .exr (linear float). Default: out.png and out.exr.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    #[command(flatten)]
    pub common: SceneArgs,
    /// Render the converged reference: every texel of the probe a light (with an environment; --lights is ignored), every SH band, no skips, no culling, f64 shading. Minutes where the fast path takes milliseconds; shows a bar with an ETA on a terminal. The reference the fast path is measured against (golden bounds, sweep).
    #[arg(long)]
    pub reference: bool,
    /// Render N frames with the camera orbiting the look-at point about world up (+y), one full turn: OUT_0000.png ... and OUT.gif (OUT from -o, default out).
    #[arg(long, value_name = "N")]
    pub turntable: Option<usize>,
    /// With --turntable: keep the camera still and turn the environment about +y instead (frame k: [env] rotation + 360 k / N degrees, every method).
    #[arg(long, requires = "turntable")]
    pub turntable_env: bool,
    /// Only shard I of N (0-based I/N), for array jobs. With --turntable: only frames k with k % N == I, and no GIF (--assemble makes it after). A still image (any render, --reference included): only its bands of rows b with b % N == I (a band is a whole number of tiles, 32 rows by default), written to -o PART.exr as a partial image whose header records the shard, the full size and the scene's hash; --merge joins the N parts.
    #[arg(long, value_name = "I/N")]
    pub shard: Option<String>,
    /// Render nothing: join the partial images of `render --shard I/N` (every shard 0..N once, all of one scene and size) into -o (.exr or .png; default out.png and out.exr), the bits of the unsharded render. The parts carry the scene and its size: only -o, --exposure and --tonemap go with it.
    #[arg(long, value_name = "PART", num_args = 1.., conflicts_with_all = [
        "turntable", "shard", "reference", "device", "scene", "width", "height", "threads",
        "mesh", "cull", "aov", "tile_size", "env", "sampler", "lights", "env_method",
        "material", "lookup", "drop_lights", "no_band_skip", "kernel", "stats", "no_cache",
    ])]
    pub merge: Vec<PathBuf>,
    /// With --turntable: render nothing; build OUT.gif from the existing OUT_0000.png ... frames.
    #[arg(long, requires = "turntable")]
    pub assemble: bool,
    /// With --turntable: GIF frame rate (frames per second; GIF stores delays in 1/100 s).
    #[arg(long, default_value_t = 25, requires = "turntable")]
    pub fps: u32,
    /// Renderer: cpu (the oracle, default), gpu (the wgpu renderer: needs the `gpu` cargo feature and an adapter), auto (gpu when it can, else cpu with one line saying why).
    #[arg(long, value_enum, default_value = "cpu")]
    pub device: device::Device,
}

/// `acquire --method`: how the hemisphere data is extended to the sphere (the library's
/// `acquire::Method`; `lsq` takes its weight from `--lambda`).
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq)]
pub enum MethodArg {
    Zero,
    Lsq,
    Even,
    Positive,
    Nonneg,
}

#[derive(clap::ValueEnum, Clone, Copy, Debug)]
pub enum CullArg {
    None,
    Back,
}

/// `golden check --device`.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum GoldenDevice {
    Cpu,
    Gpu,
}

#[derive(Subcommand, Debug)]
pub enum GoldenAction {
    /// Re-render golden entries (all, or the named ones) and compare each with its stored image: identical bits on the platform and kernel path that blessed it (the manifest's blessed_on), the entry's tolerance elsewhere (exit 1 if any fails). Never writes golden/. Reads and writes no cache: every light set is computed from its probe.
    #[command(
        after_help = "Examples:\n  brdfkit golden check                      # every entry, on the best kernel path\n  brdfkit golden check --kernel portable     # the same on the portable path\n  brdfkit golden check --bounds fig3-8-lloyd-studio   # also re-measure fast vs reference (small)"
    )]
    Check {
        /// Entries to check (default: every entry of the manifest).
        names: Vec<String>,
        /// Golden directory.
        #[arg(long, default_value = "golden")]
        dir: PathBuf,
        /// Kernel path to render on: auto (the widest this CPU runs), portable, avx2 or avx512.
        #[arg(long, value_enum, default_value = "auto")]
        kernel: crate::lanes::KernelPath,
        /// Also re-measure each shaded entry's fast-vs-reference bound at 1/4 of its size (f64 reference with every probe texel a light: seconds per environment entry) and hold it to the stored bound (10% + 1e-6 margin).
        #[arg(long)]
        bounds: bool,
        /// cpu: re-render on the CPU (exact bits on the blessing path); gpu: render every entry the wgpu renderer supports and compare at the entry's FLIP bounds (golden/gpu-bounds.toml may tighten or loosen them per entry), listing the others as skipped.
        #[arg(long, value_enum, default_value = "cpu")]
        device: GoldenDevice,
        /// Seeded GPU fault (half-texel, no-cosine, mirrored-azimuth, srgb-twice), to show that the check fails on it.
        #[arg(long, hide = true)]
        gpu_fault: Option<String>,
        /// Only shard I of N (0-based I/N): entries k with k % N == I of the selection (the names given, else every entry) in manifest order. With --json, a report to merge.
        #[arg(long, value_name = "I/N")]
        shard: Option<String>,
        /// Also write a JSON report (the shard, the selection, the manifest's hash, each entry's outcome) to FILE, for `golden check --merge`.
        #[arg(long, value_name = "FILE")]
        json: Option<PathBuf>,
        /// Check nothing: merge the --json reports of every shard (0..N, each once, of one manifest and selection) into one verdict, with the exit status of an unsharded check.
        #[arg(long, value_name = "REPORT", num_args = 1.., conflicts_with_all = ["shard", "json", "bounds", "names"])]
        merge: Vec<PathBuf>,
    },
    /// List the golden entries for scripts: one line per entry, tab-separated: name, scene file, FLIP bounds of the manifest (mean=M,p99=V), FLIP bounds a GPU build is held to (golden/gpu-bounds.toml's, else the manifest's), AOV (- for a shaded image).
    List {
        /// Golden directory.
        #[arg(long, default_value = "golden")]
        dir: PathBuf,
        /// Print the entries as one JSON object on stdout instead.
        #[arg(long)]
        json: bool,
    },
    /// Re-render and overwrite golden images (all, or the named entries), their hashes, configuration summaries and measured fast-vs-reference bounds (the reference render with the full probe is slow), and the table in golden/README.md. The only command that writes golden/. Reads and writes no cache.
    Bless {
        /// Entries to bless (default: every entry of the manifest).
        names: Vec<String>,
        #[arg(long, default_value = "golden")]
        dir: PathBuf,
        /// Kernel path to render on (recorded in the manifest's blessed_on).
        #[arg(long, value_enum, default_value = "auto")]
        kernel: crate::lanes::KernelPath,
        /// Only shard I of N (0-based I/N): entries k with k % N == I of the selection in manifest order. Writes those entries' images, and their manifest records to --records FILE instead of the manifest; `golden bless --merge` writes the records into the manifest.
        #[arg(long, value_name = "I/N", requires = "records")]
        shard: Option<String>,
        /// With --shard: where the shard's manifest records go (TOML).
        #[arg(long, value_name = "FILE", requires = "shard")]
        records: Option<PathBuf>,
        /// Bless nothing: write the --records of every shard (0..N, each once, from this manifest) into the manifest and the README table.
        #[arg(long, value_name = "RECORDS", num_args = 1.., conflicts_with_all = ["shard", "records", "names"])]
        merge: Vec<PathBuf>,
    },
}

/// Runs the command line; `Ok(false)` means "ran, but the check failed" (exit 1).
pub fn run(cli: Cli) -> Result<bool> {
    match cli.command {
        Command::Render(args) => render::run(args).map(|_| true),
        Command::Golden { action } => golden::run(action),
        Command::Lights(args) => lights::run(args).map(|_| true),
        Command::Compare(args) => compare::run(args),
        Command::Acquire(args) => acquire::run_acquire(args).map(|_| true),
        Command::FitDbrdf(args) => acquire::run_fit(args).map(|_| true),
        Command::Materials => acquire::run_materials().map(|_| true),
        Command::Cache(args) => cache::run(args).map(|_| true),
        Command::Sweep(args) => sweep::run(args),
        Command::Export(args) => export::run(args).map(|_| true),
        Command::View(args) => view::run(args).map(|_| true),
    }
}
