//! The analytic test materials written as RGL files ([`super::writer`]): the files the
//! tests, `examples/write_rgl.rs` and the Mitsuba comparison (scripts/peer/render_rgl_peer.py)
//! use, each with the analytic RGB BRDF it came from.
//!
//! - `blinn-rgb`: isotropic, RGB: brdfkit's energy-normalised Blinn-Phong
//!   (`kd = 0.3/0.2/0.1`, `ks = 0.5`, exponent 20, the peer comparison's Blinn-Phong);
//! - `aniso-rgb`: anisotropic, RGB: Ashikhmin-Shirley (`nu = 8` along the tangent,
//!   `nv = 64` along the bitangent, `rs = 0.25`, `rd = 0.35/0.2/0.1`);
//! - `blinn-spectral`: isotropic, spectral (24 wavelengths, 370-830 nm): Blinn-Phong with
//!   a flat `ks = 0.4`, exponent 40, and a diffuse spectrum
//!   `kd(l) = 0.05 + 0.5 exp(-((l - 610 nm) / 50 nm)^2)` (orange); its RGB reference is the
//!   Blinn-Phong whose `kd` is that spectrum in linear sRGB ([`super::colour`]) at the
//!   file's wavelengths (the conversion is linear, and a flat spectrum stays grey).
//!
//! Each warp uses the lobe's own distribution mixed with 15% of a cosine distribution
//! `cos(theta)/pi`, so the table also resolves the diffuse part away from the lobe.

use super::colour::srgb_weights;
use super::writer::{tabulate, Layout};
use crate::brdf::{AshikhminShirley, BlinnPhong, Brdf};
use glam::{DVec3, Vec3};
use std::f64::consts::PI;

/// The names of the test materials.
pub const SAMPLE_NAMES: [&str; 3] = ["blinn-rgb", "aniso-rgb", "blinn-spectral"];

/// A test material: the file's bytes and the analytic RGB BRDF it tabulates.
pub struct Sample {
    pub bytes: Vec<u8>,
    pub source: Box<dyn Brdf>,
}

fn cosine(m: DVec3) -> f64 {
    m.z.max(0.0) / PI
}

fn blinn_ndf(n: f64) -> impl Fn(DVec3) -> f64 + Sync {
    move |m: DVec3| 0.85 * (n + 2.0) / (2.0 * PI) * m.z.max(0.0).powf(n) + 0.15 * cosine(m)
}

/// The diffuse spectrum of `blinn-spectral` at wavelength `l` (nm), module doc.
pub fn spectral_kd(l: f64) -> f64 {
    0.05 + 0.5 * (-((l - 610.0) / 50.0).powi(2)).exp()
}

/// The wavelengths of `blinn-spectral`: 370 to 830 nm in 20 nm steps.
pub fn spectral_wavelengths() -> Vec<f32> {
    (0..24).map(|k| 370.0 + 20.0 * k as f32).collect()
}

fn blinn_rgb() -> BlinnPhong {
    BlinnPhong {
        kd: Vec3::new(0.3, 0.2, 0.1),
        ks: Vec3::splat(0.5),
        exponent: 20.0,
    }
}

fn aniso() -> AshikhminShirley {
    AshikhminShirley {
        nu: 8.0,
        nv: 64.0,
        rs: Vec3::splat(0.25),
        rd: Vec3::new(0.35, 0.2, 0.1),
    }
}

const SPECTRAL_KS: f64 = 0.4;
const SPECTRAL_EXPONENT: f64 = 40.0;

/// The RGB Blinn-Phong the spectral material stands for (module doc): `kd` the diffuse
/// spectrum in linear sRGB, `ks` and the exponent those of the file.
pub fn spectral_reference() -> BlinnPhong {
    let waves = spectral_wavelengths();
    let weights = srgb_weights(&waves.iter().map(|&w| w as f64).collect::<Vec<_>>());
    let mut kd = DVec3::ZERO;
    for (w, c) in waves.iter().zip(&weights) {
        kd += DVec3::from(*c) * spectral_kd(*w as f64);
    }
    BlinnPhong {
        kd: kd.as_vec3(),
        ks: Vec3::splat(SPECTRAL_KS as f32),
        exponent: SPECTRAL_EXPONENT as f32,
    }
}

/// The analytic RGB BRDF of the test material `name` without writing its file, or `None`
/// for an unknown name.
pub fn source(name: &str) -> Option<Box<dyn Brdf>> {
    Some(match name {
        "blinn-rgb" => Box::new(blinn_rgb()),
        "aniso-rgb" => Box::new(aniso()),
        "blinn-spectral" => Box::new(spectral_reference()),
        _ => return None,
    })
}

