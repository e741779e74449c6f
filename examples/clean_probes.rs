//! Makes the shipped light probes (`assets/probes/{city,studio,sky}.exr`) from the original
//! Poly Haven files: each original (DWAB, lossy) is loaded through the project's own loader
//! ([`Probe::load`]: every negative texel's mass moved into nearby positive texels,
//! `src/env/probe/clean.rs`) and the cleaned radiance is written as a lossless OpenEXR,
//! f32 RGB, ZIP compression (16 scan lines a block). Loading the new file gives exactly the
//! f32 texels the loader made from the original (checked here, bit for bit), so every
//! render, golden image and light set keeps its bits, and the loader finds no negative
//! texel left to clean.
//!
//! ```text
//! cargo run --release --example clean_probes -- [SOURCE_DIR [OUT_DIR]]
//! ```
//!
//! SOURCE_DIR holds the originals `city.exr`, `studio.exr` and `sky.exr` (default
//! `../shared/envmaps`, the shared set; the originals are also in the repository's history
//! before the cleaning, see `assets/probes/README.md`). OUT_DIR defaults to
//! `assets/probes`; each file is written whole or not at all (a temporary file beside it,
//! renamed). Prints per probe: the texels with a negative channel, the texels the cleaning
//! changed (those and the positive neighbours that took their mass), the luminance power
//! moved (W/m^2 and % of the probe's signed power, as the loader's warning states it), the
//! cleaned probe's largest channel value and max / median luminance, and the sizes of the
//! original and of the new file under ZIP and PIZ.
//!
//! Why ZIP: both ZIP and PIZ are lossless for f32, and on these three probes ZIP is 2-10%
//! smaller (the table in `assets/probes/README.md`). DWAB, PXR24 and B44 are lossy for
//! f32 and would bring back what the cleaning removed; f16 would round the texels the
//! cleaning scaled.

use brdfkit::env::{LoadOptions, Probe};
use exr::prelude::*;
use std::io::Write;
use std::path::{Path, PathBuf};

/// The shipped probes, by file name.
const PROBES: [&str; 3] = ["city.exr", "studio.exr", "sky.exr"];

/// The raw (uncleaned) texels of an OpenEXR file as its decoder gives them, row 0 first.
fn raw_texels(path: &Path) -> Vec<[f32; 3]> {
    let image = read_first_rgba_layer_from_file(
        path,
        |res, _| (res.width(), vec![[0.0f32; 3]; res.width() * res.height()]),
        |(w, px): &mut (usize, Vec<[f32; 3]>), pos, (r, g, b, _a): (f32, f32, f32, f32)| {
            px[pos.y() * *w + pos.x()] = [r, g, b];
        },
    )
    .unwrap_or_else(|e| panic!("{}: cannot decode: {e}", path.display()));
    image.layer_data.channel_data.pixels.1
}

/// `probe`'s texels encoded as a one-layer f32 RGB OpenEXR with `compression`, scan lines
/// top to bottom.
fn encode(probe: &Probe, compression: Compression) -> Vec<u8> {
    let (w, h) = (probe.width(), probe.height());
    let channels = SpecificChannels::rgb(|pos: Vec2<usize>| {
        let t = probe.texel(pos.y(), pos.x());
        (t[0], t[1], t[2])
    });
    let encoding = Encoding {
        compression,
        blocks: Blocks::ScanLines,
        line_order: LineOrder::Increasing,
    };
    let mut bytes = std::io::Cursor::new(Vec::new());
    Image::from_encoded_channels((w, h), encoding, channels)
        .write()
        .to_buffered(&mut bytes)
        .expect("encoding into memory");
    bytes.into_inner()
}

/// Writes `bytes` to `path` whole: a temporary file in its directory, renamed over it.
fn write_whole(path: &Path, bytes: &[u8]) {
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut tmp = tempfile::NamedTempFile::new_in(dir)
        .unwrap_or_else(|e| panic!("{}: cannot create a file there: {e}", dir.display()));
    // Readable by everyone, as a checked-out file (a temporary file starts private).
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        tmp.as_file()
            .set_permissions(std::fs::Permissions::from_mode(0o644))
            .unwrap_or_else(|e| panic!("{}: cannot set permissions: {e}", path.display()));
    }
    tmp.write_all(bytes)
        .and_then(|_| tmp.as_file().sync_all())
        .unwrap_or_else(|e| panic!("{}: cannot write: {e}", path.display()));
    tmp.persist(path)
        .unwrap_or_else(|e| panic!("{}: cannot write: {e}", path.display()));
}

fn main() {
    let args: Vec<PathBuf> = std::env::args_os().skip(1).map(PathBuf::from).collect();
    let source = args
        .first()
        .cloned()
        .unwrap_or_else(|| PathBuf::from("../shared/envmaps"));
    let out = args
        .get(1)
        .cloned()
        .unwrap_or_else(|| PathBuf::from("assets/probes"));
    let opts = LoadOptions::default();
    println!(
        "| file | negative texels | texels changed | luminance power moved | max value | max / median luminance | original | ZIP f32 (written) | PIZ f32 |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    for name in PROBES {
        let src = source.join(name);
        let original = std::fs::read(&src)
            .unwrap_or_else(|e| panic!("{}: cannot read the original: {e}", src.display()));
        let (probe, report) = Probe::load(&src, &opts).unwrap_or_else(|e| panic!("{e}"));
        let raw = raw_texels(&src);
        let changed = raw
            .iter()
            .zip(probe.texels())
            .filter(|(a, b)| a.map(f32::to_bits) != b.map(f32::to_bits))
            .count();
        let (moved, total) = report.luminance_power_moved();
        let zip = encode(&probe, Compression::ZIP16);
        let piz = encode(&probe, Compression::PIZ);
        let dst = out.join(name);
        write_whole(&dst, &zip);
        // The written file loads to the same bits and is clean.
        let (again, again_report) = Probe::load(&dst, &opts).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(again_report.negative_texels, 0, "{name}: negatives left");
        assert!(
            again
                .texels()
                .iter()
                .zip(probe.texels())
                .all(|(a, b)| a.map(f32::to_bits) == b.map(f32::to_bits)),
            "{name}: the written file does not load to the cleaned texels"
        );
        let max = probe
            .texels()
            .iter()
            .flatten()
            .fold(0.0f32, |m, &c| m.max(c));
        let mut lum: Vec<f64> = probe
            .texels()
            .iter()
            .map(|&t| brdfkit::env::luminance(t))
            .collect();
        lum.sort_by(f64::total_cmp);
        let ratio = lum[lum.len() - 1] / lum[lum.len() / 2];
        println!(
            "| {name} | {} | {changed} | {moved:.4e} W/m^2 ({:.3}% of {total:.4e}) | {max:.4} | {ratio:.3e} | {} B | {} B | {} B |",
            report.negative_texels,
            100.0 * moved / total,
            original.len(),
            zip.len(),
            piz.len()
        );
    }
}
