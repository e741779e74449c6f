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
//!   `(sin p sin a, cos p, sin p cos a)`, the sign of the convention's x dropped).

use crate::error::{Error, Result};

/// A set of seeded faults (bit flags, as the shader reads them).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Faults(pub u32);

impl Faults {
    /// No fault: the correct renderer.
    pub const NONE: Faults = Faults(0);
    /// Every fault by name, with its shader bit.
    pub const ALL: [(&'static str, u32); 5] = [
        ("half-texel", 1),
        ("no-cosine", 2),
        ("mirrored-azimuth", 4),
        ("srgb-twice", 8),
        ("transfer-mirrored-azimuth", 16),
    ];

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
