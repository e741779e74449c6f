//! The fast path measured against the converged reference: [`MeasuredBound`], recorded by
//! `bless` and re-measured at a small size by `golden check --bounds` ([`check_bounds`]).

use super::*;

/// The measured difference between an entry's render and its reference render
/// (the converged reference, [`crate::render::RenderOptions::converged_reference`]: f64,
/// every light of the full probe, no skips, no culling), over all pixels and channels of the linear images.
/// Each value is rounded *up* to three significant digits, so it stays a bound.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MeasuredBound {
    /// Largest absolute channel difference (radiance units).
    pub max_abs: f64,
    /// `sqrt(sum (fast - ref)^2 / sum ref^2)`: the error relative to the image's energy.
    pub rel_rmse: f64,
    /// Mean FLIP of the two images' displays (exposure 0, ACES, sRGB).
    pub flip_mean: f64,
}

/// `x` rounded up to three significant digits (0 stays 0).
pub(crate) fn round_up_3(x: f64) -> f64 {
    if !(x > 0.0 && x.is_finite()) {
        return x;
    }
    let text = format!("{x:.2e}");
    let (m, e) = text.split_once('e').expect("exponent form");
    let (m, e): (f64, i32) = (m.parse().expect("mantissa"), e.parse().expect("exponent"));
    let r: f64 = text.parse().expect("number");
    if r >= x {
        r
    } else {
        format!("{:.2}e{e}", m + 0.01).parse().expect("number")
    }
}

/// Divisor of the width and height at which [`check_bounds`] re-measures the
/// fast-vs-reference bound: an environment entry's reference shades every probe texel
/// (131,072 lights for a 512x256 probe) at every pixel, about a minute at 64x48 on two
/// cores, a few seconds at 1/4 of each side.
pub const BOUND_CHECK_SCALE: u32 = 4;

/// How far a re-measured bound may exceed the stored one: `stored * (1 + rel) + abs` per
/// metric. On the platform that blessed the set both sides are deterministic and the
/// measurement repeats exactly; the margin admits another platform's rounding (another
/// libm moves light directions by ulps, which moves a sampler's error by far less than
/// 10%), not a change of the light set or of either render path.
pub const BOUND_MARGIN: (f64, f64) = (0.1, 1e-6);

/// Measures the fast path against the converged reference on an entry's scene, with both
/// images at 1/`scale` of the entry's width and height (at least 1 pixel each): the fast
/// side is the f32 kernel render of the scene (for an f64 entry too, so it is never its own
/// reference), the reference the same scene with the environment (if any) as the full
/// probe, through [`render::RenderOptions::converged_reference`] (f64, every light, no
/// skips, no culling). `None` for
/// debug outputs (nothing is shaded). Slow with an environment at full size (every probe
/// texel is a light).
pub fn measure(dir: &Path, entry: &Entry, scale: u32) -> Result<Option<MeasuredBound>> {
    if entry.aov.is_some() {
        return Ok(None);
    }
    let scene_path = dir.join(&entry.scene);
    let mut file = SceneFile::load(&scene_path)?;
    file.render.width = (file.render.width / scale.max(1)).max(1);
    file.render.height = (file.render.height / scale.max(1)).max(1);
    file.render.precision = Precision::F32;
    let fast = render::render(
        &resolve_named(&file, dir, &scene_path)?,
        &RenderOptions::default(),
    )
    .image;
    if let Some(env) = file.env.as_mut() {
        env.use_full_probe();
    }
    let scene = resolve_named(&file, dir, &scene_path)?;
    let reference = render::render(&scene, &RenderOptions::converged_reference()).image;
    Ok(Some(bound(&fast, &reference)?))
}

/// Whether a re-measured bound stays within the stored one ([`BOUND_MARGIN`]), per metric.
pub fn within_bound(measured: &MeasuredBound, stored: &MeasuredBound) -> bool {
    let (rel, abs) = BOUND_MARGIN;
    let ok = |m: f64, s: f64| m <= s * (1.0 + rel) + abs;
    ok(measured.max_abs, stored.max_abs)
        && ok(measured.rel_rmse, stored.rel_rmse)
        && ok(measured.flip_mean, stored.flip_mean)
}

/// The outcome of re-measuring one entry's small fast-vs-reference bound.
#[derive(Debug, Serialize)]
pub struct BoundOutcome {
    pub name: String,
    pub passed: bool,
    pub stored: MeasuredBound,
    pub measured: MeasuredBound,
}

/// Re-measures [`Entry::fast_vs_reference_small`] of the named shaded entries (all if
/// `names` is empty; debug outputs have none) at 1/[`BOUND_CHECK_SCALE`] of their size and
/// holds each to the stored bound within [`BOUND_MARGIN`]. A shaded entry without a stored
/// small bound is an error (run `golden bless`).
pub fn check_bounds(dir: &Path, names: &[String]) -> Result<Vec<BoundOutcome>> {
    let manifest = load_manifest(dir)?;
    for n in names {
        Entry::find(&manifest, &manifest_path(dir), n)?;
    }
    let mut out = Vec::new();
    for entry in &manifest.entries {
        if entry.aov.is_some() || (!names.is_empty() && !names.contains(&entry.name)) {
            continue;
        }
        let Some(stored) = entry.fast_vs_reference_small else {
            return Err(Error::format(
                manifest_path(dir),
                format!(
                    "entry '{}' has no fast_vs_reference_small: run `brdfkit golden bless {}`",
                    entry.name, entry.name
                ),
            ));
        };
        let measured = measure(dir, entry, BOUND_CHECK_SCALE)?.expect("a shaded entry");
        out.push(BoundOutcome {
            name: entry.name.clone(),
            passed: within_bound(&measured, &stored),
            stored,
            measured,
        });
    }
    Ok(out)
}

/// The [`MeasuredBound`] between two images of one size (a size difference is an error):
/// the largest absolute difference and FLIP mean as [`compare::compare`] measures them over
/// every pixel ([`compare::Pixels::All`], not `brdfkit compare`'s covered pixels: the
/// stored bounds were measured so, and only `golden bless` may re-measure them), the
/// relative RMSE of [`crate::metrics::relative_rmse`] over every pixel (background adds
/// nothing to either of its sums).
pub fn bound(fast: &Image, reference: &Image) -> Result<MeasuredBound> {
    let (m, _) = compare::compare(
        &Loaded::from_linear(reference.clone()),
        &Loaded::from_linear(fast.clone()),
        &Thresholds::DEFAULT,
    )?;
    Ok(MeasuredBound {
        max_abs: round_up_3(m.max_abs as f64),
        rel_rmse: round_up_3(crate::metrics::relative_rmse(reference, fast, None)),
        flip_mean: round_up_3(m.flip_mean as f64),
    })
}
