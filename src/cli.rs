//! The `brdfkit` command line. Every subcommand is a thin layer over the library: parse,
//! load and check input, call the pipeline, write output atomically.

use crate::aov::{self, Aov};
use crate::error::{Error, Result};
use crate::image_io::{self, Format, Tonemap};
use crate::raster::Cull;
use crate::render;
use crate::scene::{Scene, SceneFile, MAX_SIDE};
use clap::{Parser, Subcommand};
use std::path::{Path, PathBuf};

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
        after_help = "Examples:\n  brdfkit render                       # default scene -> out.png + out.exr\n  brdfkit render scene.toml -o a.exr   # linear float EXR\n  brdfkit render --mesh sphere --aov view-polar -o polar.png\n\nThe output format follows the extension (.png: exposure, tone map, sRGB, 8 bits; .exr: linear f32).\nCommand-line options override the scene file."
    )]
    Render(RenderArgs),
    /// Check or update the golden reference images in golden/.
    Golden {
        #[command(subcommand)]
        action: GoldenAction,
    },
}

#[derive(clap::Args, Debug)]
pub struct RenderArgs {
    /// Scene file (TOML). Every field has a default; see the README for the format.
    pub scene: Option<PathBuf>,
    /// Output image: .png (tone-mapped sRGB) or .exr (linear float). Default: out.png and out.exr.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
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
}

#[derive(clap::ValueEnum, Clone, Copy, Debug)]
pub enum CullArg {
    None,
    Back,
}

#[derive(Subcommand, Debug)]
pub enum GoldenAction {
    /// Re-render every golden entry and compare (exit 1 if any differs).
    Check {
        /// Golden directory.
        #[arg(long, default_value = "golden")]
        dir: PathBuf,
    },
    /// Re-render and overwrite golden images (all, or the named entries). The only command that writes golden/.
    Bless {
        names: Vec<String>,
        #[arg(long, default_value = "golden")]
        dir: PathBuf,
    },
}

/// Runs the command line; `Ok(false)` means "ran, but the check failed" (exit 1).
pub fn run(cli: Cli) -> Result<bool> {
    match cli.command {
        Command::Render(args) => render_cmd(args).map(|_| true),
        Command::Golden { action } => golden_cmd(action),
    }
}

fn check_side(name: &str, v: u32) -> Result<u32> {
    if v == 0 || v > MAX_SIDE {
        return Err(Error::field(
            name,
            format!("{v} is out of range (1 to {MAX_SIDE} pixels)"),
        ));
    }
    Ok(v)
}

fn render_cmd(a: RenderArgs) -> Result<()> {
    let (mut file, base) = match &a.scene {
        Some(p) => (
            SceneFile::load(p)?,
            p.parent().map(Path::to_path_buf).unwrap_or_default(),
        ),
        None => (SceneFile::default(), PathBuf::from(".")),
    };
    if let Some(w) = a.width {
        file.render.width = check_side("--width", w)?;
    }
    if let Some(h) = a.height {
        file.render.height = check_side("--height", h)?;
    }
    if let Some(t) = a.threads {
        file.render.threads = t;
    }
    if let Some(t) = a.tile_size {
        file.render.tile_size = t;
    }
    if let Some(c) = a.cull {
        file.render.cull = match c {
            CullArg::None => Cull::None,
            CullArg::Back => Cull::Back,
        };
    }
    if let Some(e) = a.exposure {
        file.output.exposure = e;
    }
    if let Some(t) = a.tonemap {
        file.output.tonemap = t;
    }
    if let Some(m) = &a.mesh {
        // A mesh path given on the command line is relative to the working directory.
        file.mesh.source = m.clone();
    }
    let cli_mesh_base = a.mesh.is_some().then(|| PathBuf::from("."));
    let outputs: Vec<PathBuf> = match a.output.clone().or(file.output.path.clone()) {
        Some(p) => vec![p],
        None => vec![PathBuf::from("out.png"), PathBuf::from("out.exr")],
    };
    let formats = outputs
        .iter()
        .map(|p| image_io::format_of(p))
        .collect::<Result<Vec<_>>>()?;
    let scene = match &a.scene {
        Some(p) => Scene::resolve(&file, cli_mesh_base.as_deref().unwrap_or(&base)).map_err(
            |e| match e {
                Error::Field { .. } => Error::format(p, e.to_string()),
                other => other,
            },
        )?,
        None => Scene::resolve(&file, cli_mesh_base.as_deref().unwrap_or(&base))?,
    };
    let start = std::time::Instant::now();
    let img = render::render_with_threads(&scene, a.aov, scene.render.threads);
    let elapsed = start.elapsed();
    for (path, fmt) in outputs.iter().zip(formats) {
        match (fmt, a.aov) {
            (Format::Exr, _) => image_io::write_exr(path, &img)?,
            (Format::Png, None) => {
                image_io::write_png(path, &img, scene.output.exposure, scene.output.tonemap)?
            }
            (Format::Png, Some(aov)) => {
                image_io::write_png_bytes(path, img.width, img.height, aov::png_bytes(&img, aov))?
            }
        }
        eprintln!(
            "wrote {} ({}x{}, {:.1} ms)",
            path.display(),
            img.width,
            img.height,
            elapsed.as_secs_f64() * 1e3
        );
    }
    Ok(())
}

fn golden_cmd(action: GoldenAction) -> Result<bool> {
    match action {
        GoldenAction::Check { dir } => {
            let report = PathBuf::from("target/golden-failures");
            let outcomes = crate::golden::check(&dir, &report)?;
            let mut ok = true;
            for o in &outcomes {
                println!(
                    "{:<24} {}  max abs error {:.3e}  {}",
                    o.name,
                    if o.passed { "pass" } else { "FAIL" },
                    o.max_abs_error,
                    o.message
                );
                ok &= o.passed;
            }
            if !ok {
                println!(
                    "expected | difference | actual images and JSON reports: {}",
                    report.display()
                );
            }
            Ok(ok)
        }
        GoldenAction::Bless { names, dir } => {
            for p in crate::golden::bless(&dir, &names)? {
                println!("blessed {}", p.display());
            }
            Ok(true)
        }
    }
}
