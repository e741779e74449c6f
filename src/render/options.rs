//! The render settings in one struct ([`RenderOptions`]), passed to [`super::render`].
//!
//! Design rule: every choice a caller makes about one render is a field here (in the style
//! of vello_cpu's `RenderSettings`), so the API grows by a field, not by an entry point.
//! `Default` is what `brdfkit render` does with a scene: the scene's precision and kernel,
//! culling on, the beauty image, on rayon's current pool, no stats, no progress shown.
//! The shading choices are a [`ShadeOptions`] inside (the field `shading`), the struct
//! [`crate::shade::shade`] takes, so that `shade` needs nothing from `render`.

use crate::aov::Aov;
use crate::shade::{ShadeOptions, ShadingPath};
use crate::shard::RowBands;

/// How to render a scene; see the module doc. Build one with struct-update syntax:
/// `RenderOptions { stats: true, ..RenderOptions::default() }`.
#[derive(Clone, Debug, Default)]
pub struct RenderOptions {
    /// A debug output ([`Aov`]) instead of the beauty image; `None` renders the beauty image.
    pub aov: Option<Aov>,
    /// Worker threads: `None` runs on rayon's current pool (the global one, or the pool the
    /// caller installed); `Some(n)` on a dedicated pool of `n` (0: one per core). The image
    /// is the same for any thread count.
    pub threads: Option<usize>,
    /// Whether to return the work done ([`super::RenderStats`]). The counters are gathered
    /// either way (integers per tile), so this changes no time worth measuring.
    pub stats: bool,
    /// The shading choices: the path (fast kernels, scalar f32 oracle, f64 path with no
    /// skips), the kernel instruction set, light culling, and where tiles are counted
    /// (progress). Not used by an AOV render.
    pub shading: ShadeOptions,
    /// Only the rows of one shard of a still image (`render --shard I/N`): the bands of
    /// rows of [`RowBands`] (band height [`super::shard_rows`]) that the shard owns are
    /// rendered, every other pixel stays black; the owned pixels are the bits of the
    /// unsharded render. `None` renders every row.
    pub rows: Option<RowBands>,
}

impl RenderOptions {
    /// The converged reference: the f64 path with no skips ([`ShadingPath::F64NoSkips`]:
    /// every light, every SH band, no culling, f64). It is *the* reference only on a scene
    /// whose light set is the full probe (every texel one light, `sampler = "full"`), as
    /// `brdfkit render --reference`, the golden bounds and the sweep's error measurements
    /// set it up.
    pub fn converged_reference() -> RenderOptions {
        RenderOptions {
            shading: ShadeOptions {
                path: Some(ShadingPath::F64NoSkips),
                ..ShadeOptions::default()
            },
            ..RenderOptions::default()
        }
    }

    /// These options on shading path `path` (overriding the scene's `render.precision`).
    pub fn with_path(mut self, path: ShadingPath) -> RenderOptions {
        self.shading.path = Some(path);
        self
    }
}
