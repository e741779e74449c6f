//! Progressive refinement: while the view is still, the image is re-rendered in steps
//! towards the converged reference, each step a scene file `brdfkit render` renders too.
//!
//! Step 0 is the document itself, the fast configuration shown while the view changes.
//! Where `[env] method = "auto"`, the moving frame is `auto`'s choice
//! ([`env_method::concrete_method`]) where that takes milliseconds per frame (a transfer
//! table for Lambert and SH data sets), and [`env_method::auto_moving_method`] where it
//! takes up to seconds (light cuts): the reflection table for Blinn-Phong (23% at the 99th
//! percentile under the studio probe at worst, where the 128-light set is at 150-218%), the
//! document's delta light set for the others; the still steps are `auto`'s choice, shown at
//! the document's parameters from step 1 and refined from step 2 as below. Step `k` of `steps` (1 <= k <= steps) shades the environment with `count * 4^k` lights
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
use crate::scene::{env_method, SceneFile};

/// Largest light count a refinement step asks for.
pub const MAX_REFINED_LIGHTS: usize = 4096;

/// Default number of refinement steps after the fast frame.
pub const DEFAULT_STEPS: usize = 3;

/// The scene file of refinement step `k` of `steps` for document `file` (module doc).
pub fn step_file(file: &SceneFile, k: usize, steps: usize) -> SceneFile {
    let mut f = file.clone();
    let (moving, still) = match f.env.as_ref() {
        Some(e) if e.method == EnvMethod::Auto => {
            let chosen = env_method::concrete_method(e, &f.material);
            // A light tree per pixel takes up to seconds: while the view changes, the
            // reflection table (Blinn-Phong) or the document's delta light set (its sampler
            // and count): milliseconds per frame.
            let moving = if chosen.frame_takes_seconds() {
                env_method::auto_moving_method(&f.material)
            } else {
                chosen
            };
            (moving, chosen)
        }
        Some(e) => (e.method, e.method),
        None => return f,
    };
    let Some(env) = f.env.as_mut() else {
        return f;
    };
    if k == 0 {
        env.method = moving;
        return f;
    }
    env.method = still;
    // The first still step is `still` at the document's parameters when it differs from
    // the moving frame's method; refinement starts from the next.
    let first = if still == moving { 0 } else { 1 };
    let factor = 4usize.saturating_pow((k - first) as u32);
    still.refine(env, factor, MAX_REFINED_LIGHTS);
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
    fn under_auto_the_moving_frame_is_the_reflection_table_and_the_still_ones_light_cuts() {
        // The default material (Blinn-Phong): `auto` is light cuts, the moving frame the
        // reflection table.
        let f = SceneFile {
            env: Some(EnvSpec::new("p.exr".into())),
            ..SceneFile::default()
        };
        let method = |k| step_file(&f, k, 3).env.unwrap().method;
        assert_eq!(method(0), EnvMethod::Reflection);
        assert_eq!(method(1), EnvMethod::Lightcuts);
        let cut = |k| step_file(&f, k, 3).env.unwrap().cut_error;
        assert_eq!(cut(1), crate::env::schema::DEFAULT_CUT_ERROR);
        assert_eq!(cut(2), crate::env::schema::DEFAULT_CUT_ERROR / 4.0);
    }

    #[test]
    fn under_auto_for_a_dbrdf_the_moving_frame_is_the_light_set() {
        // A library D-BRDF: `auto` is light cuts, seconds per frame.
        let f = SceneFile::parse(
            "[material]\nkind = \"library\"\nname = \"lindt-paper\"\n[env]\nfile = \"p.exr\"\n",
        )
        .unwrap();
        let method = |k| step_file(&f, k, 3).env.unwrap().method;
        assert_eq!(method(0), EnvMethod::Lights);
        assert_eq!(step_file(&f, 0, 3).env.unwrap().count, 128);
        assert_eq!(method(1), EnvMethod::Lightcuts);
        let cut = |k| step_file(&f, k, 3).env.unwrap().cut_error;
        assert_eq!(cut(1), crate::env::schema::DEFAULT_CUT_ERROR);
        // A MERL table: its light set at every step (no cone bound for light cuts).
        let f = SceneFile::parse(
            "[material]\nkind = \"merl-file\"\npath = \"m.binary\"\n[env]\nfile = \"p.exr\"\n",
        )
        .unwrap();
        for k in 0..=3 {
            assert_eq!(step_file(&f, k, 3).env.unwrap().method, EnvMethod::Lights);
        }
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
