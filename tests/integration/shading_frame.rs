//! Property tests of the shading frame (conventions): orthonormal, right-handed, no NaN,
//! angles in range, for random normals including exactly +-up and within 1e-7 of it, and
//! directions down to grazing.

use brdfkit::conventions::{local_angles, local_direction, ShadingFrame};
use glam::Vec3;
use proptest::prelude::*;
use std::f32::consts::FRAC_PI_2;

fn unit(v: Vec3) -> Vec3 {
    v.try_normalize().unwrap_or(Vec3::Y)
}

fn normal_strategy() -> impl Strategy<Value = Vec3> {
    prop_oneof![
        // Random directions.
        (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0).prop_map(|(x, y, z)| unit(Vec3::new(x, y, z))),
        // Exactly +-up.
        Just(Vec3::Y),
        Just(-Vec3::Y),
        // Within 1e-7 (and less) of +-up.
        (-1e-7f32..1e-7, -1e-7f32..1e-7, prop::bool::ANY).prop_map(|(x, z, s)| unit(Vec3::new(
            x,
            if s { 1.0 } else { -1.0 },
            z
        ))),
        (-1e-30f32..1e-30, -1e-30f32..1e-30).prop_map(|(x, z)| Vec3::new(x, 1.0, z)),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(4000))]

    #[test]
    fn frame_is_orthonormal(n in normal_strategy()) {
        let f = ShadingFrame::from_normal(n);
        for v in [f.t, f.b, f.n] {
            prop_assert!(v.is_finite());
            prop_assert!((v.length() - 1.0).abs() < 1e-5, "{v:?} not unit for n = {n:?}");
        }
        prop_assert!(f.t.dot(f.b).abs() < 1e-5 && f.t.dot(f.n).abs() < 1e-5 && f.b.dot(f.n).abs() < 1e-5, "not orthogonal for n = {n:?}: {f:?}");
        prop_assert!(f.t.cross(f.b).distance(f.n) < 1e-5, "not right-handed for n = {n:?}");
        // Azimuth 0 is up projected onto the tangent plane (when that projection exists).
        let up_t = Vec3::Y - n * n.y;
        if up_t.length() > 1e-3 {
            prop_assert!(f.t.distance(up_t.normalize()) < 1e-4);
        }
    }

    #[test]
    fn angles_in_range_down_to_grazing(
        n in normal_strategy(),
        polar in prop_oneof![
            0.0f32..FRAC_PI_2,
            Just(FRAC_PI_2),
            (FRAC_PI_2 - 1e-4)..FRAC_PI_2,
            Just(0.0f32)
        ],
        azimuth in 0.0f32..std::f32::consts::TAU,
    ) {
        let f = ShadingFrame::from_normal(n);
        let world = f.to_world(local_direction(polar, azimuth));
        let (p, a) = local_angles(f.to_local(world));
        prop_assert!(p.is_finite() && a.is_finite());
        prop_assert!((0.0..=std::f32::consts::PI).contains(&p));
        prop_assert!((0.0..std::f32::consts::TAU).contains(&a), "azimuth {a} out of [0, 2pi)");
        prop_assert!((p - polar).abs() < 2e-3, "polar {polar} came back as {p}");
        if polar > 1e-2 {
            let d = (a - azimuth).abs();
            prop_assert!(d.min(std::f32::consts::TAU - d) < 2e-3, "azimuth {azimuth} came back as {a}");
        }
    }
}

#[test]
fn azimuth_distinguishes_mirror_directions() {
    // The thesis's acos folds azimuth x and -x together; ours does not.
    let f = ShadingFrame::from_normal(Vec3::Z);
    let (_, a1) = local_angles(f.to_local(Vec3::new(0.5, 0.5, 0.7).normalize()));
    let (_, a2) = local_angles(f.to_local(Vec3::new(-0.5, 0.5, 0.7).normalize()));
    assert!((a1 - a2).abs() > 1.0, "{a1} vs {a2}");
    assert!((a1 + a2 - std::f32::consts::TAU).abs() < 1e-5);
}
