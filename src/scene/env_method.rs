//! `[env] method = "auto"`, the default: the environment method chosen per material.
//!
//! Design rule: the choice is a function of the scene's material spec and of the renderer
//! that draws the frame ([`Renderer`]) alone (no file is read), so the command line, the
//! sweep and [`super::Scene::resolve`] make the same choice before anything is prepared. The choice comes from the sweep (`brdfkit sweep --class
//! diffuse|sh-glossy|glossy --probe city|studio|sky`; the numbers are in docs/sweeps.md,
//! "The `[env]` default per material"): the fastest method whose error against the converged
//! reference is at most 1% relative RMSE ([`crate::sweep::ERROR_BOUND`]) *and* at most 10%
//! at the 99th percentile of the per-pixel relative error (`brdfkit sweep --max-p99 0.1`),
//! under every shipped probe:
//! - Lambert and SH data sets: `transfer` (a table over normals from the full probe plus
//!   the [`DEFAULT_EXACT_LIGHTS`](crate::env::schema::DEFAULT_EXACT_LIGHTS) brightest
//!   texels summed exactly): the per-pixel cost does not grow with the probe.
//! - Analytic lobes (Blinn-Phong) and D-BRDFs: `lightcuts` at the default `cut_error`
//!   ([`DEFAULT_CUT_ERROR`](crate::env::schema::DEFAULT_CUT_ERROR)). A delta light set
//!   that meets 1% RMSE for a narrow lobe (Lloyd, 1024 lights) is faster, but its 99th
//!   percentile is tens of percent: the highlight shows the lights as spots. The cuts bound
//!   every pixel's error instead. The reflection table ([`crate::env::reflection`]) is
//!   within both bounds for the scene format's default Blinn-Phong (exponents 50 to 500)
//!   under every shipped probe, but not for the sweep's glossy class (Blinn-Phong 200,
//!   `ks` 0.9): under studio its default table is at 0.87% relative RMSE and 23% at the
//!   99th percentile (docs/sweeps.md); nor for every D-BRDF (`gold-dust-paint` under studio
//!   11%; filtered sampling of the anisotropic `lindt-paper` 15%). It is the viewer's
//!   moving frame for Blinn-Phong instead ([`auto_moving_method`]).
//! - MERL tables and RGL files: `lights` (delta lights; no cone bound for light cuts exists
//!   for a measured table, and the reflection table of a MERL table written from a
//!   Blinn-Phong of exponent 80 was over both bounds under the studio probe, 1.1% relative
//!   RMSE and 62% at the 99th percentile, with a bake of minutes).
//!
//! A table that states `sampler` or `count` and no `method` asks for a delta light set:
//! its method is then `lights` ([`super::SceneFile::parse`]; a stated `method = "auto"`
//! stays auto); so do `--sampler` and `--lights` on the command line.
//!
//! On the GPU renderer (`brdfkit render --device gpu`, `crate::gpu`), which runs light sets,
//! transfer tables and reflection tables (the table path of isotropic materials) but not
//! light cuts, `auto` keeps `transfer` and gives the materials whose CPU choice is
//! `lightcuts` the best light set of that sweep instead:
//! [`GPU_AUTO_LIGHTS`] lights by Lloyd (the rendering default sampler), the only light set
//! of the table under the RMSE bound for every glossy row; its 99th percentile is over
//! the bound (highlights show the lights as spots), which the line [`choose`] returns
//! says. The CPU's choice ([`Renderer::Cpu`]) is [`concrete_method`], unchanged.
//!
//! Beside the choice, every other question the tools ask of an `[env] method` before
//! anything is built is answered here, one exhaustive `match` each ([`gpu_unsupported`],
//! [`export_unsupported`], and the methods of `impl EnvMethod` below: the viewer's
//! refinement ladder and status line, the command line's progress bar), so the tools never
//! match the method. The file stays whole past 400 lines for that reason (half of it is
//! tests).

use super::MaterialSpec;
use crate::env::schema::{EnvMethod, EnvSpec, SamplerKind};
use crate::library::{self, Representation};

