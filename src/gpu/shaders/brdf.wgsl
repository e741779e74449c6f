// The analytic models and the D-BRDF, f_r(wi, wo) in 1/sr in the local shading frame
// (+z the normal), written from the thesis (Defs. 3, 4; 2.3.6) with the normalisations of
// src/conventions/mod.rs items 6-7. Zero below either horizon (thesis 3.1.2).

fn lambert(albedo: vec3<f32>) -> vec3<f32> {
    if has_fault(FAULT_DIFFUSE_NO_INV_PI) {
        return albedo;
    }
    return albedo / PI;
}

// Normalised Phong: k_d / pi + k_s (a + 2) / (2 pi) max(0, r.wo)^a, r = wi mirrored about n.
fn phong(wi: vec3<f32>, wo: vec3<f32>, kd: vec3<f32>, ks: vec3<f32>, a: f32) -> vec3<f32> {
    let r = vec3<f32>(-wi.x, -wi.y, wi.z);
    let rv = max(dot(r, wo), 0.0);
    return kd / PI + ks * ((a + 2.0) / (2.0 * PI) * pow(rv, a));
}

// Normalised Blinn-Phong: k_d / pi + k_s (a + 8) / (8 pi) (n.h)^a, h = normalize(wi + wo).
fn blinn_phong(wi: vec3<f32>, wo: vec3<f32>, kd: vec3<f32>, ks: vec3<f32>, a: f32) -> vec3<f32> {
    let sum = wi + wo;
    let len = length(sum);
    var nh = 0.0;
    if len > 0.0 {
        nh = max(sum.z / len, 0.0);
    }
    return kd / PI + ks * ((a + 8.0) / (8.0 * PI) * pow(nh, a));
}

// Schlick's Fresnel with RGB reflectance rs at normal incidence.
fn schlick(rs: vec3<f32>, c: f32) -> vec3<f32> {
    let m = pow(1.0 - clamp(c, 0.0, 1.0), 5.0);
    return rs + (vec3<f32>(1.0) - rs) * m;
}

// The half-vector distribution p(h) of a D-BRDF: its table bilinearly filtered.
fn dbrdf_p(h: vec3<f32>) -> f32 {
    let nu = frame.table.x;
    let nv = frame.table.y;
    let bl = bilinear_texels(hemi_texcoord(h), nu, nv);
    let p00 = table[bl.j0 * nu + bl.i0];
    let p10 = table[bl.j0 * nu + bl.i1];
    let p01 = table[bl.j1 * nu + bl.i0];
    let p11 = table[bl.j1 * nu + bl.i1];
    return mix(mix(p00, p10, bl.a), mix(p01, p11, bl.a), bl.b);
}

// D-BRDF (Ashikhmin & Premoze): c p(h) F(k.h) / (k1.n + k2.n - (k1.n)(k2.n)).
fn dbrdf(wi: vec3<f32>, wo: vec3<f32>, rs: vec3<f32>, c: f32) -> vec3<f32> {
    let sum = wi + wo;
    let len = length(sum);
    if len <= 1e-6 {
        return vec3<f32>(0.0);
    }
    let h = sum / len;
    let a = min(wi.z, 1.0);
    let b = min(wo.z, 1.0);
    let kh = clamp(0.5 * len, 0.0, 1.0);
    return c * dbrdf_p(h) * schlick(rs, kh) / (a + b - a * b);
}
