//! The buffers of a frame kept across frames ([`FrameContext`]), for callers that render
//! frame after frame (the viewer, turntables, the sweep, the benches): what
//! [`super::render_into`] reuses.
//!
//! Design rule: a context holds memory, never results a frame reads. Every buffer is
//! rewritten by the frame that uses it (the rasterizer's by [`crate::raster::rasterize_into`],
//! the image band by band by the shading pass that writes it, the workers' buffers emptied
//! as they are lent: [`crate::shade::ShadeScratch`]), so a frame has the bits of a frame
//! rendered with a new context whatever the context rendered before; a frame of the size
//! of the previous one allocates none of them.

use super::RenderStats;
use crate::image_io::Image;
use crate::raster::{RasterFault, RasterScratch, VisBuffer};
use crate::shade::ShadeScratch;
use glam::Vec4;

/// What a frame context keeps for [`super::render_into`]: one render's buffers and the
/// thread pool of its `threads` option. `FrameContext::default()` is empty; the first frame
/// sizes it.
#[derive(Debug, Default)]
pub struct FrameContext {
    pub(super) buffers: FrameBuffers,
    /// The dedicated pool of [`super::RenderOptions::threads`] and its size, built on the
    /// first frame that asks for it and kept while the thread count stays.
    pool: Option<(usize, rayon::ThreadPool)>,
}

/// One frame's buffers, in the order the frame fills them.
#[derive(Debug, Default)]
pub(super) struct FrameBuffers {
    /// The mesh's vertices in clip space.
    pub(super) clip: Vec<Vec4>,
    /// The rasterizer's snapped vertices, set-up tasks and bins.
    pub(super) raster: RasterScratch,
    /// The visibility buffer.
    pub(super) vis: VisBuffer,
    /// The shading workers' buffers.
    pub(super) shading: ShadeScratch,
    /// The image (linear radiance, or the AOV).
    pub(super) image: Image,
    /// **Test only**: a fault seeded into the rasterizer ([`FrameContext::with_fault`]).
    pub(super) fault: Option<RasterFault>,
}

impl FrameContext {
    /// **Test only**: an empty context whose frames rasterize with `fault` seeded
    /// ([`RasterFault::PreviousFrameKept`]: the previous frame's visibility not cleared), to
    /// show the tests of reuse fail on a context that leaks one frame into the next.
    #[doc(hidden)]
    pub fn with_fault(fault: RasterFault) -> FrameContext {
        FrameContext {
            buffers: FrameBuffers {
                fault: Some(fault),
                ..FrameBuffers::default()
            },
            pool: None,
        }
    }

    /// The image of the last frame rendered into this context (empty before the first).
    pub fn image(&self) -> &Image {
        &self.buffers.image
    }

    /// The last frame's image, moved out: the next frame allocates a new one.
    pub fn take_image(&mut self) -> Image {
        std::mem::take(&mut self.buffers.image)
    }

    /// The visibility buffer of the last frame rendered (its rays set, its shard rows left).
    pub fn vis(&self) -> &VisBuffer {
        &self.buffers.vis
    }

    /// The buffers and the pool of `threads` threads (0: one per core), the pool built if
    /// the kept one has another size.
    pub(super) fn buffers_and_pool(
        &mut self,
        threads: usize,
    ) -> (&mut FrameBuffers, &rayon::ThreadPool) {
        if self.pool.as_ref().map(|(n, _)| *n) != Some(threads) {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("thread pool");
            self.pool = Some((threads, pool));
        }
        let pool = &self.pool.as_ref().expect("built above").1;
        (&mut self.buffers, pool)
    }
}

/// A frame rendered into a [`FrameContext`] ([`super::render_into`]): its image, borrowed
/// from the context, and, when [`super::RenderOptions::stats`] asked for it, the work done.
#[derive(Clone, Debug)]
pub struct RenderedFrame<'c> {
    /// The beauty image (linear radiance) or the AOV asked for.
    pub image: &'c Image,
    /// The work done; `None` unless [`super::RenderOptions::stats`].
    pub stats: Option<RenderStats>,
}
