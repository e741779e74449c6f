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

// The pixel's SH coefficients sh_c, looked up in a frame turned by the angle whose cosine
// and sine are (c, s) from the world-up frame, rewritten in the world-up frame the table
// stores the environment in (src/sh/rotate.rs: for m > 0, c_m = c'_m cos(m angle) -
// c'_-m sin(m angle), c_-m = c'_m sin(m angle) + c'_-m cos(m angle)).
fn transfer_turned_back(c: f32, s: f32) -> array<vec3<f32>, SH_TERMS> {
    var out = sh_c;
    let bands = frame.table.z;
    var cm = 1.0;
    var sm = 0.0;
    for (var m = 1u; m < bands; m = m + 1u) {
        let next_c = cm * c - sm * s;
        sm = sm * c + cm * s;
        cm = next_c;
        for (var l = m; l < bands; l = l + 1u) {
            let kp = l * l + l + m;
            let kn = l * l + l - m;
            let p = out[kp];
            let q = out[kn];
            out[kp] = p * cm - q * sm;
            out[kn] = p * sm + q * cm;
        }
    }
    return out;
}

// sum_k c_k T_k(n) per colour, T bilinear in the normal's grid angles at the world unit
// normal n; (turn_c, turn_s): the unit pair of the angle from the world-up frame to the
// pixel's shading frame (1, 0 unless the material's frame is view-aligned).
fn transfer_radiance(n_world: vec3<f32>, turn_c: f32, turn_s: f32) -> vec3<f32> {
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
    var c = sh_c;
    if frame.ints.x == MAT_SH && frame.xfer_rot.w > 0.5 {
        c = transfer_turned_back(turn_c, turn_s);
    }
    // c_k(wo), the coefficients the table is dotted with: the pixel's SH coefficients at
    // its view (sh_c, filled by sh_lookup, turned back into the table's frame), or
    // albedo / pi for Lambert (one term).
    var out = vec3<f32>(0.0);
    for (var k = 0u; k < frame.xfer.z; k = k + 1u) {
        let t = w00 * transfer_node(n00, k) + w10 * transfer_node(n10, k)
            + w01 * transfer_node(n01, k) + w11 * transfer_node(n11, k);
        var ck = lambert(frame.kd.xyz);
        if frame.ints.x == MAT_SH {
            ck = c[k];
        }
        out = out + ck * t;
    }
    return out;
}
