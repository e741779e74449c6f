//! The scene packed for the GPU: one uniform block (camera, exact sphere, material
//! parameters, counts, faults), the interleaved vertices and the indices, the delta lights,
//! the material's table (SH coefficients or the D-BRDF's `p(h)`) and the environment's
//! transfer table or reflection-space table, each checked against the adapter's limits
//! before anything is allocated.
//!
//! The layouts match `shaders/frame.wgsl` (`Frame`, `Light`); the SH coefficient table keeps
//! the data set's own layout `coeffs[((j nu + i) 3 + c) T + k]` ([`crate::sh::dataset`]),
//! the transfer table its own `values[((j nu + i) 3 + c) terms + k]`
//! ([`crate::env::transfer::TransferTable`], read by `shaders/transfer.wgsl`), the
//! reflection table its own, lobes' series then diffuse term
//! ([`crate::env::reflection::ReflectionTable`], read by `shaders/reflection.wgsl`).

use super::{Faults, Gpu};
use crate::aov::Aov;
use crate::env::reflection::table::{coeffs, lobe_value_count};
use crate::env::reflection::ReflectionTerm;
use crate::env::schema::DEFAULT_REFLECTION_ORDER;
use crate::error::Result;
use crate::light::Light;
use crate::material::Material;
use crate::scene::Scene;
use crate::sh::dataset::Lookup;
use bytemuck::{Pod, Zeroable};
use glam::Mat3;
use wgpu::util::DeviceExt;

/// The uniform block `Frame` of `shaders/frame.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(super) struct FrameUniform {
    clip_from_world: [[f32; 4]; 4],
    eye: [f32; 4],
    cam_right: [f32; 4],
    cam_up: [f32; 4],
    cam_back: [f32; 4],
    viewport: [f32; 4],
    sphere: [f32; 4],
    kd: [f32; 4],
    ks: [f32; 4],
    ints: [u32; 4],
    table: [u32; 4],
    aov: [u32; 4],
    xfer: [u32; 4],
    xfer_rot: [f32; 4],
    refl: [u32; 4],
    refl_rot: [f32; 4],
}

/// The `Light` of `shaders/frame.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct GpuLight {
    where_: [f32; 4],
    value: [f32; 4],
}

/// Everything one draw reads, on the device.
pub(super) struct Uploads {
    pub frame: wgpu::Buffer,
    pub vertices: wgpu::Buffer,
    pub indices: wgpu::Buffer,
    pub index_count: u32,
    pub lights: wgpu::Buffer,
    pub table: wgpu::Buffer,
    /// The transfer table's values (one zero when the scene has none).
    pub transfer: wgpu::Buffer,
    /// Terms per colour of the transfer table (0: none).
    pub transfer_terms: u32,
    /// The reflection-space table's values (one zero when the scene has none).
    pub reflection: wgpu::Buffer,
    /// Whether the scene has a reflection-space table (its lookup's loops count per pixel).
    pub has_reflection: bool,
    /// The order of the reflection table's series in psi (the default 2 without a table):
    /// the shader's header sizes its basis by it (`REFL_ORDER`, [`super::pipeline`]).
    pub refl_order: u32,
    /// Terms per colour of the SH data set (bands^2), 1 for other materials: the size of the
    /// shader's per-pixel coefficient array.
    pub sh_terms: u32,
    pub width: u32,
    pub height: u32,
    pub cull_back: bool,
    /// Lights in the scene.
    pub light_count: u32,
    /// SH bands (0 for other materials).
    pub sh_bands: u32,
    /// Whether the draw writes a debug output (one pass, no lights summed).
    pub aov: bool,
}

/// Loop iterations one fragment may run, all loops together, in one pass. Mesa's llvmpipe
/// (lavapipe) ends a fragment's loops after 65535 iterations of its own counting (measured
/// here: a flat loop over 20000 lights passed, over 30000 it stopped early, so it counts
/// about three per iteration); a quarter of that keeps any such driver safe and costs a
/// real GPU nothing but a few more passes over a full probe. WebGPU has no limit to query
/// for this.
pub(super) const LOOP_ITERATIONS_PER_PASS: u32 = 16_000;