/// The test material `name` (module doc), or `None` for an unknown name.
pub fn sample(name: &str) -> Option<Sample> {
    sample_in(name, false)
}

/// The test material `name` in about the smallest grids the reader accepts (2 polar nodes,
/// 3 azimuth nodes when anisotropic, 2 x 2 tables but a 3 x 3 `vndf`, 3 wavelengths when
/// spectral): files of about a kilobyte, the fuzz target's seeds (fuzz/README.md). `None`
/// for an unknown name.
pub fn tiny_sample(name: &str) -> Option<Sample> {
    sample_in(name, true)
}

fn sample_in(name: &str, tiny: bool) -> Option<Sample> {
    // A 2 x 2 vndf grid has no node inside the hemisphere (its density vanishes at the pole
    // and the horizon), so the tiny files' is 3 x 3.
    let (thetas, grid, vgrid, n) = if tiny {
        (2, (2, 2), (3, 3), 2)
    } else {
        (16, (8, 32), (32, 32), 32)
    };
    let iso = Layout {
        theta_i: Layout::thetas(thetas, 87.0),
        phi_i: vec![0.0],
        ndf_res: grid,
        vndf_res: vgrid,
        sample_res: n,
        wavelengths: None,
    };
    Some(match name {
        "blinn-rgb" => {
            let m = blinn_rgb();
            let f = move |l: DVec3, v: DVec3| m.eval_f64(l, v).to_array().to_vec();
            let desc = "brdfkit test material: Blinn-Phong kd 0.3/0.2/0.1, ks 0.5, n 20";
            Sample {
                bytes: tabulate(&iso, &blinn_ndf(20.0), &f, desc),
                source: Box::new(m),
            }
        }
        "aniso-rgb" => {
            let m = aniso();
            let (nu, nv) = (m.nu as f64, m.nv as f64);
            let ndf = move |h: DVec3| {
                let s2 = (1.0 - h.z * h.z).max(0.0);
                let e = if s2 > 0.0 {
                    (nu * h.x * h.x + nv * h.y * h.y) / s2
                } else {
                    0.0
                };
                let lobe = ((nu + 2.0) * (nv + 2.0)).sqrt() / (2.0 * PI) * h.z.max(0.0).powf(e);
                0.85 * lobe + 0.15 * cosine(h)
            };
            let f = move |l: DVec3, v: DVec3| m.eval_f64(l, v).to_array().to_vec();
            let layout = if tiny {
                Layout {
                    theta_i: Layout::thetas(2, 85.0),
                    phi_i: Layout::phis(3),
                    ..iso.clone()
                }
            } else {
                Layout {
                    theta_i: Layout::thetas(9, 85.0),
                    phi_i: Layout::phis(17),
                    ndf_res: (32, 32),
                    vndf_res: (32, 32),
                    sample_res: 32,
                    wavelengths: None,
                }
            };
            let desc = "brdfkit test material: Ashikhmin-Shirley nu 8, nv 64, rs 0.25";
            Sample {
                bytes: tabulate(&layout, &ndf, &f, desc),
                source: Box::new(m),
            }
        }
        "blinn-spectral" => {
            let waves = if tiny {
                vec![450.0, 550.0, 650.0]
            } else {
                spectral_wavelengths()
            };
            let (ks, n) = (SPECTRAL_KS, SPECTRAL_EXPONENT);
            let lobe = BlinnPhong {
                kd: Vec3::ZERO,
                ks: Vec3::splat(1.0),
                exponent: n as f32,
            };
            let w2 = waves.clone();
            let f = move |l: DVec3, v: DVec3| {
                let spec = ks * lobe.eval_f64(l, v).x;
                let d = if l.z > 0.0 && v.z > 0.0 {
                    1.0 / PI
                } else {
                    0.0
                };
                w2.iter()
                    .map(|&w| spectral_kd(w as f64) * d + spec)
                    .collect()
            };
            let layout = Layout {
                wavelengths: Some(waves),
                ..iso
            };
            let desc = "brdfkit test material: spectral Blinn-Phong, orange kd, ks 0.4, n 40";
            Sample {
                bytes: tabulate(&layout, &blinn_ndf(n), &f, desc),
                source: Box::new(spectral_reference()),
            }
        }
        _ => return None,
    })
}
