//! Diagnostic behind the module doc of `brdfkit::acquire` ("Why the view weights"):
//! per-view-row error and ringing of a least-squares SH acquisition on a 16x8 view grid,
//! and a check of the Ashikhmin-Shirley code against an f64 transcription of the paper.
//! `cargo run --release --example acquire_rows -- SOURCE [BANDS,..] [x = summary only]`
use brdfkit::acquire::{acquire, AcquireOptions, ErrorGrid, Method};
use brdfkit::brdf::{eval_cosine_weighted, AshikhminShirley, Brdf};
use brdfkit::conventions::{hemi_texel_angles_f64, local_direction_f64};
use glam::{DVec3, Vec3};

fn as_ref(m: &AshikhminShirley, k1: DVec3, k2: DVec3) -> DVec3 {
    let h = (k1 + k2).normalize();
    let phi = h.y.atan2(h.x);
    let e = m.nu as f64 * phi.cos().powi(2) + m.nv as f64 * phi.sin().powi(2);
    let kh = k1.dot(h);
    let pi = std::f64::consts::PI;
    let rs = m.rs.as_dvec3();
    let rd = m.rd.as_dvec3();
    let f = rs + (DVec3::ONE - rs) * (1.0 - kh).powi(5);
    let ps = ((m.nu as f64 + 1.0) * (m.nv as f64 + 1.0)).sqrt() / (8.0 * pi) * h.z.powf(e)
        / (kh * k1.z.max(k2.z))
        * f;
    let pd = 28.0 * rd / (23.0 * pi)
        * (DVec3::ONE - rs)
        * (1.0 - (1.0 - k1.z / 2.0).powi(5))
        * (1.0 - (1.0 - k2.z / 2.0).powi(5));
    ps + pd
}

fn main() {
    // A-S check against an independent f64 transcription of the paper's formula.
    let m = AshikhminShirley {
        nu: 12.0,
        nv: 40.0,
        rs: Vec3::new(0.04, 0.5, 0.9),
        rd: Vec3::new(0.7, 0.1, 0.3),
    };
    let mut worst = 0.0f64;
    for a in 0..20 {
        for b in 0..20 {
            for c in 0..7 {
                let k1 = local_direction_f64(0.05 + 1.45 * a as f64 / 20.0, c as f64 * 0.9);
                let k2 = local_direction_f64(0.05 + 1.45 * b as f64 / 20.0, 0.3 + b as f64 * 0.37);
                let r = as_ref(&m, k1, k2);
                let x = m.eval(k1.as_vec3(), k2.as_vec3()).as_dvec3();
                worst = worst.max(((x - r).abs() / r.abs().max(DVec3::splat(1e-9))).max_element());
            }
        }
    }
    println!("A-S vs f64 paper formula: worst relative difference {worst:.2e}");
    let args: Vec<String> = std::env::args().collect();
    let name = args.get(1).map(String::as_str).unwrap_or("magenta-plastic");
    let bands: Vec<usize> = args
        .get(2)
        .map(|s| s.split(',').map(|x| x.parse().unwrap()).collect())
        .unwrap_or(vec![2, 5, 8]);
    let rowsonly = args.get(3).is_some();
    let src = brdfkit::cli::source::parse_source(name).unwrap();
    let (nu, nv) = (16, 8);
    let grid = ErrorGrid::default();
    let dirs = grid.directions();
    for &b in &bands {
        let ds = acquire(
            src.as_ref(),
            &AcquireOptions::new(b, nu, nv, Method::Lsq { lambda: 1e-6 }),
        )
        .unwrap();
        println!("{name} bands {b}");
        if !rowsonly {
            println!(
                " row polar  w_row  e2share  s2share  relL2row  srcpeak  min/peak_texel  neg_share"
            );
        }
        let (mut e2t, mut s2t, mut e2w, mut s2w, mut hig, mut log) =
            (0.0, 0.0, 0.0, 0.0, 0.0f64, 0.0f64);
        let (mut rmean, mut nmean) = (0.0, 0.0);
        let mut rows = vec![];
        for j in 0..nv {
            let t0 = (j as f64 / nv as f64) * std::f64::consts::FRAC_PI_2;
            let t1 = ((j + 1) as f64 / nv as f64) * std::f64::consts::FRAC_PI_2;
            let w = t1.sin().powi(2) - t0.sin().powi(2); // fraction of projected solid angle of the row
            let (mut e2, mut s2, mut rmin, mut sp, mut neg) = (0.0, 0.0, 0.0f64, 0.0f64, 0.0);
            let mut polar = 0.0;
            for i in 0..nu {
                let (p, a) = hemi_texel_angles_f64(i, j, nu, nv);
                polar = p;
                let wo = local_direction_f64(p, a).as_vec3();
                let (mut hi, mut lo, mut n, mut tot) = (0.0f64, 0.0f64, 0.0, 0.0);
                for d in &dirs {
                    let wi = d.as_vec3();
                    let s = eval_cosine_weighted(src.as_ref(), wi, wo).as_dvec3();
                    let x = eval_cosine_weighted(&ds, wi, wo).as_dvec3();
                    e2 += (x - s).length_squared();
                    s2 += s.length_squared();
                    hi = hi.max(x.max_element());
                    lo = lo.min(x.min_element());
                    sp = sp.max(s.max_element());
                    n += (-x).max(DVec3::ZERO).element_sum();
                    tot += x.abs().element_sum();
                }
                hig = hig.max(hi);
                log = log.min(lo);
                let r = (lo / hi).min(0.0);
                rmin = rmin.min(r);
                rmean += w / nu as f64 * r;
                neg += n / tot / nu as f64;
            }
            nmean += w * neg;
            e2t += e2;
            s2t += s2;
            e2w += w * e2;
            s2w += w * s2;
            rows.push((polar, w, e2, s2, sp, rmin, neg));
        }
        if !rowsonly {
            for (j, r) in rows.iter().enumerate() {
                println!(
                    "{j:>4} {:>5.1} {:>6.3} {:>8.4} {:>8.4} {:>9.4} {:>8.3} {:>12.2}% {:>9.2}%",
                    r.0.to_degrees(),
                    r.1,
                    r.2 / e2t,
                    r.3 / s2t,
                    (r.2 / r.3).sqrt(),
                    r.4,
                    100.0 * r.5,
                    100.0 * r.6
                );
            }
        }
        let inner_min = rows[..nv - 1].iter().fold(0.0f64, |a, r| a.min(r.5));
        println!(" relL2 unweighted {:.4} weighted {:.4} | global min/peak {:.2}% | mean texel min/peak {:.2}% | inner rows min {:.2}% | neg share {:.2}%",
            (e2t / s2t).sqrt(), (e2w / s2w).sqrt(), 100.0 * log / hig, 100.0 * rmean, 100.0 * inner_min, 100.0 * nmean);
    }
}