/// Why the GPU renderer does not draw `[env] method = "lightcuts"`: said by the GPU build
/// (`crate::gpu::unsupported`) and by `render --device gpu` before the light tree is built.
pub const LIGHTCUTS_NOT_ON_GPU: &str =
    "[env] method = \"lightcuts\" refines an adaptive cut of a light tree per pixel, which \
     the GPU path does not do; on a GPU use \"transfer\" or a light set (\"lights\")";

/// Why the GPU renderer does not draw `[env] method = "reflection"` for an anisotropic
/// D-BRDF: its path is filtered importance sampling of the residual probe's pyramid, a loop
/// of samples per pixel that only the CPU runs (the table path of isotropic materials is on
/// the GPU). Said by [`super::Environment::gpu_unsupported`] once the term is prepared.
pub const REFLECTION_FILTERED_NOT_ON_GPU: &str =
    "[env] method = \"reflection\" shades an anisotropic D-BRDF by filtered importance \
     sampling, which the GPU path does not do (it looks up the table of isotropic materials \
     only); on a GPU use \"transfer\" or a light set (\"lights\")";

/// Why the GPU renderer does not draw `method`, or `None` when it does: light sets,
/// transfer tables, reflection tables, and `auto` (which [`choose`] makes a light set where
/// the CPU would cut a light tree). [`super::Environment::gpu_unsupported`] says the same
/// of a built one, and also refuses the reflection method's filtered path
/// ([`REFLECTION_FILTERED_NOT_ON_GPU`]), which depends on the material.
pub fn gpu_unsupported(method: EnvMethod) -> Option<&'static str> {
    match method {
        EnvMethod::Auto | EnvMethod::Lights | EnvMethod::Transfer | EnvMethod::Reflection => None,
        EnvMethod::Lightcuts => Some(LIGHTCUTS_NOT_ON_GPU),
    }
}

/// Whether `brdfkit export` refuses `method`: it writes delta lights (a light set) or a
/// transfer table and its exact lights; a light tree and a reflection-space table are
/// neither (`auto` is made concrete first).
pub fn export_unsupported(method: EnvMethod) -> bool {
    match method {
        EnvMethod::Auto | EnvMethod::Lights | EnvMethod::Transfer => false,
        EnvMethod::Lightcuts | EnvMethod::Reflection => true,
    }
}

/// What each method asks of the tools before anything is prepared: the viewer's
/// refinement ladder and status line, the command line's progress bar. One exhaustive
/// `match` per question, so a new method says here what every tool does with it and the
/// tools never match the method themselves.
impl EnvMethod {
    /// Whether a frame of this method can take up to seconds (light cuts: a cut of a light
    /// tree per pixel), so that the viewer shows `auto`'s choice only when the view is
    /// still and moves with the document's delta light set (`crate::view::refine`).
    pub fn frame_takes_seconds(self) -> bool {
        match self {
            EnvMethod::Lightcuts => true,
            EnvMethod::Auto | EnvMethod::Lights | EnvMethod::Transfer | EnvMethod::Reflection => {
                false
            }
        }
    }