/// Loop iterations of one reflection-table lookup (`shaders/reflection.wgsl`) of a series of
/// order `order`: four vertices, two slices, three colours, `2 order + 1` coefficients, the
/// diffuse term's four, and the two bases' `order` each (156 at order 2).
fn reflection_lookup_iterations(order: u32) -> u32 {
    4 * 2 * 3 * (1 + coeffs(order as usize) as u32) + 4 + 4 + 2 * order
}

impl Uploads {
    /// The light ranges `[begin, end)` of the passes: each pass's loop iterations (the SH
    /// coefficient lookup, the transfer table's dot and the reflection table's lookup per
    /// pixel, then per light the light loop and the SH recurrence's
    /// `bands + bands (bands + 1) / 2`) within
    /// [`LOOP_ITERATIONS_PER_PASS`]; one empty pass for no lights.
    pub fn light_passes(&self) -> Vec<(u32, u32)> {
        if self.aov {
            return vec![(0, 0)];
        }
        let b = self.sh_bands;
        let per_light = 1 + b + b * (b + 1) / 2;
        // The SH coefficient lookup, the transfer table's dot and the reflection table's
        // lookup (first pass only, but counted for every pass to keep one bound).
        let per_pixel = if b > 0 { self.sh_terms } else { 0 }
            + self.transfer_terms
            + if self.has_reflection {
                reflection_lookup_iterations(self.refl_order)
            } else {
                0
            };
        let per_pass = (LOOP_ITERATIONS_PER_PASS.saturating_sub(per_pixel) / per_light).max(1);
        let mut out = Vec::new();
        let mut begin = 0;
        while begin < self.light_count {
            let end = (begin + per_pass).min(self.light_count);
            out.push((begin, end));
            begin = end;
        }
        if out.is_empty() {
            out.push((0, 0));
        }
        out
    }
}

/// The shader's code of a debug output (`AOV_*` in `shaders/frame.wgsl`; 0: radiance).
fn aov_code(aov: Option<Aov>) -> u32 {
    match aov {
        None => 0,
        Some(Aov::Normal) => 1,
        Some(Aov::Depth) => 2,
        Some(Aov::ViewPolar) => 3,
        Some(Aov::ViewAzimuth) => 4,
        Some(Aov::LightPolar) => 5,
        Some(Aov::LightAzimuth) => 6,
        Some(Aov::Coverage) => unreachable!("refused by gpu::unsupported"),
    }
}

fn v4(v: glam::Vec3, w: f32) -> [f32; 4] {
    [v.x, v.y, v.z, w]
}

