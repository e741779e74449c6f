//! Watertightness of the rasterizer: every pixel of a closed or tiled surface is covered
//! exactly once, and single-triangle coverage equals a brute-force 128-bit edge-function
//! reference with an independently written top-left rule. Seeds are printed on failure.
//!
//! (Past 400 lines because every test checks one property, coverage exactly once, with the
//! brute-force reference and the mesh generators defined here; split, each file would
//! repeat them.)

use brdfkit::lanes::KernelPath;
use brdfkit::raster::{self, setup, Cull, RasterConfig};
use brdfkit::scene::camera::Camera;
use glam::{Mat4, Vec2, Vec3, Vec4};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;

/// The frame of these tests and of `raster_blocks.rs`, in pixels.
pub(crate) const W: u32 = 96;
pub(crate) const H: u32 = 80;

fn cfg(count: bool, tile: u32) -> RasterConfig {
    RasterConfig {
        width: W,
        height: H,
        tile_size: tile,
        cull: Cull::None,
        near: 0.01,
        count_coverage: count,
        kernel: KernelPath::Auto,
    }
}

/// Clip-space point for a screen position (pixels, y down) at view depth `w` (negative:
/// behind the camera), in the `W x H` frame of these tests and of `raster_blocks.rs`.
pub(crate) fn clip_of_screen(p: Vec2, w: f32) -> Vec4 {
    let ndc_x = p.x / W as f32 * 2.0 - 1.0;
    let ndc_y = 1.0 - p.y / H as f32 * 2.0;
    Vec4::new(ndc_x * w, ndc_y * w, 0.01, w)
}

/// Checks a coverage image against an `inside(x, y)` predicate evaluated at pixel centres:
/// every count is 0 or 1; a pixel whose centre and 8 neighbours (1 px away) are all inside
/// has exactly 1; all outside, exactly 0.
fn check_exactly_once(cov: &[u32], inside: impl Fn(f32, f32) -> bool, what: &str) {
    let mut interior = 0;
    for y in 0..H {
        for x in 0..W {
            let c = cov[(y * W + x) as usize];
            assert!(c <= 1, "{what}: pixel ({x},{y}) covered {c} times");
            let (cx, cy) = (x as f32 + 0.5, y as f32 + 0.5);
            let mut all_in = true;
            let mut all_out = true;
            for dy in [-1.0, 0.0, 1.0] {
                for dx in [-1.0, 0.0, 1.0] {
                    let i = inside(cx + dx, cy + dy);
                    all_in &= i;
                    all_out &= !i;
                }
            }
            if all_in {
                interior += 1;
                assert_eq!(c, 1, "{what}: hole at interior pixel ({x},{y})");
            }
            if all_out {
                assert_eq!(c, 0, "{what}: pixel ({x},{y}) covered outside the shape");
            }
        }
    }
    assert!(interior > 0, "{what}: test shape has no interior pixels");
}

fn inside_convex(poly: &[Vec2], p: Vec2) -> bool {
    let n = poly.len();
    let sign = |i: usize| {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        (b - a).perp_dot(p - a)
    };
    let s0 = sign(0);
    (0..n).all(|i| sign(i) * s0 > 0.0)
}

