//! Seeded GPU faults: the mistakes a GPU port of this method typically makes, injected on
//! purpose (the hidden option `brdfkit golden check --device gpu --gpu-fault NAME`) so that
//! tests can show the golden check fails on each (`tests/gpu/golden.rs`).
//!
//! Each is a bit the fragment shader tests (`shaders/conventions.wgsl`, `frame.wgsl`):
//! - `half-texel`: table texels taken to sit on their corners, not their centres (GL's
//!   `s nu - 1/2` of `GL_LINEAR` and the `floor(s nu)` of `GL_NEAREST` both shifted by half
//!   a texel);
//! - `no-cosine`: the `cos(polar_i)` of the lighting sum left out;
//! - `mirrored-azimuth`: a left-handed shading frame (`b = t x n`), so every azimuth becomes
//!   `2 pi - azimuth` (an anisotropic BRDF renders mirrored);
//! - `srgb-twice`: the shader encodes sRGB into a target the display path encodes again;
//! - `transfer-mirrored-azimuth`: the transfer table (`shaders/transfer.wgsl`) read at the
//!   probe azimuth `2 pi - a` of the normal (the probe direction taken as
//!   `(sin p sin a, cos p, sin p cos a)`, the sign of the convention's x dropped);
//! - `gain`: every pixel 0.5% too bright (a normalisation constant, a solid angle);
//! - `nearest-azimuth`: bilinear filtering replaced by nearest on the azimuth axis of the
//!   material tables;
//! - `diffuse-no-inv-pi`: the Lambert term `albedo / pi` written `albedo` (the Lambert model
//!   and the Lambert base of Lambert + D-BRDF, the other models keep theirs);
//! - `reflection-psi-sign`: the reflection table (`shaders/reflection.wgsl`) read at `-psi`:
//!   the normal's angle about the reflected direction measured from the chart's tangent
//!   `t` towards `t x r` instead of `b = r x t` (a port that crosses in the other order),
//!   which flips the sign of the series' `sin k psi` terms at every order `k` (the basis'
//!   recurrence carries the sign of `sin psi` up);
//!
//! And, applied to what is uploaded (src/gpu/upload.rs calls [`Faults::apply_to_uploads`]):
//! - `sh-sign`: one SH coefficient's sign flipped (`l = 5, m = -3`, in every texel and
//!   colour: data sets of 6 bands or more);
//! - `f16-tables`: the material table and the environment's table (transfer or reflection)
//!   stored as f16 (rounded to nearest);
//! - `last-light-dropped`: the last delta light of the set left out;
//! - `rotation-sign`: the environment table's probe rotation (transfer or reflection)
//!   applied with the wrong sign.
//!
//! A GPU port that prepares the probe itself would add the pole row's solid angle; this
//! build receives light sets and transfer tables from the CPU, so that mistake has no place
//! here (the CPU's samplers are held to the probe's exact power by their own tests).

use crate::error::{Error, Result};

/// A set of seeded faults (bit flags, as the shader reads them).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Faults(pub u32);

impl Faults {
    /// No fault: the correct renderer.
    pub const NONE: Faults = Faults(0);
    /// Every fault by name, with its shader bit.
    pub const ALL: [(&'static str, u32); 13] = [
        ("half-texel", 1),
        ("no-cosine", 2),
        ("mirrored-azimuth", 4),
        ("srgb-twice", 8),
        ("transfer-mirrored-azimuth", 16),
        ("gain", 32),
        ("nearest-azimuth", 64),
        ("diffuse-no-inv-pi", 128),
        ("sh-sign", 256),
        ("f16-tables", 512),
        ("last-light-dropped", 1024),
        ("rotation-sign", 2048),
        ("reflection-psi-sign", 4096),
    ];
    const SH_SIGN: u32 = 256;
    const F16_TABLES: u32 = 512;
    const LAST_LIGHT_DROPPED: u32 = 1024;
    const ROTATION_SIGN: u32 = 2048;

    /// The fault named `name` (one of [`Faults::ALL`]).
    pub fn parse(name: &str) -> Result<Faults> {
        Faults::ALL
            .iter()
            .find(|(n, _)| *n == name)
            .map(|&(_, bit)| Faults(bit))
            .ok_or_else(|| {
                let names: Vec<&str> = Faults::ALL.iter().map(|(n, _)| *n).collect();
                Error::field(
                    "--gpu-fault",
                    format!("'{name}' is not a seeded fault ({})", names.join(", ")),
                )
            })
    }
}

/// What [`Faults::apply_to_uploads`] may change before the upload.
pub struct UploadedTables<'a> {
    /// The material table (SH coefficients in the layout of [`crate::sh::dataset`], or a
    /// D-BRDF's `p(h)`), and the SH terms per colour (`bands^2`, 1 for other tables).
    pub material: &'a mut [f32],
    pub sh_terms: usize,
    pub material_is_sh: bool,
    /// The environment's table (the transfer or the reflection table's values; one zero
    /// without one) and its probe rotation (radians).
    pub env_table: &'a mut [f32],
    pub rotation: &'a mut f32,
    /// The number of delta lights the shader sums.
    pub light_count: &'a mut u32,
}

impl Faults {
    fn has(self, bit: u32) -> bool {
        self.0 & bit != 0
    }

    /// Applies the upload-side seeded faults (module doc) to `t`; none without a fault.
    pub fn apply_to_uploads(self, t: UploadedTables<'_>) {
        // l = 5, m = -3: index l^2 + l + m.
        const SH_SIGN_TERM: usize = 27;
        if self.has(Self::SH_SIGN) && t.material_is_sh && t.sh_terms > SH_SIGN_TERM {
            for block in t.material.chunks_exact_mut(t.sh_terms) {
                block[SH_SIGN_TERM] = -block[SH_SIGN_TERM];
            }
        }
        if self.has(Self::F16_TABLES) {
            for v in t.material.iter_mut().chain(t.env_table.iter_mut()) {
                *v = half::f16::from_f32(*v).to_f32();
            }
        }
        if self.has(Self::LAST_LIGHT_DROPPED) {
            *t.light_count = t.light_count.saturating_sub(1);
        }
        if self.has(Self::ROTATION_SIGN) {
            *t.rotation = -*t.rotation;
        }
    }
}
