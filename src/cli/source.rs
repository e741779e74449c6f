//! The `SOURCE` argument of `brdfkit acquire` and `brdfkit fit-dbrdf`: which BRDF to measure.
//!
//! Design rule: one parser, tried in a fixed order, each form unambiguous:
//! 1. a library material name ([`crate::library::LIBRARY`], e.g. `blue-silk`): its
//!    *source model* ([`crate::brdf::stand_ins`], not its rendering representation);
//! 2. a path ending in `.binary`: a MERL table ([`crate::brdf::MerlBrdf::read`]); a path
//!    ending in `.bsdf`: an RGL material ([`crate::brdf::RglBrdf::read`]);
//! 3. an analytic spec `KIND[:KEY=VALUE,...]` with KIND `lambert` (albedo),
//!    `blinn-phong` / `phong` (kd, ks, exponent) or `ashikhmin-shirley` (nu, nv, rs, rd).
//!    A colour is `r/g/b` or one number for grey; omitted keys take the scene defaults
//!    (`kd = 0.55/0.22/0.12`, `ks = 0.25`, `exponent = 60`, `albedo = 0.8`,
//!    `nu = nv = 100`, `rs = 0.05`, `rd = 0.5`).
//!
//! Errors name the argument (`SOURCE`) or the key and say what is wrong, in one line.

use crate::brdf::{AshikhminShirley, BlinnPhong, Brdf, Lambert, MerlBrdf, Phong, RglBrdf};
use crate::error::{Error, Result};
use glam::Vec3;
use std::path::Path;
use std::sync::Arc;

fn number(key: &str, v: &str) -> Result<f32> {
    let x: f32 = v.trim().parse().map_err(|_| {
        Error::field(
            format!("SOURCE key `{key}`"),
            format!("{v:?} is not a number"),
        )
    })?;
    if !(x.is_finite() && x >= 0.0) {
        return Err(Error::field(
            format!("SOURCE key `{key}`"),
            format!("{x} must be a finite number >= 0"),
        ));
    }
    Ok(x)
}

fn colour(key: &str, v: &str) -> Result<Vec3> {
    let parts: Vec<&str> = v.split('/').collect();
    match parts.as_slice() {
        [g] => Ok(Vec3::splat(number(key, g)?)),
        [r, g, b] => Ok(Vec3::new(number(key, r)?, number(key, g)?, number(key, b)?)),
        _ => Err(Error::field(
            format!("SOURCE key `{key}`"),
            format!("{v:?} is not a colour (r/g/b or one number)"),
        )),
    }
}

/// Parses `SOURCE` (module doc). Fails with a field error naming `SOURCE` or the key, or
/// with the MERL or RGL reader's error naming the file.
pub fn parse_source(s: &str) -> Result<Arc<dyn Brdf>> {
    if let Some(m) = crate::brdf::stand_ins::source_model(s) {
        return Ok(m);
    }
    if s.ends_with(".binary") {
        let m = MerlBrdf::read(Path::new(s)).map_err(|e| Error::format(s, e.to_string()))?;
        return Ok(Arc::new(m));
    }
    if s.ends_with(".bsdf") {
        let m = RglBrdf::read(Path::new(s)).map_err(|e| Error::format(s, e.to_string()))?;
        return Ok(Arc::new(m));
    }
    let (kind, rest) = s.split_once(':').unwrap_or((s, ""));
    let mut kv = Vec::new();
    for item in rest.split(',').filter(|x| !x.trim().is_empty()) {
        let (k, v) = item
            .split_once('=')
            .ok_or_else(|| Error::field("SOURCE", format!("{item:?} is not KEY=VALUE")))?;
        kv.push((k.trim().to_string(), v.trim().to_string()));
    }
    let allowed: &[&str] = match kind {
        "lambert" => &["albedo"],
        "blinn-phong" | "phong" => &["kd", "ks", "exponent"],
        "ashikhmin-shirley" => &["nu", "nv", "rs", "rd"],
        _ => {
            return Err(Error::field(
                "SOURCE",
                format!(
                    "{s:?} is not a library material (see `brdfkit materials`), a MERL .binary \
                     or RGL .bsdf path, or an analytic spec (lambert, blinn-phong, phong, ashikhmin-shirley)"
                ),
            ))
        }
    };
    for (k, _) in &kv {
        if !allowed.contains(&k.as_str()) {
            return Err(Error::field(
                format!("SOURCE key `{k}`"),
                format!("unknown for {kind} (known: {})", allowed.join(", ")),
            ));
        }
    }
    let get = |k: &str| kv.iter().find(|(a, _)| a == k).map(|(_, v)| v.as_str());
    let col = |k: &str, d: Vec3| get(k).map_or(Ok(d), |v| colour(k, v));
    let num = |k: &str, d: f32| get(k).map_or(Ok(d), |v| number(k, v));
    Ok(match kind {
        "lambert" => Arc::new(Lambert {
            albedo: col("albedo", Vec3::splat(0.8))?,
        }),
        "blinn-phong" => Arc::new(BlinnPhong {
            kd: col("kd", Vec3::new(0.55, 0.22, 0.12))?,
            ks: col("ks", Vec3::splat(0.25))?,
            exponent: num("exponent", 60.0)?,
        }),
        "phong" => Arc::new(Phong {
            kd: col("kd", Vec3::new(0.55, 0.22, 0.12))?,
            ks: col("ks", Vec3::splat(0.25))?,
            exponent: num("exponent", 60.0)?,
        }),
        _ => Arc::new(AshikhminShirley {
            nu: num("nu", 100.0)?,
            nv: num("nv", 100.0)?,
            rs: col("rs", Vec3::splat(0.05))?,
            rd: col("rd", Vec3::splat(0.5))?,
        }),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err(s: &str) -> String {
        match parse_source(s) {
            Ok(b) => panic!("{s:?} parsed as {}", b.name()),
            Err(e) => e.to_string(),
        }
    }

    #[test]
    fn parses_specs_and_names_bad_keys() {
        let b = parse_source("ashikhmin-shirley:nu=10,nv=200,rs=0.1/0.2/0.3").unwrap();
        assert_eq!(b.name(), "ashikhmin-shirley");
        assert_eq!(parse_source("lambert").unwrap().name(), "lambert");
        assert_eq!(parse_source("blue-silk").unwrap().name(), "lambert-dbrdf");
        let e = err("lambert:kd=1");
        assert!(e.contains("`kd`"), "{e}");
        let e = err("phong:exponent=x");
        assert!(
            e.contains("`exponent`") && e.contains("not a number"),
            "{e}"
        );
        let e = err("nonsense");
        assert!(e.starts_with("SOURCE"), "{e}");
        let e = err("/nonexistent/x.binary");
        assert!(e.contains("x.binary"), "{e}");
        let e = err("/nonexistent/y.bsdf");
        assert!(e.contains("y.bsdf") && e.contains("RGL"), "{e}");
    }
}
