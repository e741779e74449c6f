//! The render pipeline and one draw: the WGSL files assembled behind a header that sizes
//! the per-pixel SH coefficient array and the reflection table's Fourier basis, a
//! depth-tested (reverse-z: `Greater`, cleared to 0, as [`crate::scene::camera`]'s
//! projection writes depth `near / w`) draw of the indexed
//! mesh into an `Rgba32Float` target (linear radiance; alpha 1 where covered, 0 elsewhere).
//! Triangles are counter-clockwise seen from the front ([`crate::mesh::Mesh`]); back faces
//! are drawn (two-sided) unless the scene culls them.
//!
//! The lights are split over passes ([`Uploads::light_passes`]): each pass rasterizes the
//! mesh again (the same visibility: same triangles, same order, same depth test) and writes
//! the sum of what the previous pass wrote and its own lights' radiance into the other of
//! two targets. No blending is needed, so no optional feature (`Rgba32Float` blending is
//! one) is assumed.

use super::upload::Uploads;
use super::Gpu;
use crate::error::{Error, Result};
use wgpu::util::DeviceExt;

/// The colour target's format: 32-bit float RGBA, renderable on every WebGPU adapter.
pub(super) const TARGET_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

/// The WGSL source for a material with `sh_terms` SH terms per colour and a reflection
/// table whose series in psi is of order `refl_order` (`shaders/reflection.wgsl`; any
/// order 1 to 8 without a table).
pub(super) fn shader_source(sh_terms: u32, refl_order: u32) -> String {
    format!(
        "const SH_TERMS: u32 = {sh_terms}u;\nconst REFL_ORDER: u32 = {refl_order}u;\n\
         {}\n{}\n{}\n{}\n{}\n{}",
        include_str!("shaders/conventions.wgsl"),
        include_str!("shaders/brdf.wgsl"),
        include_str!("shaders/sh.wgsl"),
        include_str!("shaders/frame.wgsl"),
        include_str!("shaders/transfer.wgsl"),
        include_str!("shaders/reflection.wgsl"),
    )
}

/// Draws `up` and returns the colour target (not yet read back). Error: a validation error
/// from the device (one line).
pub(super) fn draw(gpu: &Gpu, up: &Uploads) -> Result<wgpu::Texture> {
    let device = &gpu.device;
    let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("brdfkit frame"),
        source: wgpu::ShaderSource::Wgsl(shader_source(up.sh_terms, up.refl_order).into()),
    });
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("frame"),
        entries: &[
            entry(0, wgpu::BufferBindingType::Uniform),
            entry(1, wgpu::BufferBindingType::Storage { read_only: true }),
            entry(2, wgpu::BufferBindingType::Storage { read_only: true }),
            entry(3, wgpu::BufferBindingType::Uniform),
            wgpu::BindGroupLayoutEntry {
                binding: 4,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: false },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 5,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Storage { read_only: true },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 6,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Storage { read_only: true },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            },
        ],
    });
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("frame"),
        bind_group_layouts: &[Some(&layout)],
        immediate_size: 0,
    });
    let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("frame"),
        layout: Some(&pipeline_layout),
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs_main"),
            compilation_options: Default::default(),
            buffers: &[Some(wgpu::VertexBufferLayout {
                // Position, normal, tangent (zero where the mesh has none).
                array_stride: 36,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x3],
            })],
        },
        primitive: wgpu::PrimitiveState {
            topology: wgpu::PrimitiveTopology::TriangleList,
            front_face: wgpu::FrontFace::Ccw,
            cull_mode: up.cull_back.then_some(wgpu::Face::Back),
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: wgpu::TextureFormat::Depth32Float,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Greater),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module: &module,
            entry_point: Some("fs_main"),
            compilation_options: Default::default(),
            targets: &[Some(wgpu::ColorTargetState {
                format: TARGET_FORMAT,
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            })],
        }),
        multiview_mask: None,
        cache: None,
    });
    let size = wgpu::Extent3d {
        width: up.width,
        height: up.height,
        depth_or_array_layers: 1,
    };
    let texture = |label, format, usage| {
        device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size,
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage,
            view_formats: &[],
        })
    };
    // Two radiance targets, ping-ponged: pass k adds its lights to what pass k - 1 wrote.
    let targets = [0, 1].map(|_| {
        texture(
            "radiance",
            TARGET_FORMAT,
            wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
        )
    });
    let views = targets
        .each_ref()
        .map(|t| t.create_view(&Default::default()));
    let depth = texture(
        "depth",
        wgpu::TextureFormat::Depth32Float,
        wgpu::TextureUsages::RENDER_ATTACHMENT,
    );
    let depth_view = depth.create_view(&Default::default());
    let passes = up.light_passes();
    let mut encoder = device.create_command_encoder(&Default::default());
    for (k, &(begin, end)) in passes.iter().enumerate() {
        let info = [begin, end, (k == 0) as u32, (k + 1 == passes.len()) as u32];
        let info = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("pass"),
            contents: bytemuck::cast_slice(&info),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("frame"),
            layout: &layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: up.frame.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: up.lights.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: up.table.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: info.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: wgpu::BindingResource::TextureView(&views[(k + 1) % 2]),
                },
                wgpu::BindGroupEntry {
                    binding: 5,
                    resource: up.transfer.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 6,
                    resource: up.reflection.as_entire_binding(),
                },
            ],
        });
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("frame"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &views[k % 2],
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(0.0),
                    store: wgpu::StoreOp::Discard,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind, &[]);
        pass.set_vertex_buffer(0, up.vertices.slice(..));
        pass.set_index_buffer(up.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..up.index_count, 0, 0..1);
    }
    gpu.queue.submit([encoder.finish()]);
    if let Some(e) = pollster::block_on(scope.pop()) {
        let first = e.to_string();
        let first = first.lines().next().unwrap_or("").to_string();
        return Err(Error::Message(format!("--device gpu: {first}")));
    }
    let [a, b] = targets;
    Ok(if passes.len() % 2 == 1 { a } else { b })
}

fn entry(binding: u32, ty: wgpu::BufferBindingType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
        ty: wgpu::BindingType::Buffer {
            ty,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}
