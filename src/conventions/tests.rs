use super::*;

#[test]
fn frame_is_orthonormal_right_handed() {
    for n in [
        Vec3::Y,
        -Vec3::Y,
        Vec3::X,
        Vec3::new(1e-8, 1.0, 0.0),
        Vec3::new(0.3, -0.2, 0.9),
    ] {
        let f = ShadingFrame::from_normal(n);
        assert!((f.t.length() - 1.0).abs() < 1e-6);
        assert!((f.b.length() - 1.0).abs() < 1e-6);
        assert!(f.t.dot(f.n).abs() < 1e-6);
        assert!(f.t.cross(f.b).distance(f.n) < 1e-5);
    }
}

#[test]
fn up_has_azimuth_zero() {
    let n = Vec3::new(0.0, 0.0, 1.0);
    let f = ShadingFrame::from_normal(n);
    let (_, a) = local_angles(f.to_local(Vec3::new(0.0, 1.0, 1.0).normalize()));
    assert!(a.abs() < 1e-6);
}

#[test]
fn probe_axes() {
    let d = probe_direction(0.5, 0.5);
    assert!(d.distance(DVec3::NEG_Z) < 1e-12);
    let d = probe_direction(0.75, 0.5);
    assert!(d.distance(DVec3::X) < 1e-12);
    let d = probe_direction(0.0, 0.5);
    assert!(d.distance(DVec3::Z) < 1e-12);
    assert!(probe_direction(0.3, 0.0).distance(DVec3::Y) < 1e-12);
    let (u, v) = probe_uv(probe_direction(0.3, 0.7));
    assert!((u - 0.3).abs() < 1e-12 && (v - 0.7).abs() < 1e-12);
}

#[test]
fn probe_rows_sum_to_sphere() {
    let (w, h) = (7, 5);
    let total: f64 = (0..h)
        .map(|r| probe_texel_solid_angle(r, w, h) * w as f64)
        .sum();
    assert!((total - 4.0 * std::f64::consts::PI).abs() < 1e-12);
    assert!(probe_texel_solid_angle(0, w, h) > 0.0);
}

#[test]
fn rotation_turns_z_towards_x_and_texels_round_trip() {
    let d = rotate_about_up(DVec3::Z, std::f64::consts::FRAC_PI_2);
    assert!(d.distance(DVec3::X) < 1e-12);
    let (w, h) = (9, 4);
    for row in 0..h {
        for col in 0..w {
            let (u, v) = (texel_center_f64(col, w), texel_center_f64(row, h));
            let (u2, v2) = probe_uv(probe_direction(u, v));
            assert_eq!(probe_texel(u2, v2, w, h), (row, col));
        }
    }
}

/// The pole: atan2 of signed zeros, as the doc of [`local_angles`] says (the sign of x
/// decides; 0 and pi are the only values).
#[test]
fn local_angles_at_the_pole() {
    for z in [1.0f32, -1.0] {
        for (x, y, want) in [
            (0.0f32, 0.0f32, 0.0f32),
            (0.0, -0.0, 0.0),
            (-0.0, 0.0, std::f32::consts::PI),
            (-0.0, -0.0, std::f32::consts::PI),
        ] {
            let (polar, azimuth) = local_angles(Vec3::new(x, y, z));
            assert_eq!(polar, if z > 0.0 { 0.0 } else { std::f32::consts::PI });
            assert_eq!(azimuth, want, "x = {x:?}, y = {y:?}, z = {z}");
            assert!((0.0..std::f32::consts::TAU).contains(&azimuth));
        }
    }
}