#[test]
fn random_fans_cover_once() {
    for seed in 0..200u64 {
        let mut rng = Pcg64::seed_from_u64(seed);
        let c = Vec2::new(
            rng.gen_range(10.0..W as f32 - 10.0),
            rng.gen_range(10.0..H as f32 - 10.0),
        );
        let n = rng.gen_range(3..24);
        let mut angles: Vec<f32> = (0..n)
            .map(|_| rng.gen_range(0.0..std::f32::consts::TAU))
            .collect();
        angles.sort_by(f32::total_cmp);
        angles.dedup_by(|a, b| (*a - *b).abs() < 1e-3);
        if angles.len() < 3
            || angles.windows(2).any(|w| w[1] - w[0] > 3.0)
            || angles[0] + std::f32::consts::TAU - angles[angles.len() - 1] > 3.0
        {
            continue; // centre must stay strictly inside the polygon
        }
        let (rx, ry) = (rng.gen_range(5.0..60.0), rng.gen_range(5.0..60.0));
        let outer: Vec<Vec2> = angles
            .iter()
            .map(|a| c + Vec2::new(a.cos() * rx, a.sin() * ry))
            .collect();
        // Random w per vertex: projection is involved, positions on screen are the same.
        let mut clip = vec![clip_of_screen(c, rng.gen_range(0.05..50.0))];
        clip.extend(
            outer
                .iter()
                .map(|&p| clip_of_screen(p, rng.gen_range(0.05..50.0))),
        );
        let m = outer.len() as u32;
        let tris: Vec<[u32; 3]> = (0..m).map(|i| [0, 1 + i, 1 + (i + 1) % m]).collect();
        let tile = [8, 16, 32][seed as usize % 3];
        let vis = raster::rasterize(&clip, &tris, &cfg(true, tile));
        check_exactly_once(
            &vis.coverage_row_major(),
            |x, y| inside_convex(&outer, Vec2::new(x, y)),
            &format!("fan seed {seed}"),
        );
    }
}

#[test]
fn rotated_quad_grids_cover_once() {
    for seed in 0..100u64 {
        let mut rng = Pcg64::seed_from_u64(1000 + seed);
        let (nx, ny) = (rng.gen_range(1..12), rng.gen_range(1..12));
        let cell = rng.gen_range(1.5..9.0f32);
        let angle = rng.gen_range(0.0..std::f32::consts::TAU);
        let (s, co) = angle.sin_cos();
        // The grid's centre lands on screen; its corners may leave it.
        let centre = Vec2::new(rng.gen_range(0.0..W as f32), rng.gen_range(0.0..H as f32));
        let (hx, hy) = (nx as f32 / 2.0, ny as f32 / 2.0);
        let to_screen = |i: f32, j: f32| {
            centre + Vec2::new(co * (i - hx) - s * (j - hy), s * (i - hx) + co * (j - hy)) * cell
        };
        let mut clip = Vec::new();
        for j in 0..=ny {
            for i in 0..=nx {
                clip.push(clip_of_screen(
                    to_screen(i as f32, j as f32),
                    rng.gen_range(0.05..50.0),
                ));
            }
        }
        let idx = |i: u32, j: u32| j * (nx + 1) + i;
        let mut tris = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                // Alternate the diagonal so both orientations of shared edges occur.
                if (i + j) % 2 == 0 {
                    tris.push([idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)]);
                    tris.push([idx(i, j), idx(i + 1, j + 1), idx(i, j + 1)]);
                } else {
                    tris.push([idx(i, j), idx(i + 1, j), idx(i, j + 1)]);
                    tris.push([idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)]);
                }
            }
        }
        let rect = [
            to_screen(0.0, 0.0),
            to_screen(nx as f32, 0.0),
            to_screen(nx as f32, ny as f32),
            to_screen(0.0, ny as f32),
        ];
        let vis = raster::rasterize(&clip, &tris, &cfg(true, [8, 13, 32][seed as usize % 3]));
        let cov = vis.coverage_row_major();
        if nx * ny < 6 || cell * (nx.min(ny) as f32) < 4.0 {
            // Too small for an interior: still no double hits.
            assert!(cov.iter().all(|&c| c <= 1), "grid seed {}", 1000 + seed);
            continue;
        }
        check_exactly_once(
            &cov,
            |x, y| inside_convex(&rect, Vec2::new(x, y)),
            &format!("grid seed {}", 1000 + seed),
        );
    }
}

