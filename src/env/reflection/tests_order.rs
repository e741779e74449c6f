//! The order of the series in psi (`[env] reflection_order`, parent module doc, "Order of
//! the series in psi"): at the grid's nodes and slices, where the series is the table's
//! only approximation, a table of order 4 agrees with exact sums better than one of order
//! 2 (and 2 better than 1) under a probe of one bright texel, and a seeded fault in the
//! sine terms fails the same check at order 4; a cache entry of one order is never read
//! for another, and the default order's entry is what it was before the order was a
//! parameter; orders out of range name their field.

use super::build::{bake_table, downsample, radiance_sum, residual_power, sample_normal_view};
use super::build::{BakeFault, BakeParams};
use super::table::{chart_frame, chart_is_z, node_direction, slice_angle, MAX_ORDER};
use super::*;
use crate::brdf::BlinnPhong;
use crate::env::{LoadOptions, Probe};
use glam::{DVec3, Vec3};

/// Cells per side and uniform slices of the tables here: 25 nodes, 4 slices (a bake of a
/// few milliseconds at any order).
const GRID: usize = 4;
const SLICES: usize = 3;

/// A 32 x 16 probe, dim and constant but for one texel 4000 times brighter (off the axes).
/// At 32 texels wide the bake sums every texel itself (no pyramid level is that narrow),
/// so the exact sums below are the bake's.
fn one_texel_probe() -> Probe {
    let (w, h) = (32, 16);
    let mut texels = vec![[0.05f32, 0.05, 0.05]; w * h];
    texels[5 * w + 9] = [200.0, 180.0, 150.0];
    Probe::from_texels("one-texel", w, h, texels, &LoadOptions::default())
        .unwrap()
        .0
}

/// Blinn-Phong 50 without a Lambertian term: the table is the lobes' series alone (no
/// diffuse term over normals to interpolate).
fn lobe_only() -> Material {
    Material::BlinnPhong(BlinnPhong {
        kd: Vec3::ZERO,
        ks: Vec3::splat(0.9),
        exponent: 50.0,
    })
}

fn params(order: usize) -> BakeParams {
    BakeParams {
        grid: GRID,
        slices: SLICES,
        residual: 32,
        order,
    }
}

fn bake(probe: &Probe, m: &Material, p: BakeParams, fault: BakeFault) -> ReflectionTable {
    bake_table(
        probe,
        m,
        p,
        &[],
        1.0,
        &crate::progress::Progress::hidden(),
        fault,
    )
    .unwrap()
}

/// Relative RMSE (RGB, over every sample) of `table` against exact f64 sums over every
/// texel of `probe`, at every node's reflected direction, every slice's view angle but the
/// first (polar angle 0 has no psi) and 32 values of psi halfway between the bake's samples
/// of every order here (`2 pi (m + 1/2) / 32`).
fn error_at_nodes(table: &ReflectionTable, probe: &Probe, m: &Material) -> f64 {
    let (w, h) = (probe.width(), probe.height());
    let (_, texels) = downsample(&residual_power(probe, &[], 1.0), w, h, 1);
    let (mut se, mut sy) = (0.0, 0.0);
    for k in 0..(GRID + 1) * (GRID + 1) {
        let r = node_direction(k % (GRID + 1), k / (GRID + 1), GRID);
        let tb = chart_frame(r, chart_is_z(r));
        for s in 1..=SLICES {
            let polar = slice_angle(s, SLICES);
            for j in 0..32 {
                let psi = std::f64::consts::TAU * (j as f64 + 0.5) / 32.0;
                let (n, v) = sample_normal_view(r, polar, psi, tb);
                let exact = radiance_sum(m, false, DVec3::ZERO, n, v, &texels);
                let got = table.radiance(n.as_vec3(), v.as_vec3()).as_dvec3();
                se += (got - exact).length_squared();
                sy += exact.length_squared();
            }
        }
    }
    (se / sy).sqrt()
}

#[test]
fn a_higher_order_follows_psi_closer_and_a_sine_fault_fails_it() {
    let probe = one_texel_probe();
    let m = lobe_only();
    let err = |order, fault| error_at_nodes(&bake(&probe, &m, params(order), fault), &probe, &m);
    let (e1, e2, e4) = (
        err(1, BakeFault::None),
        err(2, BakeFault::None),
        err(4, BakeFault::None),
    );
    let f4 = err(4, BakeFault::SineTermsNegated);
    eprintln!(
        "rel RMSE at the nodes: order 1 {e1:.4}, 2 {e2:.4}, 4 {e4:.4}; 4 with the sine \
         terms negated {f4:.4}"
    );
    // Measured: 35.1%, 22.9%, 12.9%; the fault 72.4%.
    assert!(e2 < 0.8 * e1, "order 2 {e2} against order 1 {e1}");
    assert!(e4 < 0.7 * e2, "order 4 {e4} against order 2 {e2}");
    assert!(f4 > 2.0 * e4, "the fault passed: {f4} against {e4}");
}

#[test]
fn a_cache_entry_of_another_order_is_not_read() {
    let probe = one_texel_probe();
    let m = lobe_only();
    let (two, four) = (params(2), params(4));
    let t4 = bake(&probe, &m, four, BakeFault::None);
    assert_eq!(t4.order(), 4);
    assert_eq!(t4.values().len(), table::value_count(GRID, SLICES, 4));
    let tmp = tempfile::tempdir().unwrap();
    let path = cache::table_file_name(tmp.path(), 7);
    let bytes = cache::encode_entry(&t4, 7);
    std::fs::write(&path, &bytes).unwrap();
    assert_eq!(
        cache::read_entry(&path, 7, &four, 0.0),
        Ok(Some(t4.clone()))
    );
    let why = cache::read_entry(&path, 7, &two, 0.0).unwrap_err();
    assert!(
        why.contains("psi order 4") && why.contains("psi order 2"),
        "{why}"
    );
    // The header states an order off the default; the default's header states none (its
    // entry is byte for byte the one from before the order was a parameter) and reads
    // back as order 2.
    let header = |b: &[u8]| String::from_utf8(b.split(|&c| c == b'\n').next().unwrap().to_vec());
    assert!(header(&bytes).unwrap().contains("\"order\":4"));
    let t2 = bake(&probe, &m, two, BakeFault::None);
    let bytes2 = cache::encode_entry(&t2, 7);
    assert!(!header(&bytes2).unwrap().contains("order"));
    std::fs::write(&path, &bytes2).unwrap();
    assert_eq!(cache::read_entry(&path, 7, &two, 0.0), Ok(Some(t2)));
    assert!(cache::read_entry(&path, 7, &four, 0.0).is_err());
    // The key: every order its own.
    let o = LoadOptions::default();
    let keys: Vec<u64> = (1..=MAX_ORDER)
        .map(|order| cache::table_cache_key(b"probe", &o, &m, &params(order), 64, 1.0))
        .collect();
    for (i, a) in keys.iter().enumerate() {
        assert!(keys[i + 1..].iter().all(|b| b != a), "{keys:?}");
    }
}

#[test]
fn orders_out_of_range_name_their_field() {
    let probe = one_texel_probe();
    let m = lobe_only();
    for order in [0, MAX_ORDER + 1] {
        let e = bake_table(
            &probe,
            &m,
            params(order),
            &[],
            1.0,
            &crate::progress::Progress::hidden(),
            BakeFault::None,
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("env.reflection_order"), "{e}");
        assert_eq!(e.lines().count(), 1, "{e}");
    }
}
