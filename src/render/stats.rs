//! The work one render did ([`RenderStats`]), to show what was skipped
//! (`brdfkit render --stats`).

use crate::shade::ShadeCounts;

/// The work one render did, to show what was skipped (`brdfkit render --stats`). Counts are
/// gathered per tile (or per row for AOVs) and summed after, so they do not depend on the
/// thread count; the tile counts do depend on the tile size.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RenderStats {
    /// Tiles of the frame.
    pub tiles: u64,
    /// Work of the kernels' tile loop (all zero for an AOV render, the scalar oracle and
    /// the f64 path).
    pub shade: ShadeCounts,
    /// Directional lights in the scene (every light on the f64 path, which drops none),
    /// and how many were dropped as negligible.
    pub lights: usize,
    pub lights_dropped: usize,
    /// Dropped irradiance over total irradiance, largest over the channels (0 if none).
    pub dropped_fraction: f32,
    /// SH bands stored in the material's data set and bands shaded (0, 0 if not SH).
    pub sh_bands_stored: usize,
    pub sh_bands_used: usize,
    /// Pixels whose AOV value was computed (0 for a beauty render).
    pub aov_pixels: u64,
    /// Whether the rasterizer counted per-pixel coverage (only the `coverage` AOV needs it).
    pub coverage_counted: bool,
}

impl std::fmt::Display for RenderStats {
    /// One `name: value` line per counter.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let s = &self.shade;
        writeln!(f, "tiles: {}", self.tiles)?;
        writeln!(f, "tiles shaded: {}", s.tiles_shaded)?;
        writeln!(f, "tiles skipped (empty): {}", s.tiles_skipped)?;
        writeln!(f, "pixels shaded: {}", s.pixels_shaded)?;
        writeln!(f, "pixel x light pairs: {}", s.light_pairs)?;
        writeln!(
            f,
            "kernel lanes used: {} of {} ({:.1}%)",
            s.pairs_summed,
            s.lane_slots,
            100.0 * s.pairs_summed as f64 / s.lane_slots.max(1) as f64
        )?;
        writeln!(
            f,
            "lights: {} ({} dropped, {:.3e} of the irradiance)",
            self.lights, self.lights_dropped, self.dropped_fraction
        )?;
        writeln!(
            f,
            "pixels given the dropped lights back (per-pixel bound): {}",
            s.pixels_restored
        )?;
        writeln!(
            f,
            "sh bands: {} of {}",
            self.sh_bands_used, self.sh_bands_stored
        )?;
        writeln!(f, "aov pixels: {}", self.aov_pixels)?;
        write!(f, "coverage counted: {}", self.coverage_counted)
    }
}