/// A planar disc fan in 3D placed so that it often crosses the camera plane: the clipped
/// coverage must still be exactly once inside the visible part, found by ray casting.
#[test]
fn fans_crossing_the_camera_plane_cover_once() {
    let aspect = W as f32 / H as f32;
    let cam = Camera {
        position: Vec3::ZERO,
        target: Vec3::NEG_Z,
        up: Vec3::Y,
        fov_y_deg: 60.0,
        near: 0.05,
    };
    let clip_from_world = cam.clip_from_view(aspect) * cam.view_from_world();
    let tan_half = (30.0f32).to_radians().tan();
    for seed in 0..150u64 {
        let mut rng = Pcg64::seed_from_u64(5000 + seed);
        let centre = Vec3::new(
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-3.0..0.5),
        );
        let normal = Vec3::new(
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
        )
        .normalize();
        let u = normal.any_orthonormal_vector();
        let v = normal.cross(u);
        let radius = rng.gen_range(0.5..4.0);
        let n = rng.gen_range(5..20);
        let outer: Vec<Vec3> = (0..n)
            .map(|k| {
                let a = std::f32::consts::TAU * k as f32 / n as f32;
                centre + (u * a.cos() + v * a.sin()) * radius
            })
            .collect();
        let mut world = vec![centre];
        world.extend(&outer);
        let clip: Vec<Vec4> = world
            .iter()
            .map(|p| clip_from_world * p.extend(1.0))
            .collect();
        let tris: Vec<[u32; 3]> = (0..n as u32)
            .map(|i| [0, 1 + i, 1 + (i + 1) % n as u32])
            .collect();
        let mut c = cfg(true, 16);
        c.near = cam.near;
        let vis = raster::rasterize(&clip, &tris, &c);
        // Ray cast: camera at origin looking down -z; pixel centre to a view ray.
        let inside = |x: f32, y: f32| {
            let d = Vec3::new(
                (x / W as f32 * 2.0 - 1.0) * tan_half * aspect,
                (1.0 - y / H as f32 * 2.0) * tan_half,
                -1.0,
            );
            let denom = d.dot(normal);
            if denom.abs() < 1e-6 {
                return false;
            }
            let t = centre.dot(normal) / denom;
            // View depth along -z is t (d.z = -1); keep a margin off the near plane.
            // Written so that a NaN depth is rejected.
            #[allow(clippy::neg_cmp_op_on_partial_ord)]
            let too_near = !(t > cam.near * 1.01);
            if too_near {
                return false;
            }
            let p = d * t - centre;
            let q = Vec2::new(p.dot(u), p.dot(v));
            let poly: Vec<Vec2> = (0..n)
                .map(|k| {
                    let a = std::f32::consts::TAU * k as f32 / n as f32;
                    Vec2::new(a.cos(), a.sin()) * radius
                })
                .collect();
            inside_convex(&poly, q)
        };
        let cov = vis.coverage_row_major();
        let any_inside = (0..H).any(|y| (0..W).any(|x| inside(x as f32 + 0.5, y as f32 + 0.5)));
        if !any_inside {
            assert!(
                cov.iter().all(|&c| c == 0),
                "seed {}: coverage where nothing is visible",
                5000 + seed
            );
            continue;
        }
        for y in 0..H {
            for x in 0..W {
                let cnt = cov[(y * W + x) as usize];
                assert!(
                    cnt <= 1,
                    "seed {}: pixel ({x},{y}) covered {cnt} times",
                    5000 + seed
                );
                let (cx, cy) = (x as f32 + 0.5, y as f32 + 0.5);
                let nb: Vec<bool> = [-1.0, 0.0, 1.0]
                    .iter()
                    .flat_map(|&dy| [-1.0, 0.0, 1.0].map(|dx| inside(cx + dx, cy + dy)))
                    .collect();
                if nb.iter().all(|&b| b) {
                    assert_eq!(cnt, 1, "seed {}: hole at ({x},{y})", 5000 + seed);
                }
                if nb.iter().all(|&b| !b) {
                    assert_eq!(cnt, 0, "seed {}: stray coverage at ({x},{y})", 5000 + seed);
                }
            }
        }
    }
}

