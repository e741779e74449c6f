//! The rasterizer's fast paths against a per-pixel reference: per-vertex snapping, block
//! classification by corners, binning into flat lists and buffers reused across frames
//! must leave the visibility buffer bit for bit what the plain algorithm gives.
//!
//! The reference here is that plain algorithm written out: every source triangle clipped
//! ([`ClipPlanes::clip_triangle`]) and set up from its clipped polygon
//! ([`setup::setup`], which snaps each triangle's own vertices), then every pixel of its
//! bounds tested by its edge functions evaluated from scratch, nearest 1/w kept (ties keep
//! the earlier triangle), no tiles, no blocks, no stepping. Random scenes at several tile
//! sizes include fans (shared edges), vertices on pixel centres, degenerate triangles,
//! huge triangles and triangles crossing the camera plane. Each seeded fault of the block
//! walk ([`raster::RasterFault`]) must make the comparison fail.

use brdfkit::lanes::KernelPath;
use brdfkit::raster::clip::{ClipPlanes, ClipVertex};
use brdfkit::raster::setup::{self, SetupTriangle};
use brdfkit::raster::{self, Cull, RasterConfig, RasterFault, RasterScratch, VisBuffer};
use glam::{Vec2, Vec4};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;

use super::watertight::{clip_of_screen, H, W};

fn cfg(tile: u32, cull: Cull) -> RasterConfig {
    RasterConfig {
        width: W,
        height: H,
        tile_size: tile,
        cull,
        near: 0.01,
        count_coverage: true,
        kernel: KernelPath::Auto,
    }
}

/// The reference's output, row-major: set-up triangles, per pixel the visible one (index
/// into them), its 1/w bits and the number of triangles covering it.
struct Reference {
    triangles: Vec<SetupTriangle>,
    visible: Vec<u32>,
    depth: Vec<u32>,
    coverage: Vec<u32>,
}

fn reference(clip: &[Vec4], tris: &[[u32; 3]], c: &RasterConfig) -> Reference {
    let planes = ClipPlanes::new(c.near, c.width, c.height);
    let mut triangles = Vec::new();
    let mut poly = Vec::new();
    for (source, tri) in tris.iter().enumerate() {
        let v = tri.map(|i| clip[i as usize]);
        let codes = v.map(|p| planes.outcode(p));
        if codes[0] & codes[1] & codes[2] != 0 {
            continue;
        }
        if codes[0] | codes[1] | codes[2] == 0 {
            poly.clear();
            poly.extend((0..3).map(|k| {
                let mut bary = [0.0; 3];
                bary[k] = 1.0;
                ClipVertex { clip: v[k], bary }
            }));
        } else {
            planes.clip_triangle(v, &mut poly);
        }
        for i in 1..poly.len().saturating_sub(1) {
            let cv = [poly[0], poly[i], poly[i + 1]];
            triangles.extend(setup::setup(
                cv,
                source as u32,
                c.width,
                c.height,
                c.cull == Cull::Back,
            ));
        }
    }
    let n = (c.width * c.height) as usize;
    let mut visible = vec![raster::NO_TRIANGLE; n];
    let mut depth = vec![0.0f32; n];
    let mut coverage = vec![0u32; n];
    for (ti, t) in triangles.iter().enumerate() {
        for py in t.py_min..=t.py_max {
            for px in t.px_min..=t.px_max {
                let e = t.edges_at(px, py);
                if (0..3).all(|k| e[k] + t.bias[k] > 0) {
                    let i = (py * c.width + px) as usize;
                    let [w0, w1, w2] = e.map(|v| v as f64);
                    let q = t.inv_w.map(|v| v as f64);
                    let z = ((w0 * q[0] + w1 * q[1] + w2 * q[2]) * (1.0 / t.area2 as f64)) as f32;
                    if z > depth[i] {
                        depth[i] = z;
                        visible[i] = ti as u32;
                    }
                    coverage[i] += 1;
                }
            }
        }
    }
    Reference {
        triangles,
        visible,
        depth: depth.iter().map(|d| d.to_bits()).collect(),
        coverage,
    }
}

/// Where `vis` differs from the reference, or `None`.
fn difference(vis: &VisBuffer, want: &Reference) -> Option<String> {
    if format!("{:?}", vis.triangles) != format!("{:?}", want.triangles) {
        return Some(format!(
            "set-up triangles differ ({} against {})",
            vis.triangles.len(),
            want.triangles.len()
        ));
    }
    let cov = vis.coverage_row_major();
    for y in 0..H {
        for x in 0..W {
            let (i, r) = (vis.index(x, y), (y * W + x) as usize);
            let got = (vis.visible[i], vis.depth[i].to_bits(), cov[r]);
            let exp = (want.visible[r], want.depth[r], want.coverage[r]);
            if got != exp {
                return Some(format!(
                    "pixel ({x},{y}): (visible, 1/w bits, coverage) {got:?}, reference {exp:?}"
                ));
            }
        }
    }
    None
}

