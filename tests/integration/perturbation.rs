//! An oracle that passes everything is worthless: each deliberate fault a GPU port could
//! make must be caught by `compare` at the shipped tolerances ([`Thresholds::DEFAULT`]),
//! while the unperturbed render passes.
//!
//! Faults, each built as an equivalent perturbed data set so the renderer itself is untouched:
//! - a half-texel shift of the coefficient lookup (GL_LINEAR sampled half a texel off in
//!   azimuth = the table resampled at half-texel offsets);
//! - a wrong cosine factor (the data set's `includes_cosine` flag flipped: the cosine
//!   applied twice or not at all);
//! - a flipped azimuth (the thesis's acos fold or a mirrored frame: the table mirrored in
//!   azimuth and the odd (m < 0, sine) terms negated, i.e. the BRDF seen in a mirror);
//! - the image one pixel off (tests/integration/compare.rs).

use brdfkit::acquire::{acquire, AcquireOptions, Method, DEFAULT_LAMBDA};
use brdfkit::brdf::{AshikhminShirley, Brdf};
use brdfkit::compare::{self, Loaded, Thresholds};
use brdfkit::env::schema::{EnvMethod, EnvSpec, SamplerKind};
use brdfkit::render;
use brdfkit::scene::{MaterialSpec, Scene, SceneFile};
use brdfkit::sh::basis::sh_lm;
use brdfkit::sh::dataset::{Lookup, ShDataset};
use glam::{Quat, Vec3};
use std::path::Path;

/// A BRDF turned 45 degrees about the normal: not symmetric under azimuth -> -azimuth.
struct Turned45<B: Brdf>(B);

impl<B: Brdf> Brdf for Turned45<B> {
    fn eval(&self, wi: Vec3, wo: Vec3) -> Vec3 {
        let q = Quat::from_rotation_z(std::f32::consts::FRAC_PI_4);
        self.0.eval(q * wi, q * wo)
    }
    fn name(&self) -> &str {
        "turned-45"
    }
}