impl Uploads {
    /// Packs `scene` (checked by [`Gpu::render`] to be supported) with the seeded `faults`.
    /// Error: a size over the adapter's limits, named.
    pub fn new(gpu: &Gpu, scene: &Scene, aov: Option<Aov>, faults: Faults) -> Result<Uploads> {
        let lim = &gpu.limits;
        let (width, height) = (scene.render.width, scene.render.height);
        let side = lim.max_texture_dimension_2d;
        if width > side || height > side {
            return Err(gpu.over_limit(
                "the image side",
                "max_texture_dimension_2d",
                width.max(height) as u64,
                side as u64,
            ));
        }
        // Lights, material table, transfer table, reflection table.
        if lim.max_storage_buffers_per_shader_stage < 4 {
            return Err(gpu.over_limit(
                "the fragment shader",
                "max_storage_buffers_per_shader_stage",
                4,
                lim.max_storage_buffers_per_shader_stage as u64,
            ));
        }

        let cam = &scene.camera;
        let aspect = width as f32 / height as f32;
        let view = cam.view_from_world();
        let clip_from_world = cam.clip_from_view(aspect) * view;
        // The inverse of the view rotation is its transpose: columns right, up, backward.
        let world_from_view = Mat3::from_mat4(view).transpose();
        let tan_y = (0.5 * cam.fov_y_deg).to_radians().tan();
        let sphere = scene
            .mesh
            .exact_sphere
            .map_or([0.0; 4], |s| v4(s.center, s.radius));

        let (mut kd, mut ks) = ([0.0f32; 4], [0.0f32; 4]);
        let mut table_info = [0u32; 4];
        let mut table: Vec<f32> = Vec::new();
        let mut sh_terms = 1;
        let mut lookup = 0;
        let kind = match &scene.material {
            Material::Lambert(m) => {
                kd = v4(m.albedo, 0.0);
                0
            }
            Material::Phong(m) => {
                (kd, ks) = (v4(m.kd, m.exponent), v4(m.ks, 0.0));
                1
            }
            Material::BlinnPhong(m) => {
                (kd, ks) = (v4(m.kd, m.exponent), v4(m.ks, 0.0));
                2
            }
            Material::Sh(ds) => {
                let (nu, nv) = ds.grid();
                table.extend_from_slice(ds.coeffs());
                sh_terms = (ds.bands() * ds.bands()) as u32;
                table_info = [
                    nu as u32,
                    nv as u32,
                    ds.bands() as u32,
                    ds.cosine_included() as u32,
                ];
                lookup = match ds.coeff_lookup {
                    Lookup::Nearest => 0,
                    Lookup::Bilinear => 1,
                };
                3
            }
            Material::DBrdf(d) => {
                let (nu, nv) = d.grid();
                table.extend_from_slice(d.table());
                table_info = [nu as u32, nv as u32, 0, 0];
                ks = v4(d.rs, d.c);
                4
            }
            Material::LambertDbrdf(m) => {
                let (nu, nv) = m.lobe.grid();
                table.extend_from_slice(m.lobe.table());
                table_info = [nu as u32, nv as u32, 0, 0];
                kd = v4(m.rd, 0.0);
                ks = v4(m.lobe.rs, m.lobe.c);
                5
            }
            Material::AshikhminShirley(_) | Material::Merl(_) | Material::Rgl(_) => {
                unreachable!("refused by gpu::unsupported")
            }
        };
        if table.is_empty() {
            table.push(0.0);
        }

        let mut lights: Vec<GpuLight> = scene
            .delta_lights()
            .iter()
            .map(|l| match *l {
                Light::Directional {
                    to_light,
                    irradiance,
                } => GpuLight {
                    where_: v4(to_light, 0.0),
                    value: v4(irradiance, 0.0),
                },
                Light::Point {
                    position,
                    intensity,
                } => GpuLight {
                    where_: v4(position, 1.0),
                    value: v4(intensity, 0.0),
                },
            })
            .collect();
        let light_count = lights.len() as u32;
        if lights.is_empty() {
            lights.push(GpuLight::zeroed());
        }

        let (xfer, xfer_rot, mut transfer) = match scene.environment.transfer_table() {
            Some(t) => {
                let (nu, nv) = t.grid();
                (
                    [nu as u32, nv as u32, t.terms() as u32, 1],
                    [t.rotation(), 0.0, 0.0, 0.0],
                    t.values().to_vec(),
                )
            }
            None => ([0; 4], [0.0; 4], Vec::new()),
        };
        // The material's frame rule (crate::conventions, "Frame of isotropic tabulated
        // materials", "Frame of anisotropic materials"): the view's azimuth in a
        // view-aligned frame, as a unit pair, and 1; or 2 for the mesh's tangent.
        let mut xfer_rot = xfer_rot;
        let rule = crate::shade::effective_frame_rule(&scene.material, &scene.mesh);
        if let Some((c, s)) = rule.view_azimuth {
            xfer_rot[1..].copy_from_slice(&[c, s, 1.0]);
        } else if rule.mesh_tangent {
            xfer_rot[3] = 2.0;
        }
        // The reflection-space table (an isotropic material's: the filtered path of an
        // anisotropic D-BRDF is refused by gpu::unsupported).
        let (refl, mut refl_rot, mut reflection, refl_order) =
            match scene.environment.reflection_term() {
                Some(term) => match term.as_ref() {
                    ReflectionTerm::Table(t) => (
                        [
                            t.grid() as u32,
                            t.slices() as u32,
                            lobe_value_count(t.grid(), t.slices(), t.order()) as u32,
                            1,
                        ],
                        [t.rotation(), 0.0, 0.0, 0.0],
                        t.values().to_vec(),
                        t.order() as u32,
                    ),
                    ReflectionTerm::Filtered(_) => unreachable!("refused by gpu::unsupported"),
                },
                None => (
                    [0; 4],
                    [0.0; 4],
                    Vec::new(),
                    DEFAULT_REFLECTION_ORDER as u32,
                ),
            };
        let mut light_count = light_count;
        // A scene has one environment table at most: the faults apply to that one.
        let (env_table, rotation) = if refl[3] == 1 {
            (&mut reflection, &mut refl_rot[0])
        } else {
            (&mut transfer, &mut xfer_rot[0])
        };
        faults.apply_to_uploads(super::fault::UploadedTables {
            material: &mut table,
            sh_terms: sh_terms as usize,
            material_is_sh: kind == 3,
            env_table,
            rotation,
            light_count: &mut light_count,
        });
        for t in [&mut transfer, &mut reflection] {
            if t.is_empty() {
                t.push(0.0);
            }
        }

        let frame = FrameUniform {
            clip_from_world: clip_from_world.to_cols_array_2d(),
            eye: v4(cam.position, 1.0),
            cam_right: v4(world_from_view.x_axis, 0.0),
            cam_up: v4(world_from_view.y_axis, 0.0),
            cam_back: v4(world_from_view.z_axis, 0.0),
            viewport: [width as f32, height as f32, tan_y * aspect, tan_y],
            sphere,
            kd,
            ks,
            ints: [kind, light_count, faults.0, lookup],
            table: table_info,
            aov: [aov_code(aov), 0, 0, 0],
            xfer,
            xfer_rot,
            refl,
            refl_rot,
        };

        let mesh = &scene.mesh;
        let vertices: Vec<[f32; 9]> = mesh
            .positions
            .iter()
            .zip(&mesh.normals)
            .enumerate()
            .map(|(i, (p, n))| {
                let t = mesh.tangents.get(i).copied().unwrap_or(glam::Vec3::ZERO);
                [p.x, p.y, p.z, n.x, n.y, n.z, t.x, t.y, t.z]
            })
            .collect();
        let indices: Vec<u32> = mesh.triangles.iter().flatten().copied().collect();

        let storage = lim.max_storage_buffer_binding_size;
        for (what, bytes) in [
            (
                "the light buffer",
                std::mem::size_of_val(lights.as_slice()) as u64,
            ),
            (
                "the material table",
                std::mem::size_of_val(table.as_slice()) as u64,
            ),
            (
                "the transfer table",
                std::mem::size_of_val(transfer.as_slice()) as u64,
            ),
            (
                "the reflection table",
                std::mem::size_of_val(reflection.as_slice()) as u64,
            ),
        ] {
            if bytes > storage {
                return Err(gpu.over_limit(
                    what,
                    "max_storage_buffer_binding_size",
                    bytes,
                    storage,
                ));
            }
        }
        for (what, bytes) in [
            (
                "the vertex buffer",
                std::mem::size_of_val(vertices.as_slice()) as u64,
            ),
            (
                "the index buffer",
                std::mem::size_of_val(indices.as_slice()) as u64,
            ),
        ] {
            if bytes > lim.max_buffer_size {
                return Err(gpu.over_limit(what, "max_buffer_size", bytes, lim.max_buffer_size));
            }
        }

        let buffer = |label: &str, contents: &[u8], usage| {
            gpu.device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(label),
                    contents,
                    usage,
                })
        };
        use wgpu::BufferUsages as U;
        Ok(Uploads {
            frame: buffer("frame", bytemuck::bytes_of(&frame), U::UNIFORM),
            vertices: buffer("vertices", bytemuck::cast_slice(&vertices), U::VERTEX),
            indices: buffer("indices", bytemuck::cast_slice(&indices), U::INDEX),
            index_count: indices.len() as u32,
            lights: buffer("lights", bytemuck::cast_slice(&lights), U::STORAGE),
            table: buffer("table", bytemuck::cast_slice(&table), U::STORAGE),
            transfer: buffer("transfer", bytemuck::cast_slice(&transfer), U::STORAGE),
            transfer_terms: xfer[2],
            reflection: buffer("reflection", bytemuck::cast_slice(&reflection), U::STORAGE),
            has_reflection: refl[3] == 1,
            refl_order,
            sh_terms,
            width,
            height,
            cull_back: scene.render.cull == crate::raster::Cull::Back,
            light_count,
            sh_bands: table_info[2],
            aov: aov.is_some(),
        })
    }
}