/// A random scene of seed `seed`: clip positions and triangles.
fn scene(seed: u64) -> (Vec<Vec4>, Vec<[u32; 3]>) {
    let mut rng = Pcg64::seed_from_u64(seed);
    let mut clip = Vec::new();
    let mut tris = Vec::new();
    let point = |rng: &mut Pcg64, scale: f32| {
        let p = Vec2::new(
            rng.gen_range(-scale..W as f32 + scale),
            rng.gen_range(-scale..H as f32 + scale),
        );
        match rng.gen_range(0..4) {
            // On pixel centres and pixel edges: samples exactly on edges.
            0 => (p * 2.0).round() / 2.0,
            1 => p.floor() + Vec2::splat(0.5),
            _ => p,
        }
    };
    for _ in 0..rng.gen_range(5..40) {
        let kind = rng.gen_range(0..6);
        let base = clip.len() as u32;
        match kind {
            // A fan about a centre: every inner edge shared by two triangles.
            0 => {
                let c = point(&mut rng, 10.0);
                let r = rng.gen_range(1.0..60.0f32);
                let n = rng.gen_range(3..12u32);
                let w = rng.gen_range(0.5..5.0);
                clip.push(clip_of_screen(c, w));
                for k in 0..n {
                    let a = k as f32 / n as f32 * std::f32::consts::TAU + rng.gen_range(0.0..0.3);
                    let p = c + r * Vec2::new(a.cos(), a.sin());
                    clip.push(clip_of_screen(p, rng.gen_range(0.5..5.0)));
                }
                for k in 0..n {
                    tris.push([base, base + 1 + k, base + 1 + (k + 1) % n]);
                }
            }
            // Huge: far beyond the screen (clipped by the guard band).
            1 => {
                for _ in 0..3 {
                    let p = point(&mut rng, 30000.0);
                    clip.push(clip_of_screen(p, rng.gen_range(0.5..5.0)));
                }
                tris.push([base, base + 1, base + 2]);
            }
            // Crossing the camera plane (near clipping).
            2 => {
                for k in 0..3 {
                    let p = point(&mut rng, 50.0);
                    let w = if k == 0 {
                        rng.gen_range(-3.0..0.005)
                    } else {
                        rng.gen_range(0.2..4.0)
                    };
                    clip.push(clip_of_screen(p, w));
                }
                tris.push([base, base + 1, base + 2]);
            }
            // Degenerate: a repeated vertex or three collinear points.
            3 => {
                let a = point(&mut rng, 5.0);
                let b = point(&mut rng, 5.0);
                let t = rng.gen_range(0..3);
                let c = [a, b, (a + b) * 0.5][t];
                for p in [a, b, c] {
                    clip.push(clip_of_screen(p, rng.gen_range(0.5..5.0)));
                }
                tris.push([base, base + 1, base + 2]);
            }
            // Tiny (sub-pixel) to medium.
            _ => {
                let c = point(&mut rng, 10.0);
                let s = [0.3f32, 2.0, 9.0, 40.0][rng.gen_range(0..4)];
                for _ in 0..3 {
                    let p = c + Vec2::new(rng.gen_range(-s..s), rng.gen_range(-s..s));
                    clip.push(clip_of_screen(p, rng.gen_range(0.5..5.0)));
                }
                tris.push([base, base + 1, base + 2]);
            }
        }
    }
    (clip, tris)
}

const TILES: [u32; 7] = [1, 5, 8, 13, 16, 32, 128];

#[test]
fn blocks_match_the_per_pixel_reference() {
    // Buffers reused across every scene and size, as the viewer reuses them.
    let mut scratch = RasterScratch::default();
    let mut reused = VisBuffer::default();
    // The reused-buffer renders take each lane path this CPU runs in turn (the first
    // render takes `auto`): every path against the reference and against `auto`.
    let paths = crate::common::kernel_paths("blocks_match_the_per_pixel_reference");
    for seed in 0..300u64 {
        let (clip, tris) = scene(seed);
        let cull = if seed % 3 == 0 {
            Cull::Back
        } else {
            Cull::None
        };
        let c = cfg(TILES[seed as usize % TILES.len()], cull);
        let want = reference(&clip, &tris, &c);
        let vis = raster::rasterize(&clip, &tris, &c);
        if let Some(d) = difference(&vis, &want) {
            panic!("seed {seed}, tile {}: {d}", c.tile_size);
        }
        let c = RasterConfig {
            count_coverage: seed % 2 == 0,
            kernel: paths[seed as usize % paths.len()],
            ..c
        };
        raster::rasterize_into(&clip, &tris, &c, &mut scratch, &mut reused);
        let path = c.kernel.name();
        assert_eq!(
            reused.visible, vis.visible,
            "seed {seed}, {path}: reused buffers"
        );
        assert_eq!(
            reused.depth, vis.depth,
            "seed {seed}, {path}: reused buffers"
        );
        assert_eq!(reused.coverage.is_some(), c.count_coverage);
        assert_eq!(reused.tile_occupied, vis.tile_occupied);
    }
}

#[test]
fn one_thread_gives_the_same_bits() {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    for seed in 0..20u64 {
        let (clip, tris) = scene(1000 + seed);
        let c = cfg(TILES[seed as usize % TILES.len()], Cull::None);
        let many = raster::rasterize(&clip, &tris, &c);
        let one = pool.install(|| raster::rasterize(&clip, &tris, &c));
        assert_eq!(one.visible, many.visible, "seed {seed}");
        assert_eq!(one.depth, many.depth, "seed {seed}");
    }
}

#[test]
fn seeded_block_faults_fail_the_comparison() {
    for fault in [
        RasterFault::PartialBlockAccepted,
        RasterFault::LastBlockColumnSkipped,
        RasterFault::LaneTailSkipped,
        RasterFault::EdgeOriginWrong,
        RasterFault::OnePixelUntested,
    ] {
        let caught = (0..300u64).find(|&seed| {
            let (clip, tris) = scene(seed);
            let c = cfg(TILES[seed as usize % TILES.len()], Cull::None);
            let vis = raster::rasterize_with_fault(&clip, &tris, &c, fault);
            difference(&vis, &reference(&clip, &tris, &c)).is_some()
        });
        assert!(caught.is_some(), "{fault:?} passes the comparison");
        println!("{fault:?}: caught at seed {}", caught.unwrap());
    }
}
