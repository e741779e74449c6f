//! `brdfkit render --shard I/N` of a still image and `brdfkit render --merge`: one image
//! rendered as N shards on N machines (an array job), then joined into the bits of the
//! unsharded render.
//!
//! A shard renders the bands of rows it owns ([`crate::shard::RowBands`]: band `b`, of
//! [`render::shard_rows`] rows, to shard `b % N`; the renderer leaves the other rows'
//! tiles unshaded, [`render::RenderOptions::rows`]) and writes them as a partial image
//! ([`crate::image_io::shard_part`]) that records the shard, the full size, the band height
//! and [`scene_key`], the hash of everything that decides the pixels. `--merge` reads every
//! part first and refuses, with one line naming the file, a part that is not one, of another
//! scene, size or band height, a shard given twice or one missing; only then does it write
//! the image (atomically, as every writer).
//!
//! A failed shard is resumed by running that shard's command again: the shards share
//! nothing while they run, and a part is written only once its rows are done.

use super::RenderArgs;
use crate::aov::Aov;
use crate::error::{Error, Result};
use crate::hash::{self, StableHasher};
use crate::image_io::shard_part::{self, Part, PartHeader};
use crate::image_io::{self, Format, Image, Tonemap};
use crate::render;
use crate::scene::{MaterialSpec, SceneFile};
use crate::shard::{RowBands, Shard};
use std::path::{Path, PathBuf};

/// A still image's shard, checked before the slow work: which rows, where, and the header
/// its part records.
pub(super) struct StillShard {
    pub bands: RowBands,
    header: PartHeader,
    output: PathBuf,
}

/// `render --shard I/N` without `--turntable`: the shard of the still image, after the
/// checks that need no render: CPU renderer, exactly one `.exr` output given with `-o`, at
/// most as many shards as bands. `file` is the scene file as it will be resolved (every
/// command-line option applied, the environment method made concrete), `base` the directory
/// its paths are relative to. `None` without `--shard` or with `--turntable`.
pub(super) fn plan(
    a: &RenderArgs,
    file: &SceneFile,
    base: &Path,
    outputs: &[PathBuf],
) -> Result<Option<StillShard>> {
    let (Some(spec), None) = (&a.shard, a.turntable) else {
        return Ok(None);
    };
    let shard = Shard::parse(spec)?;
    if a.device != super::device::Device::Cpu {
        return Err(Error::field(
            "--shard",
            "a still image is split on the CPU renderer only (--device cpu): the GPU renders a frame in one go",
        ));
    }
    let output = match (&a.output, outputs) {
        (Some(o), [_]) if image_io::format_of(o)? == Format::Exr => o.clone(),
        _ => {
            return Err(Error::field(
                "--shard",
                "a shard of a still image writes one partial image: give -o PART.exr (then `render --merge PART...` writes the PNG or EXR)",
            ))
        }
    };
    let (width, height) = (file.render.width, file.render.height);
    let bands = render::row_bands(file.render.tile_size, shard);
    let count = height.div_ceil(bands.rows) as usize;
    if shard.count > count {
        return Err(Error::field(
            "--shard",
            format!(
                "{shard}: the image's {height} rows make only {count} bands of {} rows (a whole number of tiles); use at most {count} shards",
                bands.rows
            ),
        ));
    }
    let aov = a.common.aov;
    let reference = a.reference && aov.is_none();
    let header = PartHeader {
        index: shard.index,
        count: shard.count,
        rows: bands.rows,
        width,
        height,
        scene: hash::tagged(scene_key(file, base, reference, aov)?),
        aov: aov.map_or_else(|| "none".to_string(), Aov::name),
        exposure: file.output.exposure,
        tonemap: tonemap_name(file.output.tonemap),
    };
    Ok(Some(StillShard {
        bands,
        header,
        output,
    }))
}

impl StillShard {
    /// Writes the shard's rows of `img` (the full-size image [`render::render`] returned
    /// with [`render::RenderOptions::rows`] set) as its partial image.
    pub(super) fn write(&self, img: &Image) -> Result<&Path> {
        let w = img.width as usize;
        let pixels: Vec<_> = (0..img.height)
            .filter(|&y| self.bands.owns(y))
            .flat_map(|y| &img.pixels[y as usize * w..(y as usize + 1) * w])
            .copied()
            .collect();
        shard_part::write_part(&self.output, &self.header, &pixels)?;
        Ok(&self.output)
    }

