// Coordinate conventions on the GPU, written from src/conventions/mod.rs (the "Departures
// from the thesis" list) and thesis 3.1.2-3.1.4. Nothing here is shared with the CPU kernel.

const PI: f32 = 3.14159265358979;
const TAU: f32 = 6.28318530717959;
// Smallest cosine of the view direction above the horizon (conventions item 8).
const MIN_VIEW_COS: f32 = 1e-3;

// Seeded faults (bit flags in frame.ints.z), injected only by the hidden option of
// `brdfkit golden check --device gpu` to show that the check catches them.
const FAULT_HALF_TEXEL: u32 = 1u;
const FAULT_NO_COSINE: u32 = 2u;
const FAULT_MIRROR_AZIMUTH: u32 = 4u;
const FAULT_SRGB_TWICE: u32 = 8u;
const FAULT_TRANSFER_MIRROR: u32 = 16u;
const FAULT_GAIN: u32 = 32u;
const FAULT_NEAREST_AZIMUTH: u32 = 64u;
const FAULT_DIFFUSE_NO_INV_PI: u32 = 128u;
// Bits 256-2048 are faults of the uploaded data (src/gpu/fault.rs), not tested here.
const FAULT_REFLECTION_PSI_SIGN: u32 = 4096u;

fn has_fault(bit: u32) -> bool {
    return (frame.ints.z & bit) != 0u;
}

// Shading frame (t, b, n): t = world up (+y) projected onto the tangent plane, b = n x t,
// right-handed; at n = +-y, t = (0, 0, -n.y) (conventions items 1-2).
struct ShadingFrame {
    t: vec3<f32>,
    b: vec3<f32>,
    n: vec3<f32>,
}

fn shading_frame(n: vec3<f32>) -> ShadingFrame {
    let s2 = n.x * n.x + n.z * n.z;
    var t: vec3<f32>;
    if s2 > 0.0 {
        let s = sqrt(s2);
        t = vec3<f32>(-n.x * n.y / s, s, -n.z * n.y / s);
    } else {
        t = vec3<f32>(0.0, 0.0, -sign(n.y));
    }
    var b = cross(n, t);
    if has_fault(FAULT_MIRROR_AZIMUTH) {
        // A left-handed frame: every azimuth turns into its mirror image 2 pi - azimuth.
        b = -b;
    }
    return ShadingFrame(t, b, n);
}

// The frame of n whose tangent is the mesh's tangent projected onto the tangent plane
// (src/conventions/mod.rs, "Frame of anisotropic materials"); `up` (n's world-up frame)
// where that projection is below MIN_TANGENT_SIN = 1e-3 of the tangent's length or the
// tangent is zero.
fn frame_from_tangent(up: ShadingFrame, tangent: vec3<f32>) -> ShadingFrame {
    let n = up.n;
    let along = tangent - n * dot(n, tangent);
    let l2 = dot(along, along);
    let t2 = dot(tangent, tangent);
    if !(l2 > 1e-6 * t2) {
        return up;
    }
    let t = along / sqrt(l2);
    var b = cross(n, t);
    if has_fault(FAULT_MIRROR_AZIMUTH) {
        b = -b;
    }
    return ShadingFrame(t, b, n);
}

// The frame turned about n so that the unit world view v has the azimuth whose cosine and
// sine are (c, s): t' = cos(phi - a) t + sin(phi - a) b with phi the view's azimuth in f;
// f itself when v is within 1e-6 of the normal's axis (VIEW_TURN_MIN_SIN).
fn turned_to_view(f: ShadingFrame, v: vec3<f32>, c: f32, s: f32) -> ShadingFrame {
    let x = dot(v, f.t);
    let y = dot(v, f.b);
    let h = sqrt(x * x + y * y);
    if !(h > 1e-6) {
        return f;
    }
    let cp = x / h;
    let sp = y / h;
    let ct = cp * c + sp * s;
    let st = sp * c - cp * s;
    return ShadingFrame(f.t * ct + f.b * st, f.b * ct - f.t * st, f.n);
}

fn to_local(f: ShadingFrame, d: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(dot(d, f.t), dot(d, f.b), dot(d, f.n));
}

// View direction lifted to at least MIN_VIEW_COS above the horizon, azimuth kept.
fn lift_above_horizon(w: vec3<f32>) -> vec3<f32> {
    if w.z >= MIN_VIEW_COS {
        return w;
    }
    let h = sqrt(w.x * w.x + w.y * w.y);
    if h <= 0.0 {
        return vec3<f32>(0.0, 0.0, 1.0);
    }
    let s = sqrt(1.0 - MIN_VIEW_COS * MIN_VIEW_COS);
    return vec3<f32>(w.x / h * s, w.y / h * s, MIN_VIEW_COS);
}

// Texture coordinates (s, t) of a hemispherical table for a local direction:
// s = azimuth / 2 pi with azimuth = atan2(y, x) in [0, 2 pi), t = polar / (pi / 2).
fn hemi_texcoord(w: vec3<f32>) -> vec2<f32> {
    let polar = acos(clamp(w.z, -1.0, 1.0));
    var az = atan2(w.y, w.x);
    if az < 0.0 {
        az = az + TAU;
    }
    if az >= TAU {
        az = 0.0;
    }
    return vec2<f32>(az / TAU, polar / (0.5 * PI));
}

// GL_NEAREST on an nu x nv table (OpenGL 4.6 core, 8.14.1, with the wrap modes of 8.14.2):
// azimuth GL_REPEAT, polar GL_CLAMP_TO_EDGE. Returns texel (i, j).
fn nearest_texel(st: vec2<f32>, nu: u32, nv: u32) -> vec2<u32> {
    var u = fract(st.x) * f32(nu);
    var v = st.y * f32(nv);
    if has_fault(FAULT_HALF_TEXEL) {
        // Texel values taken to sit on texel corners instead of centres.
        u = u + 0.5;
        v = v + 0.5;
    }
    let i = u32(floor(u)) % nu;
    let j = u32(clamp(floor(v), 0.0, f32(nv - 1u)));
    return vec2<u32>(i, j);
}

// GL_LINEAR on an nu x nv table: u = s nu - 1/2, v = t nv - 1/2 (the texel centres),
// i0 = floor(u), alpha = fract(u); azimuth indices wrap, polar indices clamp.
struct Bilinear {
    i0: u32,
    i1: u32,
    j0: u32,
    j1: u32,
    a: f32,
    b: f32,
}

fn bilinear_texels(st: vec2<f32>, nu: u32, nv: u32) -> Bilinear {
    var u = st.x * f32(nu) - 0.5;
    var v = st.y * f32(nv) - 0.5;
    if has_fault(FAULT_HALF_TEXEL) {
        u = u + 0.5;
        v = v + 0.5;
    }
    let uf = floor(u);
    let vf = floor(v);
    let ni = i32(nu);
    let i0 = ((i32(uf) % ni) + ni) % ni;
    let i1 = (i0 + 1) % ni;
    let j0 = clamp(i32(vf), 0, i32(nv) - 1);
    let j1 = clamp(i32(vf) + 1, 0, i32(nv) - 1);
    var a = u - uf;
    if has_fault(FAULT_NEAREST_AZIMUTH) {
        // Nearest on the azimuth axis: the weight snapped to the closer texel.
        a = round(a);
    }
    return Bilinear(u32(i0), u32(i1), u32(j0), u32(j1), a, v - vf);
}