fn base_scene() -> Scene {
    let mut f = SceneFile::default();
    f.render.width = 160;
    f.render.height = 120;
    f.material = MaterialSpec::Library {
        name: "blue-silk".into(),
        lookup: None,
    };
    let mut env =
        EnvSpec::new(Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/probes/city.exr"));
    env.sampler = SamplerKind::MedianCut;
    env.count = 64;
    env.method = EnvMethod::Lights;
    f.env = Some(env);
    f.lights = Some(brdfkit::scene::default_lights());
    Scene::resolve(&f, Path::new("/")).unwrap()
}

fn with_material(s: &Scene, ds: ShDataset) -> Scene {
    let mut s = s.clone();
    s.material = brdfkit::material::Material::from(ds);
    s
}

fn rebuild(ds: &ShDataset, coeffs: Vec<f32>, includes_cosine: bool) -> ShDataset {
    let (nu, nv) = ds.grid();
    let mut out =
        ShDataset::new(nu, nv, ds.bands(), includes_cosine, ds.provenance(), coeffs).unwrap();
    out.coeff_lookup = ds.coeff_lookup;
    out.basis_lookup = ds.basis_lookup;
    out
}

fn verdict(expected: &Scene, actual: &Scene) -> (bool, compare::Metrics) {
    let e = Loaded::from_linear(render::render(expected, &Default::default()).image);
    let a = Loaded::from_linear(render::render(actual, &Default::default()).image);
    // Over the covered pixels, as `brdfkit compare` measures.
    let (m, _) = compare::compare_with(
        &e,
        &a,
        &Thresholds::DEFAULT,
        compare::AlphaMode::Ignore,
        compare::Pixels::Covered,
    )
    .unwrap();
    eprintln!(
        "FLIP mean {:.4}, p99 {:.4}, max abs {:.3e} over {} of {} pixels",
        m.flip_mean,
        m.flip_at_percentile,
        m.max_abs,
        m.covered,
        m.width * m.height
    );
    (m.passes(&Thresholds::DEFAULT), m)
}

#[test]
fn deliberate_faults_are_caught_and_the_truth_passes() {
    let scene = base_scene();
    let silk = scene
        .material
        .as_sh()
        .expect("blue-silk is an SH data set")
        .clone();
    let (nu, nv) = silk.grid();
    let t = silk.bands() * silk.bands();
    let idx = |i: usize, j: usize, c: usize, k: usize| ((j * nu + i) * 3 + c) * t + k;
    let src = silk.coeffs().to_vec();

    // The truth: the same data set rebuilt passes (and is bit-identical).
    let (ok, m) = verdict(
        &scene,
        &with_material(&scene, rebuild(&silk, src.clone(), silk.cosine_included())),
    );
    assert!(
        ok && m.max_abs == 0.0,
        "the unperturbed render must pass exactly: {m:?}"
    );

    // Half-texel shift of the (bilinear) coefficient lookup in azimuth.
    let mut bil = silk.clone();
    bil.coeff_lookup = Lookup::Bilinear;
    let truth = with_material(&scene, bil.clone());
    let mut shifted = src.clone();
    for j in 0..nv {
        for i in 0..nu {
            for c in 0..3 {
                for k in 0..t {
                    shifted[idx(i, j, c, k)] =
                        0.5 * (src[idx(i, j, c, k)] + src[idx((i + 1) % nu, j, c, k)]);
                }
            }
        }
    }
    let (ok, m) = verdict(
        &truth,
        &with_material(&scene, rebuild(&bil, shifted, bil.cosine_included())),
    );
    assert!(
        !ok,
        "a half-texel lookup shift passed: FLIP mean {} p99 {}",
        m.flip_mean, m.flip_at_percentile
    );

    // Wrong cosine factor.
    let (ok, m) = verdict(
        &scene,
        &with_material(&scene, rebuild(&silk, src.clone(), !silk.cosine_included())),
    );
    assert!(
        !ok,
        "a wrong cosine factor passed: FLIP mean {} p99 {}",
        m.flip_mean, m.flip_at_percentile
    );

    // Flipped azimuth. Silk (Ashikhmin-Shirley) depends only on cos^2 and sin^2 of the
    // azimuth, so it is mirror-symmetric and a flip cannot show on it; an anisotropic lobe
    // turned 45 degrees in the tangent plane is not. Mirror its view texels and negate the
    // sine (m < 0) terms.
    let skew = acquire(
        &Turned45(AshikhminShirley {
            nu: 4.0,
            nv: 160.0,
            rs: Vec3::new(0.3, 0.35, 0.6),
            rd: Vec3::new(0.02, 0.04, 0.22),
        }),
        &AcquireOptions::new(
            8,
            16,
            8,
            Method::Lsq {
                lambda: DEFAULT_LAMBDA,
            },
        ),
    )
    .unwrap();
    let truth = with_material(&scene, skew.clone());
    let (nu, nv) = skew.grid();
    let t = skew.bands() * skew.bands();
    let idx = |i: usize, j: usize, c: usize, k: usize| ((j * nu + i) * 3 + c) * t + k;
    let src = skew.coeffs().to_vec();
    let mut mirrored = src.clone();
    for j in 0..nv {
        for i in 0..nu {
            // Azimuth a -> -a maps texel centre (i + 1/2)/nu to (nu - 1 - i + 1/2)/nu.
            let mi = nu - 1 - i;
            for c in 0..3 {
                for k in 0..t {
                    let sign = if sh_lm(k).1 < 0 { -1.0 } else { 1.0 };
                    mirrored[idx(i, j, c, k)] = sign * src[idx(mi, j, c, k)];
                }
            }
        }
    }
    let (ok, m) = verdict(
        &truth,
        &with_material(&scene, rebuild(&skew, mirrored, skew.cosine_included())),
    );
    assert!(
        !ok,
        "a flipped azimuth passed: FLIP mean {} p99 {}",
        m.flip_mean, m.flip_at_percentile
    );
}
