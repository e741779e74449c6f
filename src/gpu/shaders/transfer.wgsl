// The transfer-table term of `[env] method = "transfer"`, written from the module doc of
// src/env/transfer/mod.rs (L_o(n, wo) = sum_k c_k(wo) T_k(n) per colour; "Grid of normals")
// and the probe convention of src/conventions/mod.rs ("Light probes": the direction of
// polar p from +y and probe azimuth a is (-sin p sin a, cos p, sin p cos a); a probe
// rotation r turns the environment about +y by r, right-handed). Not translated from the
// CPU's TransferTable lookup.
//
// frame.xfer: nu (azimuth nodes, wrapping), nv (polar nodes, both poles included), terms
// per colour, 1 when the scene has a table; frame.xfer_rot.x: the probe rotation r.
// Node (i, j) holds T for the normal of polar pi j / (nv - 1) and probe azimuth
// 2 pi i / nu, in that node's shading frame, at transfer[((j nu + i) 3 + colour) terms + k].

@group(0) @binding(5) var<storage, read> transfer: array<f32>;

// The world normal n seen in the probe's own frame: the environment was turned by r about
// +y, so n is turned back by -r (R_y(-r): x' = x cos r - z sin r, z' = x sin r + z cos r).
fn probe_frame(n: vec3<f32>) -> vec3<f32> {
    let r = frame.xfer_rot.x;
    let c = cos(r);
    let s = sin(r);
    return vec3<f32>(n.x * c - n.z * s, n.y, n.x * s + n.z * c);
}

// T_k of node `node`, the three colours.
fn transfer_node(node: u32, k: u32) -> vec3<f32> {
    let terms = frame.xfer.z;
    let base = node * 3u * terms + k;
    return vec3<f32>(transfer[base], transfer[base + terms], transfer[base + 2u * terms]);
}

// The coefficient c_k(wo) the table is dotted with: the pixel's SH coefficients at its
// view (sh_c, filled by sh_lookup), or albedo / pi for Lambert (one term).
fn transfer_coeff(k: u32) -> vec3<f32> {
    if frame.ints.x == MAT_SH {
        return sh_c[k];
    }
    return lambert(frame.kd.xyz);
}

// sum_k c_k T_k(n) per colour, T bilinear in the normal's grid angles at the world unit
// normal n.
fn transfer_radiance(n_world: vec3<f32>) -> vec3<f32> {
    let nu = frame.xfer.x;
    let nv = frame.xfer.y;
    let n = probe_frame(n_world);
    // Polar angle from +y, and the azimuth a solving (n.x, n.z) = sin p (-sin a, cos a).
    let polar = acos(clamp(n.y, -1.0, 1.0));
    var az = atan2(-n.x, n.z);
    if has_fault(FAULT_TRANSFER_MIRROR) {
        // The probe's azimuth taken with the opposite sign (a port that reads the
        // direction as (sin p sin a, ., .)): the table is read at 2 pi - a.
        az = atan2(n.x, n.z);
    }
    if az < 0.0 {
        az = az + TAU;
    }
    // Continuous node coordinates: azimuth wraps (node nu is node 0); the poles are rows 0
    // and nv - 1, so the polar coordinate needs no clamping but the last cell's.
    let x = az / TAU * f32(nu);
    let y = polar / PI * f32(nv - 1u);
    let xf = floor(x);
    let i0 = u32(xf) % nu;
    let i1 = (i0 + 1u) % nu;
    let j0 = min(u32(max(floor(y), 0.0)), nv - 2u);
    let j1 = j0 + 1u;
    let fx = x - xf;
    let fy = clamp(y - f32(j0), 0.0, 1.0);
    let n00 = j0 * nu + i0;
    let n10 = j0 * nu + i1;
    let n01 = j1 * nu + i0;
    let n11 = j1 * nu + i1;
    let w00 = (1.0 - fx) * (1.0 - fy);
    let w10 = fx * (1.0 - fy);
    let w01 = (1.0 - fx) * fy;
    let w11 = fx * fy;
    var out = vec3<f32>(0.0);
    for (var k = 0u; k < frame.xfer.z; k = k + 1u) {
        let t = w00 * transfer_node(n00, k) + w10 * transfer_node(n10, k)
            + w01 * transfer_node(n01, k) + w11 * transfer_node(n11, k);
        out = out + transfer_coeff(k) * t;
    }
    return out;
}
