//! Work counters of the tile loop.
//!
//! Design rule: integers gathered per tile and summed after, so the totals do not depend
//! on the thread count or the order of the sum; tests read them to see each skip
//! (tests/integration/skips.rs), the command line reports them.

/// Work done by the kernels' tile loop in one [`super::shade`] call, gathered per tile and summed after
/// (integers: the totals do not depend on the thread count or the order of the sum).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ShadeCounts {
    /// Tiles with at least one triangle, shaded.
    pub tiles_shaded: u64,
    /// Tiles no triangle touched, skipped without looking at a pixel.
    pub tiles_skipped: u64,
    /// Pixels shaded (visible surface).
    pub pixels_shaded: u64,
    /// (pixel x light) pairs handed to the kernel: per tile, its pixels times the live
    /// lights of the chunks its normal cone keeps plus the point lights.
    pub light_pairs: u64,
    /// Pixels that got the dropped lights back because leaving them out could change more
    /// than `render.drop_lights` of their value ([`crate::kernel::skip::needs_restore`]);
    /// their pairs with those lights are in `light_pairs`.
    pub pixels_restored: u64,
    /// (pixel x light) pairs the kernels summed: on the per-pixel path the lights above
    /// each pixel's horizon (what [`crate::kernel::gather`] kept); on the pixel-packed
    /// paths every pair of a batch's pixels with the frame's lights (a light below a
    /// pixel's horizon there fills its lane with an exact 0; the packed analytic path
    /// skips a light no pixel of the batch sees, which is still counted).
    pub pairs_summed: u64,
    /// Lanes those pairs occupied: per pixel, its groups of eight (the last one padded);
    /// pixel-packed, the batch's lanes (empty ones included) times the lights. So
    /// `pairs_summed / lane_slots` is the share of lanes holding a light above the horizon
    /// on the per-pixel path, and how full the batches of pixels are on the packed paths
    /// (`render --stats`: "kernel lanes used"). Scalar evaluations count one lane each.
    /// Depends on the kernel path (8 or 16 pixels per packed batch).
    pub lane_slots: u64,
}

impl super::traverse::TileSum for ShadeCounts {
    fn plus(self, o: Self) -> Self {
        self + o
    }
}

impl std::ops::Add for ShadeCounts {
    type Output = ShadeCounts;
    fn add(self, o: ShadeCounts) -> ShadeCounts {
        ShadeCounts {
            tiles_shaded: self.tiles_shaded + o.tiles_shaded,
            tiles_skipped: self.tiles_skipped + o.tiles_skipped,
            pixels_shaded: self.pixels_shaded + o.pixels_shaded,
            light_pairs: self.light_pairs + o.light_pairs,
            pixels_restored: self.pixels_restored + o.pixels_restored,
            pairs_summed: self.pairs_summed + o.pairs_summed,
            lane_slots: self.lane_slots + o.lane_slots,
        }
    }
}