    /// What the method prepares from a probe, in a user's words (error messages):
    /// `auto` is made concrete before anything asks.
    pub fn prepares(self) -> &'static str {
        match self {
            EnvMethod::Lights => "a set of delta lights",
            EnvMethod::Transfer => "a transfer table over normals and its exact lights",
            EnvMethod::Lightcuts => "a light tree, cut per pixel",
            EnvMethod::Reflection => "a reflection-space radiance table and its exact lights",
            EnvMethod::Auto => "the method it chooses for the material",
        }
    }

    /// Makes `env` (of this method) `factor` times finer, for a step of the viewer's
    /// refinement ladder (`crate::view::refine`): `factor` times the lights of a light set
    /// (at most `max_lights`, or its own count if larger; Lloyd refined by median cut,
    /// whose preparation does not grow with texels x lights), `factor` times a transfer
    /// table's exact lights (at least 1 first; at most `max_lights` and
    /// [`MAX_LIGHTS`](crate::env::schema::MAX_LIGHTS)), light cuts' cut error divided by
    /// `factor`. A reflection table is kept (a finer one is a bake of seconds, not a
    /// frame); `auto` is made concrete before ([`concrete_method`]).
    pub fn refine(self, env: &mut EnvSpec, factor: usize, max_lights: usize) {
        match self {
            EnvMethod::Lights => {
                env.count = env
                    .count
                    .saturating_mul(factor)
                    .min(max_lights.max(env.count));
                if env.sampler == SamplerKind::Lloyd {
                    env.sampler = SamplerKind::MedianCut;
                }
            }
            EnvMethod::Transfer => {
                env.exact_lights = (env.exact_lights.max(1))
                    .saturating_mul(factor)
                    .min(max_lights.max(env.exact_lights))
                    .min(crate::env::schema::MAX_LIGHTS)
            }
            EnvMethod::Lightcuts => env.cut_error /= factor as f32,
            EnvMethod::Reflection | EnvMethod::Auto => {}
        }
    }

    /// The method and its parameters in the viewer's status line (`crate::view::app`), in
    /// the names a scene file and the command line spell (`median-cut`, never Rust's
    /// `MedianCut`): `lights lloyd 128` for a light set of `env`, the method's name for the
    /// others.
    pub fn status_words(self, env: &EnvSpec) -> String {
        let m = self.name();
        match self {
            EnvMethod::Lights => {
                let sampler = clap::ValueEnum::to_possible_value(&env.sampler)
                    .map(|v| v.get_name().to_string())
                    .unwrap_or_default();
                format!("{m} {sampler} {}", env.count)
            }
            EnvMethod::Auto
            | EnvMethod::Transfer
            | EnvMethod::Lightcuts
            | EnvMethod::Reflection => m.to_string(),
        }
    }

    /// What the command line's progress bar counts while this method prepares `env`
    /// (`crate::cli::render`): its label and unit, drawn once the preparation sets its
    /// length (nothing on a cache hit); `None` when nothing is counted: a light set file
    /// (read, not sampled), `auto` (made concrete before anything is prepared).
    pub fn preparation_progress(self, env: &EnvSpec) -> Option<(String, &'static str)> {
        match self {
            EnvMethod::Transfer => Some((
                format!(
                    "transfer table: {} x {} normals",
                    env.transfer_azimuth, env.transfer_polar
                ),
                "rows",
            )),
            EnvMethod::Reflection => Some((
                format!(
                    "reflection table: {g} x {g} cells, {s} + 1 slices, psi order {o}",
                    g = env.reflection_grid,
                    s = env.reflection_slices,
                    o = env.reflection_order
                ),
                "nodes",
            )),
            EnvMethod::Lights if env.lights.is_some() => None,
            EnvMethod::Lights => {
                let config = env.sampler_config();
                let what = match config.n() {
                    Some(n) => format!("light set: {n} lights by {}", config.name()),
                    None => "light set: the full probe".to_string(),
                };
                Some((what, config.progress_unit()))
            }
            EnvMethod::Lightcuts => Some(("light tree".to_string(), "texel visits")),
            EnvMethod::Auto => None,
        }
    }
}

/// The renderer a frame is drawn by, as far as `auto` depends on it (module doc).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Renderer {
    /// The CPU renderer: every method.
    Cpu,
    /// The wgpu renderer: light sets, transfer tables and reflection tables, no light cuts.
    Gpu,
}

/// Lights of the Lloyd light set `auto` gives a GPU frame where the CPU would use light
/// cuts: the "Lloyd 1024" column of docs/sweeps.md ("The `[env]` default per material"),
/// relative RMSE 0.06-0.49% for the glossy class under the shipped probes, p99 14-33%.
pub const GPU_AUTO_LIGHTS: usize = 1024;