/// The octahedral hemisphere map: decode then encode is the identity on the square, encode
/// then decode on the hemisphere, and encode ignores the length of its input.
#[test]
fn octahedral_map_round_trips() {
    let n = 97;
    for b in 0..=n {
        for a in 0..=n {
            let u = -1.0 + 2.0 * a as f64 / n as f64;
            let v = -1.0 + 2.0 * b as f64 / n as f64;
            let d = hemi_oct_decode_f64(u, v);
            assert!(
                (d.length() - 1.0).abs() < 1e-12 && d.z >= 0.0,
                "{u} {v}: {d}"
            );
            let (u2, v2) = hemi_oct_encode_f64(d * 3.7);
            assert!((u2 - u).abs() < 1e-12 && (v2 - v).abs() < 1e-12, "{u} {v}");
            let (u3, v3) = hemi_oct_encode(d.as_vec3() * 0.25);
            assert!((u3 as f64 - u).abs() < 1e-6 && (v3 as f64 - v).abs() < 1e-6);
        }
    }
    for k in 0..2000 {
        let polar = (k as f64 * 0.618_034).fract() * std::f64::consts::FRAC_PI_2;
        let az = (k as f64 * 0.414_214).fract() * std::f64::consts::TAU;
        let d = local_direction_f64(polar, az);
        let (u, v) = hemi_oct_encode_f64(d);
        assert!(u.abs() <= 1.0 && v.abs() <= 1.0);
        assert!((hemi_oct_decode_f64(u, v) - d).length() < 1e-12, "{d}");
    }
    // Centre and fallbacks.
    assert_eq!(hemi_oct_encode(Vec3::Z), (0.0, 0.0));
    assert_eq!(hemi_oct_encode(Vec3::ZERO), (0.0, 0.0));
}

/// Coverage and continuity: the horizon is the square's boundary (max(|u|, |v|) = 1 exactly
/// at z = 0) and the normal its centre; a small step on the hemisphere is a small step in
/// the square and back (the map is Lipschitz both ways: the cone bound of the D-BRDF uses
/// `|dh| <= sqrt(9/2) |d(u, v)|`, checked here by finite differences).
#[test]
fn octahedral_map_covers_the_hemisphere_continuously() {
    for k in 0..360 {
        let az = k as f64 * std::f64::consts::TAU / 360.0;
        let (u, v) = hemi_oct_encode_f64(local_direction_f64(std::f64::consts::FRAC_PI_2, az));
        assert!((u.abs().max(v.abs()) - 1.0).abs() < 1e-12, "{az}: {u} {v}");
    }
    let mut worst = 0.0f64;
    let n = 400;
    let step = 1e-4;
    for b in 0..n {
        for a in 0..n {
            let u = -1.0 + (a as f64 + 0.37) * 2.0 / n as f64;
            let v = -1.0 + (b as f64 + 0.61) * 2.0 / n as f64;
            let d0 = hemi_oct_decode_f64(u, v);
            for (du, dv) in [(step, 0.0), (0.0, step), (step, step), (step, -step)] {
                let d1 = hemi_oct_decode_f64(u + du, v + dv);
                let ratio = (d1 - d0).length() / (du * du + dv * dv).sqrt();
                worst = worst.max(ratio);
            }
        }
    }
    assert!(worst <= 4.5f64.sqrt(), "stretch {worst}");
    assert!(worst > 1.0, "stretch {worst}");
}

/// The octahedral `GL_LINEAR` texels: weights sum to 1, texel centres give their texel
/// alone, coordinates beyond the edge centres clamp (the edge texels' values), and the f32
/// and f64 forms agree.
#[test]
fn octahedral_texels_follow_gl_linear_clamp_to_edge() {
    let n = 8;
    for i in 0..n {
        let c = hemi_oct_texel_center_f64(i, n) as f32;
        let cu = hemi_oct_texel_coord(c, n);
        assert!((cu - i as f32).abs() < 1e-6, "{i}: {cu}");
        let t = hemi_oct_bilinear_texels(cu, cu, n);
        let w: f32 = t.iter().filter(|x| x.0 == i && x.1 == i).map(|x| x.2).sum();
        assert!((w - 1.0).abs() < 1e-6, "{i}: {t:?}");
    }
    assert_eq!(hemi_oct_texel_coord(-1.0, n), 0.0);
    assert_eq!(hemi_oct_texel_coord(1.0, n), 7.0);
    assert_eq!(hemi_oct_texel_coord(f32::NAN, n), 0.0);
    for k in 0..500 {
        let u = -1.0 + 2.0 * (k as f32 * 0.618_034).fract();
        let v = -1.0 + 2.0 * (k as f32 * 0.754_877).fract();
        let t = hemi_oct_bilinear_texels(hemi_oct_texel_coord(u, n), hemi_oct_texel_coord(v, n), n);
        let t64 = hemi_oct_bilinear_texels_f64(u as f64, v as f64, n);
        let s: f32 = t.iter().map(|x| x.2).sum();
        assert!((s - 1.0).abs() < 1e-6);
        for (a, b) in t.iter().zip(&t64) {
            assert!(a.0 < n && a.1 < n);
            assert_eq!((a.0, a.1), (b.0, b.1));
            assert!((a.2 as f64 - b.2).abs() < 1e-5);
        }
    }
}
