//! The field checkers every part of scene resolution uses: a value checked once, else an
//! error naming its field ([`Error::field`]).

use crate::error::{Error, Result};
use glam::Vec3;

/// A finite vector, else a field error naming `field`.
pub(super) fn vec3(field: &str, v: [f32; 3]) -> Result<Vec3> {
    let v = Vec3::from(v);
    if !v.is_finite() {
        return Err(Error::field(
            field,
            format!("[{}, {}, {}] is not finite", v.x, v.y, v.z),
        ));
    }
    Ok(v)
}

/// A finite number >= 0, else a field error naming `field`.
pub(super) fn nonneg(field: &str, x: f32) -> Result<f32> {
    if !(x.is_finite() && x >= 0.0) {
        return Err(Error::field(
            field,
            format!("{x} must be a finite number >= 0"),
        ));
    }
    Ok(x)
}

/// An RGB triple of finite numbers >= 0, else a field error naming `field`.
pub(super) fn rgb(field: &str, v: [f32; 3]) -> Result<Vec3> {
    for x in v {
        nonneg(field, x)?;
    }
    Ok(Vec3::from(v))
}

/// The message of a field error without its field (to re-attach another field name).
pub(super) fn strip_field(e: Error) -> String {
    match e {
        Error::Field { message, .. } => message,
        other => other.to_string(),
    }
}