/// Independent reference: 128-bit edge functions at every pixel centre, with the top-left
/// rule written from its definition (an edge is top if horizontal with the triangle below,
/// left if the triangle lies to its right), without incremental stepping or binning.
fn reference_mask(x: [i64; 3], y: [i64; 3]) -> Vec<bool> {
    let e = |i: usize, j: usize, px: i128, py: i128| -> i128 {
        (x[j] as i128 - x[i] as i128) * (py - y[i] as i128)
            - (y[j] as i128 - y[i] as i128) * (px - x[i] as i128)
    };
    let area = e(0, 1, x[2] as i128, y[2] as i128);
    let mut mask = vec![false; (W * H) as usize];
    if area == 0 {
        return mask;
    }
    // Order the vertices so the interior is on the positive side of each edge.
    let order: [usize; 3] = if area > 0 { [0, 1, 2] } else { [0, 2, 1] };
    let edges = [
        (order[0], order[1]),
        (order[1], order[2]),
        (order[2], order[0]),
    ];
    let owns = |(i, j): (usize, usize)| {
        let third = 3 - i - j;
        let (dx, dy) = (x[j] - x[i], y[j] - y[i]);
        if dy == 0 {
            // Horizontal: top edge if the third vertex is below it (larger y, y down).
            y[third] > y[i] && dx != 0
        } else {
            // Left edge: the third vertex is to its right at the same height.
            let t_y = y[third];
            let x_at = x[i] as f64 + (t_y - y[i]) as f64 * dx as f64 / dy as f64;
            (x[third] as f64) > x_at
        }
    };
    for py in 0..H {
        for px in 0..W {
            let sx = px as i128 * 256 + 128;
            let sy = py as i128 * 256 + 128;
            mask[(py * W + px) as usize] = edges.iter().all(|&(i, j)| {
                let v = e(i, j, sx, sy);
                v > 0 || (v == 0 && owns((i, j)))
            });
        }
    }
    mask
}

#[test]
fn random_triangles_match_brute_force_reference() {
    for seed in 0..400u64 {
        let mut rng = Pcg64::seed_from_u64(9000 + seed);
        let scale = [2.0, 8.0, 40.0, 200.0][seed as usize % 4];
        let base = Vec2::new(
            rng.gen_range(-20.0..W as f32 + 20.0),
            rng.gen_range(-20.0..H as f32 + 20.0),
        );
        let mut pts: Vec<Vec2> = (0..3)
            .map(|_| base + Vec2::new(rng.gen_range(-scale..scale), rng.gen_range(-scale..scale)))
            .collect();
        if seed % 7 == 0 {
            // Snap to pixel centres and edges so on-edge samples occur often.
            for p in &mut pts {
                *p = (*p * 2.0).round() / 2.0;
            }
        }
        let clip: Vec<Vec4> = pts
            .iter()
            .map(|&p| clip_of_screen(p, rng.gen_range(0.1..20.0)))
            .collect();
        let vis = raster::rasterize(
            &clip,
            &[[0, 1, 2]],
            &cfg(true, [7, 16, 64][seed as usize % 3]),
        );
        let snapped: Vec<(i64, i64)> = clip.iter().map(|&c| setup::snap(c, W, H)).collect();
        let want = reference_mask(
            snapped
                .iter()
                .map(|p| p.0)
                .collect::<Vec<_>>()
                .try_into()
                .unwrap(),
            snapped
                .iter()
                .map(|p| p.1)
                .collect::<Vec<_>>()
                .try_into()
                .unwrap(),
        );
        let got: Vec<bool> = vis.coverage_row_major().iter().map(|&c| c == 1).collect();
        if got != want {
            let first = got.iter().zip(&want).position(|(a, b)| a != b).unwrap();
            panic!(
                "seed {}: coverage differs from reference first at pixel ({}, {}); vertices {:?}",
                9000 + seed,
                first as u32 % W,
                first as u32 / W,
                snapped
            );
        }
    }
}

