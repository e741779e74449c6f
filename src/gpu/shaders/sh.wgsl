// Real spherical harmonics, orthonormal over the sphere, without the Condon-Shortley
// phase, index k = l^2 + l + m (src/conventions/mod.rs item 9; thesis 2.3.3, Def. 11),
// evaluated with the normalised associated-Legendre recurrence in the polynomial form
// Q_l^m = P_l^m / sin^m (no factorials, no atan2):
//   Q_0^0 = 1/sqrt(4 pi), Q_m^m = sqrt((2m+1)/(2m)) Q_{m-1}^{m-1},
//   Q_{m+1}^m = sqrt(2m+3) z Q_m^m,
//   Q_l^m = a_lm (z Q_{l-1}^m - b_lm Q_{l-2}^m), a_lm = sqrt((4l^2-1)/(l^2-m^2)),
//   b_lm = sqrt(((l-1)^2-m^2)/(4(l-1)^2-1));
// Y_l0 = Q_l^0, Y_lm = sqrt 2 Q_l^m Re((x+iy)^m), Y_l,-m = sqrt 2 Q_l^m Im((x+iy)^m).
// The sum over the view-dependent coefficients is taken as the basis is generated.

// sum_k c[k] Y_k(w) for the pixel's coefficients `sh_c` (private, filled by sh_lookup).
fn sh_sum(w: vec3<f32>) -> vec3<f32> {
    let bands = i32(frame.table.z);
    let z = w.z;
    var acc = vec3<f32>(0.0);
    var qmm = 0.28209479177387814; // 1 / sqrt(4 pi)
    var cre = 1.0; // Re((x + iy)^m)
    var cim = 0.0; // Im((x + iy)^m)
    for (var m = 0; m < bands; m = m + 1) {
        if m > 0 {
            let fm = f32(m);
            qmm = qmm * sqrt((2.0 * fm + 1.0) / (2.0 * fm));
            let re = cre * w.x - cim * w.y;
            cim = cre * w.y + cim * w.x;
            cre = re;
        }
        var q2 = 0.0; // Q_{l-2}^m
        var q1 = qmm; // Q_{l-1}^m, then Q_l^m
        for (var l = m; l < bands; l = l + 1) {
            var q = qmm;
            if l == m + 1 {
                q = sqrt(2.0 * f32(m) + 3.0) * z * qmm;
            } else if l > m + 1 {
                let fl = f32(l);
                let fm = f32(m);
                let a = sqrt((4.0 * fl * fl - 1.0) / (fl * fl - fm * fm));
                let b = sqrt(((fl - 1.0) * (fl - 1.0) - fm * fm) / (4.0 * (fl - 1.0) * (fl - 1.0) - 1.0));
                q = a * (z * q1 - b * q2);
            }
            if l > m {
                q2 = q1;
                q1 = q;
            }
            let k = l * l + l;
            if m == 0 {
                acc = acc + sh_c[k] * q;
            } else {
                acc = acc + sh_c[k + m] * (1.4142135623730951 * q * cre);
                acc = acc + sh_c[k - m] * (1.4142135623730951 * q * cim);
            }
        }
    }
    return acc;
}

// Coefficient texel (i, j), colour c, term k of the table: coeffs[((j nu + i) 3 + c) T + k].
fn sh_coeff(i: u32, j: u32, k: u32) -> vec3<f32> {
    let base = ((j * frame.table.x + i) * 3u) * SH_TERMS + k;
    return vec3<f32>(table[base], table[base + SH_TERMS], table[base + 2u * SH_TERMS]);
}

// Fills sh_c with the coefficients at view direction wo, filtered as frame.ints.w says
// (0: GL_NEAREST, 1: GL_LINEAR).
fn sh_lookup(wo: vec3<f32>) {
    let nu = frame.table.x;
    let nv = frame.table.y;
    let st = hemi_texcoord(wo);
    if frame.ints.w == 0u {
        let ij = nearest_texel(st, nu, nv);
        for (var k = 0u; k < SH_TERMS; k = k + 1u) {
            sh_c[k] = sh_coeff(ij.x, ij.y, k);
        }
    } else {
        let bl = bilinear_texels(st, nu, nv);
        let w00 = (1.0 - bl.a) * (1.0 - bl.b);
        let w10 = bl.a * (1.0 - bl.b);
        let w01 = (1.0 - bl.a) * bl.b;
        let w11 = bl.a * bl.b;
        for (var k = 0u; k < SH_TERMS; k = k + 1u) {
            sh_c[k] = w00 * sh_coeff(bl.i0, bl.j0, k) + w10 * sh_coeff(bl.i1, bl.j0, k)
                + w01 * sh_coeff(bl.i0, bl.j1, k) + w11 * sh_coeff(bl.i1, bl.j1, k);
        }
    }
}
