//! The converged reference a light set is measured against: the probe's exact irradiance
//! at a normal (every texel, f64), and a light set's relative irradiance error against it
//! over nearly uniform normals (the render-free error metric of `brdfkit lights`).

use super::LightSet;
use crate::env::probe::ProbeTables;
use crate::env::Probe;
use glam::DVec3;
use rayon::prelude::*;

/// `n` nearly uniform unit directions on the sphere (Fibonacci lattice, golden-angle
/// spiral, `y_i = 1 - (2 i + 1)/n`). Deterministic; used as the normals of the
/// render-free error metric.
pub fn fibonacci_sphere(n: usize) -> Vec<DVec3> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..n)
        .map(|i| {
            let y = 1.0 - (2.0 * i as f64 + 1.0) / n as f64;
            let r = (1.0 - y * y).max(0.0).sqrt();
            let a = golden * i as f64;
            DVec3::new(r * a.cos(), y, r * a.sin())
        })
        .collect()
}

/// Exact irradiance from the probe's texels at unit normal `n`, f64:
/// `E(n) = sum_texels max(0, n.d_t) L_t Omega_t` with `d_t` the texel centre direction and
/// `Omega_t` its exact solid angle. This is the converged reference every light set is
/// measured against (it equals [`crate::env::SamplerConfig::Full`]'s light set evaluated in f64).
pub fn reference_irradiance(probe: &Probe, n: DVec3) -> DVec3 {
    let mut e = DVec3::ZERO;
    for row in 0..probe.height() {
        let omega = probe.solid_angle(row);
        let mut acc = DVec3::ZERO;
        for col in 0..probe.width() {
            let c = n.dot(probe.direction(row, col));
            if c > 0.0 {
                let t = probe.texel(row, col);
                acc += DVec3::new(t[0] as f64, t[1] as f64, t[2] as f64) * c;
            }
        }
        e += acc * omega;
    }
    e
}

/// [`reference_irradiance`] for many normals, in parallel (texel directions and powers
/// are tabulated once; same f64 sums, grouped per texel instead of per row).
pub fn reference_irradiance_many(probe: &Probe, normals: &[DVec3]) -> Vec<DVec3> {
    let t = ProbeTables::new(probe);
    normals
        .par_iter()
        .map(|&n| {
            let mut e = DVec3::ZERO;
            for (d, p) in t.dir.iter().zip(&t.power) {
                let c = n.dot(*d);
                if c > 0.0 {
                    e += *p * c;
                }
            }
            e
        })
        .collect()
}

/// Exact outgoing radiance of a Lambertian surface (thesis 2.2.1, `f_r = albedo/pi`) with
/// unit normal `n` under the probe: `albedo / pi x E(n)`, f64, RGB.
pub fn reference_lambert(probe: &Probe, n: DVec3, albedo: DVec3) -> DVec3 {
    albedo * reference_irradiance(probe, n) / std::f64::consts::PI
}

/// Relative RMS irradiance error of a light set against reference irradiances `reference`
/// (from [`reference_irradiance_many`]) at the same `normals`:
/// `sqrt(sum_n |E_lights(n) - E_ref(n)|^2 / sum_n |E_ref(n)|^2)`, `|.|` the Euclidean
/// norm over RGB ([`crate::metrics::relative_l2`]: 0 when the reference is all zero and
/// the lights are too, infinite when only the reference is).
pub fn irradiance_error(lights: &LightSet, normals: &[DVec3], reference: &[DVec3]) -> f64 {
    assert_eq!(normals.len(), reference.len());
    // Irradiances in parallel, summed in index order: a reduction across rayon tasks would
    // group the sum by the thread count's split, and so change its last bits.
    let got: Vec<DVec3> = normals.par_iter().map(|&n| lights.irradiance(n)).collect();
    let (num, den) = crate::metrics::squared_error_sums(&got, reference);
    crate::metrics::relative_l2(num, den)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fibonacci_normals_cover_the_sphere() {
        let n = fibonacci_sphere(256);
        let mean: DVec3 = n.iter().copied().sum::<DVec3>() / 256.0;
        assert!(mean.length() < 1e-2);
        assert!(n.iter().all(|d| (d.length() - 1.0).abs() < 1e-12));
    }
}
