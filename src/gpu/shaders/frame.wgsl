// One frame: the mesh rasterized by the GPU (depth test, reverse-z: larger depth is
// nearer) and every visible fragment shaded once with the sum over delta lights
// L = sum_k f(l_k, v) cos(polar_k) E_k (thesis 2.3.2, Def. 10). The header that
// src/gpu/pipeline.rs puts before this file defines SH_TERMS.

struct Frame {
    clip_from_world: mat4x4<f32>,
    // xyz: camera position.
    eye: vec4<f32>,
    // The camera's world axes: right (view +x), up (view +y), backward (view +z).
    cam_right: vec4<f32>,
    cam_up: vec4<f32>,
    cam_back: vec4<f32>,
    // width, height (pixels), tan(fov_x / 2), tan(fov_y / 2).
    viewport: vec4<f32>,
    // The exact sphere the mesh tessellates: centre, radius (radius 0: none).
    sphere: vec4<f32>,
    // Lambert albedo, or k_d, or the diffuse base of Lambert + D-BRDF; w: exponent.
    kd: vec4<f32>,
    // k_s, or the D-BRDF's R_s; w: the D-BRDF's c.
    ks: vec4<f32>,
    // material kind, light count, fault bits, SH lookup (0 nearest, 1 bilinear).
    ints: vec4<u32>,
    // table nu (azimuth texels), nv (polar texels), SH bands, whether f includes the cosine.
    table: vec4<u32>,
    // x: the debug output instead of radiance (AOV_* below; 0: radiance).
    aov: vec4<u32>,
    // The transfer table (transfer.wgsl): nu, nv, terms per colour, 1 when there is one.
    xfer: vec4<u32>,
    // x: the probe rotation about +y, radians. y, z, w: the material's frame rule
    // (src/conventions/mod.rs, "Frame of isotropic tabulated materials"): w = 1 when the
    // frame is turned about the normal until the view lies at the azimuth whose cosine and
    // sine are y and z; w = 2 for the mesh's tangent (anisotropic materials, "Frame of
    // anisotropic materials"); w = 0 for the world-up frame.
    xfer_rot: vec4<f32>,
    // The reflection-space table (reflection.wgsl): grid cells per side, uniform view
    // slices, the index of its diffuse term, 1 when there is one.
    refl: vec4<u32>,
    // x: the reflection table's probe rotation about +y, radians.
    refl_rot: vec4<f32>,
}

// Debug outputs (thesis Figs. 3.1-3.3; src/aov.rs documents each): the shading normal, the
// view-axis distance, and the view's and the first light's polar angle over pi/2 and
// azimuth over 2 pi in the shading frame.
const AOV_NORMAL: u32 = 1u;
const AOV_DEPTH: u32 = 2u;
const AOV_VIEW_POLAR: u32 = 3u;
const AOV_VIEW_AZIMUTH: u32 = 4u;
const AOV_LIGHT_POLAR: u32 = 5u;
const AOV_LIGHT_AZIMUTH: u32 = 6u;

// A delta light: w of `where_` is 0 for a directional light (xyz: unit direction towards
// the light, `value` its irradiance at normal incidence, W/m^2) and 1 for a point light
// (xyz: position, `value` its intensity, W/sr).
struct Light {
    where_: vec4<f32>,
    value: vec4<f32>,
}

const MAT_LAMBERT: u32 = 0u;
const MAT_PHONG: u32 = 1u;
const MAT_BLINN_PHONG: u32 = 2u;
const MAT_SH: u32 = 3u;
const MAT_DBRDF: u32 = 4u;
const MAT_LAMBERT_DBRDF: u32 = 5u;

// Smallest squared distance at which a point light's 1/d^2 applies (src/light.rs).
const MIN_POINT_DISTANCE2: f32 = 1e-12;

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> lights: array<Light>;
@group(0) @binding(2) var<storage, read> table: array<f32>;

// The pass: first light, end of its lights, whether it is the first pass (1: nothing to
// add), whether it is the last (1).
@group(0) @binding(3) var<uniform> pass_info: vec4<u32>;
// The radiance summed by the earlier passes (ignored by the first).
@group(0) @binding(4) var previous: texture_2d<f32>;

var<private> sh_c: array<vec3<f32>, SH_TERMS>;

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) tangent: vec3<f32>,
}

@vertex
fn vs_main(@location(0) position: vec3<f32>, @location(1) normal: vec3<f32>, @location(2) tangent: vec3<f32>) -> VsOut {
    var out: VsOut;
    out.clip = frame.clip_from_world * vec4<f32>(position, 1.0);
    out.world = position;
    out.normal = normal;
    out.tangent = tangent;
    return out;
}

// f_r cos(polar_i) of the material (the cosine only when the model does not include it).
fn brdf_cos(wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    if wi.z <= 0.0 || wo.z <= 0.0 {
        return vec3<f32>(0.0);
    }
    let kind = frame.ints.x;
    var f: vec3<f32>;
    if kind == MAT_LAMBERT {
        f = lambert(frame.kd.xyz);
    } else if kind == MAT_PHONG {
        f = phong(wi, wo, frame.kd.xyz, frame.ks.xyz, frame.kd.w);
    } else if kind == MAT_BLINN_PHONG {
        f = blinn_phong(wi, wo, frame.kd.xyz, frame.ks.xyz, frame.kd.w);
    } else if kind == MAT_SH {
        f = sh_sum(wi);
    } else if kind == MAT_DBRDF {
        f = dbrdf(wi, wo, frame.ks.xyz, frame.ks.w);
    } else {
        f = lambert(frame.kd.xyz) + dbrdf(wi, wo, frame.ks.xyz, frame.ks.w);
    }
    if frame.table.w == 1u || has_fault(FAULT_NO_COSINE) {
        return f;
    }
    return f * wi.z;
}