    /// The progress bar's label: `what` and the shard.
    pub(super) fn label(&self, what: &str) -> String {
        format!("{what}, shard {}", self.bands.shard)
    }
}

fn tonemap_name(t: Tonemap) -> String {
    use clap::ValueEnum;
    t.to_possible_value()
        .map(|v| v.get_name().to_string())
        .unwrap_or_default()
}

/// The hash ([`StableHasher`], XXH3-64) that ties a still image's shards to one render: a
/// tag, the crate version, the scene file as it will be resolved (its `Debug` text) with
/// what changes no pixel cleared (the thread count, the kernel instruction set, the output
/// path) and every input file named only by its file name, the bytes of those input files
/// (probe, light set, material, OBJ mesh, transfer table), and the render options that
/// change pixels (the converged reference, the AOV). So the shards of one command agree
/// wherever they run (another directory, another CPU), and a shard of another scene, size,
/// material, probe or option does not.
pub(super) fn scene_key(
    file: &SceneFile,
    base: &Path,
    reference: bool,
    aov: Option<Aov>,
) -> Result<u64> {
    let mut f = file.clone();
    f.render.threads = 0;
    f.render.kernel = crate::lanes::KernelPath::Auto;
    f.output.path = None;
    let mut inputs: Vec<PathBuf> = Vec::new();
    let mut take = |p: &mut PathBuf| {
        inputs.push(base.join(&*p));
        *p = p.file_name().map(PathBuf::from).unwrap_or_default();
    };
    if let Some(env) = f.env.as_mut() {
        take(&mut env.file);
        if let Some(l) = env.lights.as_mut() {
            take(l);
        }
    }
    match &mut f.material {
        MaterialSpec::ShFile { path, .. }
        | MaterialSpec::DbrdfFile { path }
        | MaterialSpec::MerlFile { path }
        | MaterialSpec::RglFile { path } => take(path),
        MaterialSpec::Lambert { .. }
        | MaterialSpec::BlinnPhong { .. }
        | MaterialSpec::Library { .. } => {}
    }
    if let Some(t) = f.transfer.as_mut() {
        take(&mut t.table);
    }
    if !matches!(f.mesh.source.as_str(), "teapot" | "sphere") {
        let mut p = PathBuf::from(&f.mesh.source);
        take(&mut p);
        f.mesh.source = p.to_string_lossy().into_owned();
    }
    let mut h = StableHasher::new();
    h.write(b"brdfkit-render-shard-v1");
    h.write_str(env!("CARGO_PKG_VERSION"));
    h.write_str(&format!("{f:?}"));
    h.write_u64(reference as u64);
    h.write_str(&aov.map_or_else(|| "none".to_string(), Aov::name));
    for p in inputs {
        let bytes = std::fs::read(&p).map_err(|e| Error::io(&p, "cannot read", e))?;
        h.write_u64(bytes.len() as u64);
        h.write(&bytes);
    }
    Ok(h.finish())
}

/// `render --merge PART...`: the parts read and checked (module doc), joined, written to
/// `-o` (default out.png and out.exr).
pub(super) fn merge(a: &RenderArgs) -> Result<()> {
    let outputs: Vec<PathBuf> = match &a.output {
        Some(p) => vec![p.clone()],
        None => vec![PathBuf::from("out.png"), PathBuf::from("out.exr")],
    };
    let flag = if a.output.is_some() {
        "--output"
    } else {
        "output path"
    };
    for p in &outputs {
        image_io::check_output(p, &["png", "exr"], flag)?;
    }
    let start = std::time::Instant::now();
    let parts = a
        .merge
        .iter()
        .map(|p| shard_part::read_part(p).map(|part| (p.as_path(), part)))
        .collect::<Result<Vec<_>>>()?;
    let img = join(&parts)?;
    let first = &parts[0].1.header;
    let aov = match first.aov.as_str() {
        "none" => None,
        name => Some(
            <Aov as clap::ValueEnum>::from_str(name, false).map_err(|_| {
                Error::format(
                    parts[0].0,
                    format!("brdfkit.shard.aov: unknown AOV {name:?}"),
                )
            })?,
        ),
    };
    let exposure = a.common.exposure.unwrap_or(first.exposure);
    let tonemap = match a.common.tonemap {
        Some(t) => t,
        None => <Tonemap as clap::ValueEnum>::from_str(&first.tonemap, false).map_err(|_| {
            Error::format(
                parts[0].0,
                format!(
                    "brdfkit.shard.tonemap: unknown tone map {:?}",
                    first.tonemap
                ),
            )
        })?,
    };
    for path in &outputs {
        match (image_io::format_of(path)?, aov) {
            (Format::Exr, _) => image_io::write_exr(path, &img)?,
            (Format::Png, None) => image_io::write_png(path, &img, exposure, tonemap)?,
            (Format::Png, Some(aov)) => image_io::write_png_bytes(
                path,
                img.width,
                img.height,
                crate::aov::png_bytes(&img, aov),
            )?,
        }
        eprintln!(
            "wrote {} ({}x{}, {} shards merged, {:.1} ms)",
            path.display(),
            img.width,
            img.height,
            parts.len(),
            start.elapsed().as_secs_f64() * 1e3
        );
    }
    Ok(())
}

