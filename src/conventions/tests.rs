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