// The unit direction from p towards the light (w unused); a point light at p gives +y.
fn light_at(light: Light, p: vec3<f32>) -> vec4<f32> {
    if light.where_.w > 0.5 {
        let dv = light.where_.xyz - p;
        let d2 = dot(dv, dv);
        if d2 > 0.0 {
            return vec4<f32>(dv / sqrt(d2), 0.0);
        }
        return vec4<f32>(0.0, 1.0, 0.0, 0.0);
    }
    return vec4<f32>(light.where_.xyz, 0.0);
}

// sRGB's encoding (IEC 61966-2-1), used only by the seeded fault FAULT_SRGB_TWICE.
fn srgb_encode(c: vec3<f32>) -> vec3<f32> {
    let x = max(c, vec3<f32>(0.0));
    return select(1.055 * pow(x, vec3<f32>(1.0 / 2.4)) - 0.055, 12.92 * x, x <= vec3<f32>(0.0031308));
}

@fragment
fn fs_main(in: VsOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    var p = in.world;
    var n = normalize(in.normal);
    let eye = frame.eye.xyz;
    if frame.sphere.w > 0.0 {
        // The camera ray through the pixel centre meets the exact sphere: first hit seen
        // through a front face, second through a back face; a miss keeps the facet.
        let ndc = vec2<f32>(2.0 * in.clip.x / frame.viewport.x - 1.0, 1.0 - 2.0 * in.clip.y / frame.viewport.y);
        let d = frame.cam_right.xyz * (ndc.x * frame.viewport.z) + frame.cam_up.xyz * (ndc.y * frame.viewport.w) - frame.cam_back.xyz;
        let o = eye - frame.sphere.xyz;
        let a = dot(d, d);
        let b = dot(o, d);
        let c = dot(o, o) - frame.sphere.w * frame.sphere.w;
        let disc = b * b - a * c;
        if disc > 0.0 {
            let s = sqrt(disc);
            var t = (-b - s) / a;
            if !front {
                t = (-b + s) / a;
            }
            p = eye + t * d;
            n = (p - frame.sphere.xyz) / frame.sphere.w;
        }
    }
    if !front {
        n = -n;
    }
    // The world-up frame (the AOVs' frame), and the material's: turned to the view when
    // its rule says so.
    let sf_up = shading_frame(n);
    let v = normalize(eye - p);
    var sf = sf_up;
    if frame.xfer_rot.w > 1.5 {
        sf = frame_from_tangent(sf_up, in.tangent);
    } else if frame.xfer_rot.w > 0.5 {
        sf = turned_to_view(sf_up, v, frame.xfer_rot.y, frame.xfer_rot.z);
    }
    let wo = lift_above_horizon(to_local(sf, v));
    let aov = frame.aov.x;
    if aov != 0u {
        let wo = lift_above_horizon(to_local(sf_up, v));
        let sf = sf_up;
        var v = vec3<f32>(0.0);
        if aov == AOV_NORMAL {
            v = n;
        } else if aov == AOV_DEPTH {
            v = vec3<f32>(dot(p - eye, -frame.cam_back.xyz));
        } else if aov == AOV_VIEW_POLAR || aov == AOV_VIEW_AZIMUTH {
            let st = hemi_texcoord(wo);
            v = vec3<f32>(select(st.x, st.y, aov == AOV_VIEW_POLAR));
        } else if frame.ints.y > 0u {
            let st = hemi_texcoord(to_local(sf, light_at(lights[0], p).xyz));
            v = vec3<f32>(select(st.x, st.y, aov == AOV_LIGHT_POLAR));
        }
        return vec4<f32>(v, 1.0);
    }
    if frame.ints.x == MAT_SH {
        sh_lookup(wo);
    }
    var radiance = vec3<f32>(0.0);
    if pass_info.z == 1u && frame.xfer.w == 1u {
        // The environment's transfer term, once per pixel (transfer.wgsl).
        radiance = transfer_radiance(n, dot(sf.t, sf_up.t), dot(sf.t, sf_up.b));
    }
    if pass_info.z == 1u && frame.refl.w == 1u {
        // The environment's reflection-table term, once per pixel (reflection.wgsl), at the
        // view lifted above the horizon in the world-up frame (the table is isotropic).
        let wl = lift_above_horizon(to_local(sf_up, v));
        radiance = radiance + reflection_radiance(n, wl.x * sf_up.t + wl.y * sf_up.b + wl.z * sf_up.n);
    }
    // This pass's lights (src/gpu/pipeline.rs splits the light set over passes).
    for (var i = pass_info.x; i < pass_info.y; i = i + 1u) {
        let light = lights[i];
        let wi = to_local(sf, light_at(light, p).xyz);
        var e = light.value.xyz;
        if light.where_.w > 0.5 {
            let dv = light.where_.xyz - p;
            let d2 = dot(dv, dv);
            e = select(vec3<f32>(0.0), light.value.xyz / max(d2, MIN_POINT_DISTANCE2), d2 > 0.0);
        }
        if wi.z > 0.0 {
            radiance = radiance + brdf_cos(wi, wo) * e;
        }
    }
    if pass_info.z == 0u {
        // The sum of the earlier passes at this pixel.
        radiance = radiance + textureLoad(previous, vec2<i32>(floor(in.clip.xy)), 0).rgb;
    }
    if pass_info.w == 1u && has_fault(FAULT_GAIN) {
        radiance = radiance * 1.005;
    }
    if pass_info.w == 1u && has_fault(FAULT_SRGB_TWICE) {
        radiance = srgb_encode(radiance);
    }
    return vec4<f32>(radiance, 1.0);
}
