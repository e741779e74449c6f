// The reflection-space table term of `[env] method = "reflection"` (isotropic materials),
// written from the module doc of src/env/reflection/mod.rs ("Parameterisation", "Diffuse
// term"), the layout stated on `ReflectionTable` (src/env/reflection/table.rs) and the
// sphere grid of src/conventions/mod.rs ("Octahedral sphere grids"). Not translated from
// the CPU's `ReflectionTable::radiance`.
//
// frame.refl: G (cells per side of the octahedral grid, (G + 1)^2 vertices), S (uniform
// view slices; one horizon slice follows them), the index where the diffuse term starts
// (the lobes' value count), 1 when the scene has a table; frame.refl_rot.x: the probe
// rotation r (radians: the environment turned by r about +y, right-handed).
// Vertex (i, j) sits at octahedral (u, v) = (-1 + 2 i / G, -1 + 2 j / G), node j (G + 1) + i.
// Lobes: the C = 2 REFL_ORDER + 1 Fourier coefficients (a0, a1, b1, ..., a_order, b_order)
// of node, slice s, colour c at reflection[((node (S + 1) + s) 3 + c) C + k]; diffuse term
// c E(n): the diffuse start + node 3 + c. REFL_ORDER, the order of the series in psi
// (`[env] reflection_order`, default 2), is defined by the header src/gpu/pipeline.rs
// puts before these files.

@group(0) @binding(6) var<storage, read> reflection: array<f32>;

// Fourier coefficients per (node, slice, colour): order REFL_ORDER in psi.
const REFL_COEFFS: u32 = 2u * REFL_ORDER + 1u;
// The view's polar angle of the last uniform slice, 85 degrees, and of the horizon slice,
// 89.9 degrees, in radians.
const REFL_LAST_UNIFORM: f32 = 1.4835298641951802;
const REFL_HORIZON: f32 = 1.5690509975429023;
// |r.y| of a node above which its psi is measured from +z instead of +y.
const REFL_CHART_SWITCH: f32 = 0.8;

// A world direction seen in the probe's own frame: the environment was turned by r about
// +y, so the direction is turned by -r (R_y(-r): x' = x cos r - z sin r,
// z' = x sin r + z cos r).
fn refl_probe_frame(d: vec3<f32>) -> vec3<f32> {
    let r = frame.refl_rot.x;
    let c = cos(r);
    let s = sin(r);
    return vec3<f32>(d.x * c - d.z * s, d.y, d.x * s + d.z * c);
}

// +1 for x >= 0 (the sphere grid's sign, which takes 0 as positive), else -1.
fn refl_sign(x: f32) -> f32 {
    return select(-1.0, 1.0, x >= 0.0);
}

// Octahedral coordinates of a direction, +y at the centre: (x, z) / (|x| + |y| + |z|) on the
// upper half, folded to ((1 - |v|) sign u, (1 - |u|) sign v) on the lower half (-y: the
// four corners).
fn refl_oct_encode(d: vec3<f32>) -> vec2<f32> {
    let l1 = abs(d.x) + abs(d.y) + abs(d.z);
    let u = d.x / l1;
    let v = d.z / l1;
    if d.y >= 0.0 {
        return vec2<f32>(u, v);
    }
    return vec2<f32>((1.0 - abs(v)) * refl_sign(u), (1.0 - abs(u)) * refl_sign(v));
}

// The unit direction of vertex `node` (the inverse map: y = 1 - |u| - |v|, and on the lower
// half x = (1 - |v|) sign u, z = (1 - |u|) sign v).
fn refl_node_direction(node: u32) -> vec3<f32> {
    let g = frame.refl.x;
    let i = node % (g + 1u);
    let j = node / (g + 1u);
    let u = -1.0 + 2.0 * f32(i) / f32(g);
    let v = -1.0 + 2.0 * f32(j) / f32(g);
    let y = 1.0 - abs(u) - abs(v);
    var d = vec3<f32>(u, y, v);
    if y < 0.0 {
        d = vec3<f32>((1.0 - abs(v)) * refl_sign(u), y, (1.0 - abs(u)) * refl_sign(v));
    }
    return normalize(d);
}

// The four vertices around a unit direction and their bilinear weights: vertex coordinate
// (u + 1) G / 2 clamped to [0, G], the cell's lower vertex at most G - 1.
struct ReflCorners {
    node: array<u32, 4>,
    weight: array<f32, 4>,
}

fn refl_corners(d: vec3<f32>) -> ReflCorners {
    let g = frame.refl.x;
    let uv = refl_oct_encode(d);
    let f = clamp((uv + vec2<f32>(1.0)) * 0.5 * f32(g), vec2<f32>(0.0), vec2<f32>(f32(g)));
    let i0 = min(u32(floor(f.x)), g - 1u);
    let j0 = min(u32(floor(f.y)), g - 1u);
    let a = f.x - f32(i0);
    let b = f.y - f32(j0);
    let row = g + 1u;
    var out: ReflCorners;
    out.node = array<u32, 4>(j0 * row + i0, j0 * row + i0 + 1u, (j0 + 1u) * row + i0, (j0 + 1u) * row + i0 + 1u);
    out.weight = array<f32, 4>((1.0 - a) * (1.0 - b), a * (1.0 - b), (1.0 - a) * b, a * b);
    return out;
}

