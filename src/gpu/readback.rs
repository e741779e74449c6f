//! Read-back: the `Rgba32Float` colour target copied into a mapped buffer (rows padded to
//! wgpu's `COPY_BYTES_PER_ROW_ALIGNMENT`) and unpacked into the CPU path's [`Image`] (RGB,
//! row-major, row 0 the top, as the EXR and PNG writers expect); alpha is dropped.

use super::Gpu;
use crate::error::{Error, Result};
use crate::image_io::Image;
use glam::Vec3;

/// Copies `texture` (`width x height`, `Rgba32Float`) back into an [`Image`].
pub(super) fn read_image(
    gpu: &Gpu,
    texture: &wgpu::Texture,
    width: u32,
    height: u32,
) -> Result<Image> {
    let unpadded = width as u64 * 16;
    let align = wgpu::COPY_BYTES_PER_ROW_ALIGNMENT as u64;
    let row = unpadded.div_ceil(align) * align;
    let size = row * height as u64;
    if size > gpu.limits.max_buffer_size {
        return Err(gpu.over_limit(
            "the read-back buffer",
            "max_buffer_size",
            size,
            gpu.limits.max_buffer_size,
        ));
    }
    let buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("read-back"),
        size,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    encoder.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: 0,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(row as u32),
                rows_per_image: Some(height),
            },
        },
        wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
    );
    gpu.queue.submit([encoder.finish()]);
    let (tx, rx) = std::sync::mpsc::channel();
    buffer.map_async(wgpu::MapMode::Read, .., move |r| {
        let _ = tx.send(r);
    });
    gpu.device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| Error::Message(format!("--device gpu: {e}")))?;
    rx.recv()
        .map_err(|e| Error::Message(format!("--device gpu: read-back: {e}")))?
        .map_err(|e| Error::Message(format!("--device gpu: read-back: {e}")))?;
    let mut img = Image::new(width, height);
    {
        let view = buffer
            .get_mapped_range(..)
            .map_err(|e| Error::Message(format!("--device gpu: read-back: {e}")))?;
        let floats: &[f32] = bytemuck::cast_slice(&view);
        let row_floats = (row / 4) as usize;
        for y in 0..height as usize {
            for x in 0..width as usize {
                let p = &floats[y * row_floats + 4 * x..];
                img.pixels[y * width as usize + x] = Vec3::new(p[0], p[1], p[2]);
            }
        }
    }
    buffer.unmap();
    Ok(img)
}
