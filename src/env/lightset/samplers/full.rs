//! The full probe as a light set ([`full_probe`]): one light per lit texel, the converged
//! reference every other sampler approaches.
//!
//! Design rule: no choice is made here at all; the light set is the probe's texels, so
//! evaluating it equals [`crate::env::lightset::reference_irradiance`] up to f32 storage of the
//! powers.

use crate::env::probe::ProbeTables;
use crate::env::{LightSet, Probe};

/// The full probe as a light set: one light per texel with non-zero weight, at the texel
/// centre, carrying `RGB x solid angle` (computed in f64). Evaluating it equals
/// [`crate::env::lightset::reference_irradiance`] up to f32 storage of the powers.
pub fn full_probe(probe: &Probe) -> LightSet {
    let t = ProbeTables::new(probe);
    let mut ls = LightSet::with_capacity(t.weight.len());
    for i in 0..t.weight.len() {
        if t.weight[i] > 0.0 {
            ls.push(t.dir[i], t.power[i]);
        }
    }
    ls
}