// The Fourier basis (1, cos psi, sin psi, ..., cos(REFL_ORDER psi), sin(REFL_ORDER psi))
// of the normal n about the reflected direction r in the chart whose axis is +z (z_chart)
// or +y: t = the axis projected normal to r, b = r x t, psi the angle of n's component
// normal to r from t towards b; (1, 1, 0, 1, 0, ...) when n is along r. cos 2 psi and
// sin 2 psi as c^2 - s^2 and 2 c s, higher orders by angle addition from the one below.
fn refl_psi_basis(n: vec3<f32>, r: vec3<f32>, cos_o: f32, z_chart: bool) -> array<f32, REFL_COEFFS> {
    var axis = vec3<f32>(0.0, 1.0, 0.0);
    if z_chart {
        axis = vec3<f32>(0.0, 0.0, 1.0);
    }
    let ta = axis - dot(axis, r) * r;
    let tl = length(ta);
    var t = vec3<f32>(1.0, 0.0, 0.0);
    if tl > 0.0 {
        t = ta / tl;
    }
    let b = cross(r, t);
    let d = n - cos_o * r;
    let x = dot(d, t);
    var y = dot(d, b);
    if has_fault(FAULT_REFLECTION_PSI_SIGN) {
        // psi measured the other way round (b taken as t x r).
        y = -y;
    }
    let len = sqrt(x * x + y * y);
    var c = 1.0;
    var s = 0.0;
    if len > 1e-12 {
        c = x / len;
        s = y / len;
    }
    var q: array<f32, REFL_COEFFS>;
    q[0] = 1.0;
    var ck = c;
    var sk = s;
    for (var k = 1u; k <= REFL_ORDER; k = k + 1u) {
        if k == 2u {
            ck = c * c - s * s;
            sk = 2.0 * c * s;
        } else if k > 2u {
            let cn = ck * c - sk * s;
            sk = sk * c + ck * s;
            ck = cn;
        }
        q[2u * k - 1u] = ck;
        q[2u * k] = sk;
    }
    return q;
}

// The series of one (node, slice) in the three colours at the basis q.
fn refl_series(node: u32, slice: u32, q: array<f32, REFL_COEFFS>) -> vec3<f32> {
    let slices = frame.refl.y + 1u;
    let at = (node * slices + slice) * 3u * REFL_COEFFS;
    var out = vec3<f32>(0.0);
    for (var c = 0u; c < 3u; c = c + 1u) {
        let base = at + c * REFL_COEFFS;
        var sum = 0.0;
        for (var k = 0u; k < REFL_COEFFS; k = k + 1u) {
            sum = sum + reflection[base + k] * q[k];
        }
        out[c] = sum;
    }
    return out;
}

// The table's radiance at the unit world normal n_world and unit world view v_world (the
// view lifted above the horizon, as every other term sees it): in the probe's frame, the
// lobes' series bilinear over the four vertices around r = 2 (n.v) n - v, linear between
// the two slices around the view's polar angle acos(n.v) (slices 0..S-1 uniform over 0-85
// degrees, slice S at 89.9, clamped there), each vertex's series at psi measured in its own
// chart (+z where |y| of the vertex's direction exceeds 0.8, else +y); plus the diffuse
// term bilinear over the four vertices around n.
fn reflection_radiance(n_world: vec3<f32>, v_world: vec3<f32>) -> vec3<f32> {
    let n = refl_probe_frame(n_world);
    let v = refl_probe_frame(v_world);
    let cos_o = clamp(dot(n, v), 0.0, 1.0);
    let rr = 2.0 * cos_o * n - v;
    let rl = length(rr);
    var r = n;
    if rl > 0.0 {
        r = rr / rl;
    }
    // The two slices and the second's weight.
    let slices = frame.refl.y;
    let polar = acos(cos_o);
    var s0 = slices - 1u;
    var ws = 0.0;
    if polar < REFL_LAST_UNIFORM {
        let f = polar / REFL_LAST_UNIFORM * f32(slices - 1u);
        s0 = min(u32(floor(f)), slices - 2u);
        ws = f - f32(s0);
    } else {
        ws = min((polar - REFL_LAST_UNIFORM) / (REFL_HORIZON - REFL_LAST_UNIFORM), 1.0);
    }
    let basis_y = refl_psi_basis(n, r, cos_o, false);
    let basis_z = refl_psi_basis(n, r, cos_o, true);
    var out = vec3<f32>(0.0);
    let lobe = refl_corners(r);
    for (var k = 0u; k < 4u; k = k + 1u) {
        let node = lobe.node[k];
        var q = basis_y;
        if abs(refl_node_direction(node).y) > REFL_CHART_SWITCH {
            q = basis_z;
        }
        let series = (1.0 - ws) * refl_series(node, s0, q) + ws * refl_series(node, s0 + 1u, q);
        out = out + lobe.weight[k] * series;
    }
    let diffuse = refl_corners(n);
    for (var k = 0u; k < 4u; k = k + 1u) {
        let at = frame.refl.z + diffuse.node[k] * 3u;
        out = out + diffuse.weight[k] * vec3<f32>(reflection[at], reflection[at + 1u], reflection[at + 2u]);
    }
    return out;
}