/// The full image from `parts` (each with the path it was read from), after checking that
/// they are the N shards of one render, each once: the first part sets the size, N, band
/// height and scene (checked in that order: the scene hash covers the size too); a part that differs, repeats a shard or holds the wrong number of rows is an
/// error naming it, and a missing shard an error naming the shard.
pub(super) fn join(parts: &[(&Path, Part)]) -> Result<Image> {
    let Some((first_path, first)) = parts.first() else {
        return Err(Error::field("--merge", "no partial images given"));
    };
    let h0 = &first.header;
    let mut seen: Vec<Option<&Path>> = vec![None; h0.count];
    for (path, part) in parts {
        let h = &part.header;
        let other = |what: &str, this: String, theirs: String| {
            Err(Error::format(
                *path,
                format!(
                    "a shard of another {what} ({this}; {} has {theirs}): not merged",
                    first_path.display()
                ),
            ))
        };
        if (h.width, h.height) != (h0.width, h0.height) {
            return other(
                "size",
                format!("{}x{}", h.width, h.height),
                format!("{}x{}", h0.width, h0.height),
            );
        }
        if (h.count, h.rows) != (h0.count, h0.rows) {
            return other(
                "split",
                format!("{} shards of {}-row bands", h.count, h.rows),
                format!("{} shards of {}-row bands", h0.count, h0.rows),
            );
        }
        if h.scene != h0.scene {
            return other("scene", format!("scene {}", h.scene), h0.scene.clone());
        }
        if let Some(earlier) = seen[h.index] {
            return Err(Error::format(
                *path,
                format!(
                    "shard {}/{} given twice (also {}): not merged",
                    h.index,
                    h.count,
                    earlier.display()
                ),
            ));
        }
        seen[h.index] = Some(path);
        let bands = RowBands {
            shard: Shard {
                index: h.index,
                count: h.count,
            },
            rows: h.rows,
        };
        let want = bands.rows_owned(h.height) as usize * h.width as usize;
        if part.pixels.len() != want {
            return Err(Error::format(
                *path,
                format!(
                    "holds {} pixels, shard {}/{} of {}x{} owns {want}: not merged",
                    part.pixels.len(),
                    h.index,
                    h.count,
                    h.width,
                    h.height
                ),
            ));
        }
    }
    let missing: Vec<String> = (0..h0.count)
        .filter(|&i| seen[i].is_none())
        .map(|i| format!("{i}/{}", h0.count))
        .collect();
    if !missing.is_empty() {
        return Err(Error::field(
            "--merge",
            format!(
                "shard {} missing ({} of {} parts given): rerun `render --shard I/N` for it, then merge all {}",
                missing.join(", "),
                parts.len(),
                h0.count,
                h0.count
            ),
        ));
    }
    let mut by_shard: Vec<&Part> = vec![&parts[0].1; h0.count];
    for (_, part) in parts {
        by_shard[part.header.index] = part;
    }
    let (w, rows) = (h0.width as usize, h0.rows);
    let mut img = Image::new(h0.width, h0.height);
    let mut next_row = vec![0usize; h0.count];
    for y in 0..h0.height as usize {
        let s = (y as u32 / rows) as usize % h0.count;
        let r = next_row[s];
        next_row[s] += 1;
        img.pixels[y * w..(y + 1) * w].copy_from_slice(&by_shard[s].pixels[r * w..(r + 1) * w]);
    }
    Ok(img)
}
