//! Tests of the sweep grid ([`super`]): enumeration order, fitting to a material, names.
use super::*;

#[test]
fn grid_order_and_size() {
    let g = Grid::default();
    // lights: 5 samplers x 11 counts; transfer: 3 grids x 3 exact counts; lightcuts: 4 cut
    // errors x 1 largest cut; reflection: 2 grids x 3 exact counts; x 8 x 2 (before the
    // grid is fitted to a material).
    assert_eq!(g.len(), (55 + 9 + 4 + 6) * 16);
    let c = g.configs();
    assert_eq!(c.len(), g.len());
    assert!(c.iter().enumerate().all(|(i, c)| c.index == i));
    // precision innermost, then lookup, order, the method's parameters; method outermost
    assert_eq!(c[1].lookup, Some(Lookup::Bilinear));
    assert_eq!(c[2].order, 2);
    let lights = |s, n| MethodAxis::Lights {
        sampler: s,
        count: n,
    };
    assert_eq!(c[16].method, lights(SamplerKind::Uniform, 2));
    assert_eq!(c[176].method, lights(SamplerKind::Importance, 1));
    // The lights rows keep the indices of a lights-only grid (the CSVs before methods).
    assert_eq!(c[831].method, lights(SamplerKind::Lloyd, 128));
    assert_eq!((c[831].order, c[831].lookup), (8, Some(Lookup::Bilinear)));
    let transfer = |a, p, k| MethodAxis::Transfer {
        azimuth: a,
        polar: p,
        exact_lights: k,
    };
    assert_eq!(c[880].method, transfer(32, 17, 0));
    assert_eq!(c[880 + 16].method, transfer(32, 17, 16));
    assert_eq!(c[880 + 48].method, transfer(64, 33, 0));
    assert_eq!(c[1023].method, transfer(128, 65, 64));
    let cuts = |e, m| MethodAxis::Lightcuts {
        cut_error: e,
        cut_max: m,
    };
    assert_eq!(c[1024].method, cuts(0.005, 1000));
    assert_eq!(c[1024 + 63].method, cuts(0.05, 1000));
    let reflection = |grid, k| MethodAxis::Reflection {
        grid,
        exact_lights: k,
    };
    assert_eq!(c[1024 + 64].method, reflection(32, 0));
    assert_eq!(c.last().unwrap().method, reflection(64, 64));
    let only = Grid {
        methods: vec![MethodKind::Transfer],
        ..Grid::default()
    };
    assert_eq!(only.len(), 9 * 16);
    assert_eq!(only.configs()[0].method, transfer(32, 17, 0));
}

#[test]
fn fit_material_drops_orders_and_methods() {
    let all = |_: MethodKind| None;
    let no_transfer = |m: MethodKind| {
        (m == MethodKind::Transfer).then(|| "shades SH data sets and Lambert only".to_string())
    };
    let mut g = Grid::default();
    assert!(g.fit_material(Some(5), all).unwrap().is_empty());
    assert_eq!(g.orders, vec![1, 2, 3, 4, 5]);
    let mut g = Grid::default();
    g.fit_material(None, all).unwrap();
    assert_eq!((g.orders.clone(), g.lookups.clone()), (vec![0], vec![None]));
    assert_eq!(g.methods, MethodKind::ALL.to_vec());
    let mut g = Grid {
        orders: vec![9],
        ..Grid::default()
    };
    assert!(g.fit_material(Some(8), all).is_err());
    // A material transfer cannot shade: transfer dropped with a note, or an error when
    // it was the only method.
    let mut g = Grid::default();
    let notes = g.fit_material(None, no_transfer).unwrap();
    assert_eq!(
        g.methods,
        vec![
            MethodKind::Lights,
            MethodKind::Lightcuts,
            MethodKind::Reflection
        ]
    );
    assert!(notes[0].contains("transfer"), "{notes:?}");
    let mut g = Grid {
        methods: vec![MethodKind::Transfer],
        ..Grid::default()
    };
    assert!(g.fit_material(None, no_transfer).is_err());
}

#[test]
fn method_names_are_the_env_method_names() {
    for m in MethodKind::ALL {
        let serde_name = toml::Value::try_from(m.env_method()).unwrap();
        assert_eq!(serde_name.as_str(), Some(m.name().as_str()));
        assert_eq!(MethodKind::parse(&m.name()), Some(m));
    }
    assert_eq!(MethodKind::parse("light"), None);
    // `auto` names no point of the axis: the sweep makes it concrete first.
    let mut spec = EnvSpec::new("p.exr".into());
    assert_eq!(MethodAxis::of_spec(&spec), None);
    spec.method = EnvMethod::Lights;
    assert_eq!(
        MethodAxis::of_spec(&spec),
        Some(MethodAxis::Lights {
            sampler: SamplerKind::Lloyd,
            count: 128
        })
    );
    let spec = EnvSpec {
        method: EnvMethod::Transfer,
        ..spec
    };
    assert_eq!(
        MethodAxis::of_spec(&spec),
        Some(MethodAxis::Transfer {
            azimuth: 128,
            polar: 65,
            exact_lights: 64
        })
    );
    let spec = EnvSpec {
        method: EnvMethod::Reflection,
        ..spec
    };
    assert_eq!(
        MethodAxis::of_spec(&spec),
        Some(MethodAxis::Reflection {
            grid: 64,
            exact_lights: 64
        })
    );
}
