//! Progressive refinement: while the view is still, the image is re-rendered in steps
//! towards the converged reference, each step a scene file `brdfkit render` renders too.
//!
//! Step 0 is the document itself (the fast configuration shown while the view changes;
//! where `[env] method = "auto"` stands for light cuts, which take up to seconds per frame,
//! the document's delta light set instead, then light cuts from step 1, refined from step 2
//! as below; where it stands for a transfer table, the table at every step). Step `k` of `steps` (1 <= k <= steps) shades the environment with `count * 4^k` lights
//! (at most [`MAX_REFINED_LIGHTS`]) of the same sampler — median cut for Lloyd, whose
//! relaxation costs texels x lights per iteration (4096 lights from a 512 x 256 probe: 15 s
//! on this project's 2-core machine, median cut 0.1 s) — a transfer table with 4^k times the
//! exact lights, or light cuts with the cut error divided by 4^k; the last step also drops
//! no light (`render.drop_lights = 0`) and shades every SH band (`render.band_skip = false`).
//! The converged reference itself (every one of a 512 x 256 probe's 131,072 texels a light,
//! f64: `render --reference`) takes minutes at window sizes, so the ladder stops short of
//! it; its last step is what `brdfkit sweep` measures against that reference for the same
//! configuration.

use crate::env::schema::EnvMethod;
use crate::scene::SceneFile;

/// Largest light count a refinement step asks for.
pub const MAX_REFINED_LIGHTS: usize = 4096;

/// Default number of refinement steps after the fast frame.
pub const DEFAULT_STEPS: usize = 3;

/// The scene file of refinement step `k` of `steps` for document `file` (module doc).
pub fn step_file(file: &SceneFile, k: usize, steps: usize) -> SceneFile {
    let mut f = file.clone();
    // `[env] method = "auto"` where it stands for light cuts (Blinn-Phong, D-BRDFs: up to
    // seconds per frame): while the view changes, the document's delta light set (its
    // sampler and count: milliseconds per frame); when still, light cuts from step 1,
    // refined from step 2 on. Where it stands for a transfer table (Lambert, SH data sets:
    // as fast as the light set and more accurate), every step is the table.
    let auto_cuts = f.env.as_ref().is_some_and(|e| {
        e.method == EnvMethod::Auto
            && crate::scene::env_method::concrete_method(e, &f.material).frame_takes_seconds()
    });
    if k == 0 {
        match f.env.as_mut() {
            Some(env) if auto_cuts => env.method = EnvMethod::Lights,
            _ => f.resolve_env_method(),
        }
        return f;
    }
    f.resolve_env_method();
    let factor = 4usize.saturating_pow(if auto_cuts { k - 1 } else { k } as u32);
    if let Some(env) = f.env.as_mut() {
        env.method.refine(env, factor, MAX_REFINED_LIGHTS);
    }
    if k >= steps {
        f.render.drop_lights = 0.0;
        f.render.band_skip = false;
    }
    f
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::env::schema::{EnvSpec, SamplerKind};

    #[test]
    fn under_auto_the_moving_frame_is_the_light_set_and_the_still_ones_the_auto_method() {
        // The default material (Blinn-Phong): `auto` is light cuts.
        let f = SceneFile {
            env: Some(EnvSpec::new("p.exr".into())),
            ..SceneFile::default()
        };
        let method = |k| step_file(&f, k, 3).env.unwrap().method;
        assert_eq!(method(0), EnvMethod::Lights);
        assert_eq!(method(1), EnvMethod::Lightcuts);
        let cut = |k| step_file(&f, k, 3).env.unwrap().cut_error;
        assert_eq!(cut(1), crate::env::schema::DEFAULT_CUT_ERROR);
        assert_eq!(cut(2), crate::env::schema::DEFAULT_CUT_ERROR / 4.0);
        assert_eq!(step_file(&f, 0, 3).env.unwrap().count, 128);
    }

    #[test]
    fn under_auto_for_an_sh_data_set_every_step_is_the_transfer_table() {
        let f = SceneFile::parse(
            "[material]\nkind = \"library\"\nname = \"teal-paint\"\n[env]\nfile = \"p.exr\"\n",
        )
        .unwrap();
        let env = |k| step_file(&f, k, 3).env.unwrap();
        assert_eq!(env(0).method, EnvMethod::Transfer);
        assert_eq!(env(3).method, EnvMethod::Transfer);
        let k0 = env(0).exact_lights;
        assert_eq!(env(1).exact_lights, 4 * k0);
    }

    #[test]
    fn steps_raise_the_light_count_and_the_last_drops_no_light() {
        // A delta light set (`auto` is left as it is: its method has no light count).
        let mut env = EnvSpec::new("p.exr".into());
        env.method = crate::env::schema::EnvMethod::Lights;
        let f = SceneFile {
            env: Some(env),
            ..SceneFile::default()
        };
        let counts: Vec<usize> = (0..=3)
            .map(|k| step_file(&f, k, 3).env.unwrap().count)
            .collect();
        assert_eq!(counts, [128, 512, 2048, 4096]);
        let last = step_file(&f, 3, 3);
        assert_eq!(last.render.drop_lights, 0.0);
        assert!(!last.render.band_skip);
        assert!(step_file(&f, 2, 3).render.band_skip);
        // Lloyd (the default) refines by median cut; step 0 keeps the document's sampler.
        assert_eq!(step_file(&f, 0, 3).env.unwrap().sampler, SamplerKind::Lloyd);
        assert_eq!(
            step_file(&f, 1, 3).env.unwrap().sampler,
            SamplerKind::MedianCut
        );
    }
}