fn culled_counts(mesh: &brdfkit::mesh::Mesh, view_from: Vec3) -> Vec<u32> {
    let b = mesh.bounds();
    let r = mesh.radius_about(b.center());
    let cam = Camera {
        position: b.center() + view_from.normalize() * r * 3.0,
        target: b.center(),
        up: Vec3::Y,
        fov_y_deg: 45.0,
        near: r * 0.01,
    };
    let m: Mat4 = cam.clip_from_view(W as f32 / H as f32) * cam.view_from_world();
    let clip: Vec<Vec4> = mesh.positions.iter().map(|p| m * p.extend(1.0)).collect();
    let mut c = cfg(true, 16);
    c.cull = Cull::Back;
    c.near = cam.near;
    raster::rasterize(&clip, &mesh.triangles, &c).coverage_row_major()
}

#[test]
fn culled_sphere_is_covered_at_most_once_without_holes() {
    let sphere = brdfkit::mesh::sphere::uv_sphere(24);
    let mut rng = Pcg64::seed_from_u64(77);
    for k in 0..12 {
        let dir = if k < 2 {
            Vec3::Y * if k == 0 { 1.0 } else { -1.0 }
        } else {
            Vec3::new(
                rng.gen_range(-1.0..1.0),
                rng.gen_range(-1.0..1.0),
                rng.gen_range(-1.0..1.0),
            )
        };
        let cov = culled_counts(&sphere, dir);
        assert!(
            cov.iter().all(|&c| c <= 1),
            "view {k}: double coverage on a closed sphere"
        );
        // The silhouette is convex: no hole strictly inside the covered region's rows.
        for y in 0..H {
            let row = &cov[(y * W) as usize..((y + 1) * W) as usize];
            if let (Some(a), Some(b)) = (
                row.iter().position(|&c| c == 1),
                row.iter().rposition(|&c| c == 1),
            ) {
                assert!(
                    row[a..=b].iter().all(|&c| c == 1),
                    "view {k}: hole in row {y}"
                );
            }
        }
    }
}

#[test]
fn culled_teapot_counts_match_reference() {
    // The teapot is not closed and its spout and handle pierce the body, so two front
    // faces may legitimately overlap. Its counts must equal the per-triangle reference
    // sum exactly (no double hits on shared edges, no holes). The overlaps (spout and
    // handle roots, lid over the rim lip, knob) are about 7% of the covered pixels from
    // this view; a seam double hit along every patch edge would add far more.
    let teapot = brdfkit::mesh::teapot::teapot(6);
    let dir = Vec3::new(0.3, 0.5, 1.0);
    let cov = culled_counts(&teapot, dir);
    let b = teapot.bounds();
    let r = teapot.radius_about(b.center());
    let cam = Camera {
        position: b.center() + dir.normalize() * r * 3.0,
        target: b.center(),
        up: Vec3::Y,
        fov_y_deg: 45.0,
        near: r * 0.01,
    };
    let m = cam.clip_from_view(W as f32 / H as f32) * cam.view_from_world();
    let clip: Vec<Vec4> = teapot.positions.iter().map(|p| m * p.extend(1.0)).collect();
    let mut want = vec![0u32; (W * H) as usize];
    for t in &teapot.triangles {
        let s = t.map(|i| setup::snap(clip[i as usize], W, H));
        let x = s.map(|p| p.0);
        let y = s.map(|p| p.1);
        let area = (x[1] - x[0]) * (y[2] - y[0]) - (y[1] - y[0]) * (x[2] - x[0]);
        if area >= 0 {
            continue; // back facing (clockwise on screen) or degenerate
        }
        for (i, on) in reference_mask(x, y).into_iter().enumerate() {
            want[i] += on as u32;
        }
    }
    assert_eq!(cov, want);
    let ones = cov.iter().filter(|&&c| c == 1).count();
    let more = cov.iter().filter(|&&c| c > 1).count();
    assert!(
        ones > 1000 && more * 10 < ones,
        "{ones} pixels covered once, {more} more than once"
    );
}