/// The method `auto` stands for under `material` (module doc).
pub fn auto_method(material: &MaterialSpec) -> EnvMethod {
    match material {
        MaterialSpec::Lambert { .. } | MaterialSpec::ShFile { .. } => EnvMethod::Transfer,
        MaterialSpec::BlinnPhong { .. } | MaterialSpec::DbrdfFile { .. } => EnvMethod::Lightcuts,
        MaterialSpec::MerlFile { .. } | MaterialSpec::RglFile { .. } => EnvMethod::Lights,
        MaterialSpec::Library { name, .. } => match library::find(name).map(|e| e.representation) {
            Some(Representation::Sh { .. }) => EnvMethod::Transfer,
            Some(Representation::Dbrdf) => EnvMethod::Lightcuts,
            // An unknown name is reported when the material is resolved.
            None => EnvMethod::Lights,
        },
    }
}

/// The method the viewer shows while the view moves where `[env] method = "auto"` stands
/// for a method whose frame takes up to seconds (light cuts; `crate::view::refine`): the
/// reflection table for Blinn-Phong (tens of milliseconds per frame; under the sweep's
/// worst probe 0.87% relative RMSE and 23% at the 99th percentile, where the 128-light set
/// is at 150-218%), the document's delta light set (`lights`) for the others (filtered
/// sampling of an anisotropic D-BRDF takes over a second per frame).
pub fn auto_moving_method(material: &MaterialSpec) -> EnvMethod {
    match material {
        MaterialSpec::BlinnPhong { .. } => EnvMethod::Reflection,
        MaterialSpec::Lambert { .. }
        | MaterialSpec::ShFile { .. }
        | MaterialSpec::DbrdfFile { .. }
        | MaterialSpec::MerlFile { .. }
        | MaterialSpec::RglFile { .. }
        | MaterialSpec::Library { .. } => EnvMethod::Lights,
    }
}

/// The `[env]` table's method, with `auto` replaced by [`auto_method`] of `material`, or by
/// `lights` when the table reads a light set file (`lights = "set.json"`: delta lights).
pub fn concrete_method(env: &EnvSpec, material: &MaterialSpec) -> EnvMethod {
    match env.method {
        EnvMethod::Auto if env.lights.is_some() => EnvMethod::Lights,
        EnvMethod::Auto => auto_method(material),
        m @ (EnvMethod::Lights
        | EnvMethod::Transfer
        | EnvMethod::Lightcuts
        | EnvMethod::Reflection) => m,
    }
}

/// The `[env]` table `renderer` draws: `env` with `auto` replaced by its method
/// ([`concrete_method`] on the CPU; on the GPU the same but light cuts, replaced by a
/// light set of [`GPU_AUTO_LIGHTS`] lights by Lloyd, module doc), and the one line to print
/// when the renderer changed the choice (`None` when it did not, or `env` is not `auto`).
/// Nothing is read or built: the caller prepares the returned table.
pub fn choose(
    env: &EnvSpec,
    material: &MaterialSpec,
    renderer: Renderer,
) -> (EnvSpec, Option<String>) {
    let mut chosen = env.clone();
    chosen.method = concrete_method(env, material);
    if env.method != EnvMethod::Auto
        || renderer == Renderer::Cpu
        || gpu_unsupported(chosen.method).is_none()
    {
        return (chosen, None);
    }
    chosen.method = EnvMethod::Lights;
    chosen.sampler = SamplerKind::Lloyd;
    chosen.count = GPU_AUTO_LIGHTS;
    let note = format!(
        "auto: method \"{}\" is CPU only; the GPU renders {GPU_AUTO_LIGHTS} Lloyd lights \
         (under 1% relative RMSE on glossy lobes, but highlights may show them as spots: \
         docs/sweeps.md; set [env] method or --env-method to choose)",
        concrete_method(env, material).name()
    );
    (chosen, Some(note))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::SceneFile;

    fn method_of(toml: &str) -> EnvMethod {
        let f = SceneFile::parse(toml).unwrap();
        concrete_method(f.env.as_ref().unwrap(), &f.material)
    }

    #[test]
    fn auto_chooses_per_material_class() {
        let env = "[env]\nfile = \"p.exr\"\n";
        for (material, want) in [
            ("kind = \"lambert\"", EnvMethod::Transfer),
            (
                "kind = \"library\"\nname = \"teal-paint\"",
                EnvMethod::Transfer,
            ),
            (
                "kind = \"library\"\nname = \"lindt-paper\"",
                EnvMethod::Lightcuts,
            ),
            ("kind = \"blinn-phong\"", EnvMethod::Lightcuts),
            (
                "kind = \"merl-file\"\npath = \"m.binary\"",
                EnvMethod::Lights,
            ),
            ("kind = \"sh-file\"\npath = \"m.exr\"", EnvMethod::Transfer),
            (
                "kind = \"dbrdf-file\"\npath = \"m.exr\"",
                EnvMethod::Lightcuts,
            ),
        ] {
            let text = format!("[material]\n{material}\n{env}");
            assert_eq!(method_of(&text), want, "{material}");
        }
        // No [material]: the default Blinn-Phong.
        assert_eq!(method_of(env), EnvMethod::Lightcuts);
    }

    #[test]
    fn a_stated_sampler_or_count_asks_for_lights() {
        for stated in ["sampler = \"median-cut\"", "count = 64"] {
            let text =
                format!("[material]\nkind = \"lambert\"\n[env]\nfile = \"p.exr\"\n{stated}\n");
            assert_eq!(method_of(&text), EnvMethod::Lights, "{stated}");
        }
        // An explicit method other than `lights`: `count` is another method's field, an error.
        let text = "[material]\nkind = \"lambert\"\n[env]\nfile = \"p.exr\"\ncount = 64\nmethod = \"transfer\"\n";
        let e = SceneFile::parse(text).unwrap_err();
        assert!(
            e.starts_with("line 5: env.count: belongs to method = \"lights\""),
            "{e}"
        );
        // A stated `auto` stays auto (a written-out scene file states every field).
        let text = "[env]\nfile = \"p.exr\"\nmethod = \"auto\"\ncount = 64\n";
        assert_eq!(method_of(text), EnvMethod::Lightcuts);
        // A light set file is delta lights.
        let text = "[material]\nkind = \"lambert\"\n[env]\nlights = \"set.json\"\n";
        assert_eq!(method_of(text), EnvMethod::Lights);
    }

    #[test]
    fn auto_on_the_gpu_replaces_cpu_only_methods_by_lloyd_lights_and_says_so() {
        let choice = |toml: &str, renderer| {
            let f = SceneFile::parse(toml).unwrap();
            choose(f.env.as_ref().unwrap(), &f.material, renderer)
        };
        let env = "[env]\nfile = \"p.exr\"\n";
        for (material, on_cpu) in [
            ("kind = \"blinn-phong\"", EnvMethod::Lightcuts),
            (
                "kind = \"library\"\nname = \"lindt-paper\"",
                EnvMethod::Lightcuts,
            ),
            (
                "kind = \"dbrdf-file\"\npath = \"m.exr\"",
                EnvMethod::Lightcuts,
            ),
        ] {
            let text = format!("[material]\n{material}\n{env}");
            // The CPU's choice (light cuts or the reflection table), said by no extra line.
            let (cpu, note) = choice(&text, Renderer::Cpu);
            assert_eq!(cpu.method, on_cpu, "{material}");
            assert_eq!(note, None, "{material}");
            // The GPU's: the Lloyd light set, and one line naming it and why.
            let (gpu, note) = choice(&text, Renderer::Gpu);
            assert_eq!(gpu.method, EnvMethod::Lights, "{material}");
            assert_eq!(gpu.sampler, SamplerKind::Lloyd, "{material}");
            assert_eq!(gpu.count, GPU_AUTO_LIGHTS, "{material}");
            let note = note.expect("the GPU's choice is said");
            assert!(
                note.starts_with(&format!("auto: method \"{}\" is CPU only", on_cpu.name()))
                    && note.contains(&format!("{GPU_AUTO_LIGHTS} Lloyd lights"))
                    && !note.contains('\n'),
                "{note}"
            );
        }
        // Transfer runs on the GPU: kept, nothing said; so are light sets.
        for material in [
            "kind = \"lambert\"",
            "kind = \"library\"\nname = \"teal-paint\"",
        ] {
            let text = format!("[material]\n{material}\n{env}");
            let (gpu, note) = choice(&text, Renderer::Gpu);
            assert_eq!(
                (gpu.method, note),
                (EnvMethod::Transfer, None),
                "{material}"
            );
        }
        // A stated method is never changed, on either renderer (the GPU refuses light cuts
        // with its own error).
        let stated = "[env]\nfile = \"p.exr\"\nmethod = \"lightcuts\"\n";
        for renderer in [Renderer::Cpu, Renderer::Gpu] {
            let (kept, note) = choice(stated, renderer);
            assert_eq!((kept.method, note), (EnvMethod::Lightcuts, None));
            assert_eq!(kept.count, 128);
        }
        let lights = "[env]\nfile = \"p.exr\"\ncount = 64\n";
        let (kept, note) = choice(lights, Renderer::Gpu);
        assert_eq!(
            (kept.method, kept.count, note),
            (EnvMethod::Lights, 64, None)
        );
    }

    /// The module doc, its `//!` lines joined by single spaces.
    fn module_doc() -> String {
        include_str!("env_method.rs")
            .lines()
            .take_while(|l| l.starts_with("//!"))
            .map(|l| l.trim_start_matches("//!").trim())
            .collect::<Vec<_>>()
            .join(" ")
    }

    /// The number written just before the first `suffix` of `text`.
    fn number_before(text: &str, suffix: &str) -> f64 {
        let end = text.find(suffix).unwrap_or_else(|| panic!("no {suffix:?}"));
        let start = text[..end]
            .rfind(|c: char| !(c.is_ascii_digit() || c == '.'))
            .map_or(0, |i| i + 1);
        let n = &text[start..end];
        n.parse()
            .unwrap_or_else(|e| panic!("{n:?} before {suffix:?}: {e}"))
    }

    /// The number written just after the first `prefix` of `text`.
    fn number_after(text: &str, prefix: &str) -> f64 {
        let start = text.find(prefix).unwrap_or_else(|| panic!("no {prefix:?}")) + prefix.len();
        let rest = &text[start..];
        let len = rest
            .find(|c: char| !(c.is_ascii_digit() || c == '.'))
            .unwrap_or(rest.len());
        let n = rest[..len].trim_end_matches('.');
        n.parse()
            .unwrap_or_else(|e| panic!("{n:?} after {prefix:?}: {e}"))
    }

    /// The module doc restates the bounds the rule was chosen at, so they are held to the
    /// code: the RMSE bound to [`crate::sweep::ERROR_BOUND`], the 99th-percentile bound to
    /// the `--max-p99` value the doc names and to the one `brdfkit sweep --help` gives for
    /// the rule (there is no constant for it). The exact-light count and the cut error are
    /// intra-doc links to their constants, so no number may stand before "brightest".
    #[test]
    fn the_module_doc_states_the_bounds_the_code_uses() {
        let doc = module_doc();
        let rmse = number_before(&doc, "% relative RMSE");
        assert!(
            (rmse / 100.0 - crate::sweep::ERROR_BOUND).abs() < 1e-12,
            "the doc states {rmse}% relative RMSE, ERROR_BOUND is {}",
            crate::sweep::ERROR_BOUND
        );
        let p99 = number_before(&doc, "% at the 99th percentile");
        let flag = number_after(&doc, "--max-p99 ");
        assert!(
            (p99 / 100.0 - flag).abs() < 1e-12,
            "the doc states {p99}% at the 99th percentile and --max-p99 {flag}"
        );
        let help = number_after(include_str!("../cli/mod.rs"), "method = \"auto\"` uses ");
        assert_eq!(
            flag, help,
            "--max-p99's help gives {help} for the auto rule"
        );
        for (i, _) in doc.match_indices(" brightest") {
            let word = doc[..i].rsplit(' ').next().unwrap_or("");
            assert!(
                word.parse::<f64>().is_err(),
                "the doc states {word} brightest texels: link DEFAULT_EXACT_LIGHTS instead"
            );
        }
    }
}
