//! Pinhole camera: look-at placement and a vertical field of view.
//!
//! Projection: glam's `perspective_infinite_reverse_rh` (right-handed view space looking
//! down -z; clip `w` = view distance; depth as 1/w, larger is nearer; no far plane).

use crate::mesh::Bounds;
use glam::{Mat4, Vec3};

/// A camera placed by look-at.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub position: Vec3,
    pub target: Vec3,
    pub up: Vec3,
    /// Vertical field of view in degrees, in (0, 180).
    pub fov_y_deg: f32,
    /// Near clipping distance (> 0), in scene units.
    pub near: f32,
}

/// Direction the auto-framed camera looks from (towards the mesh centre): in front, a
/// little to the right and above, like the thesis's teapot figures.
pub const AUTO_VIEW_FROM: Vec3 = Vec3::new(0.35, 0.45, 1.0);
/// Default vertical field of view (degrees).
pub const DEFAULT_FOV_Y_DEG: f32 = 35.0;

impl Camera {
    /// Frames a mesh for the given aspect ratio (width / height): the sphere of radius
    /// `radius` around the centre of `bounds` fits the narrower field of view with a 5%
    /// margin. Near is 1/1000 of the distance.
    pub fn frame(bounds: &Bounds, radius: f32, aspect: f32, fov_y_deg: f32) -> Camera {
        let r = radius.max(1e-30);
        let half_y = 0.5 * fov_y_deg.to_radians();
        let half_x = (half_y.tan() * aspect).atan();
        let half = half_y.min(half_x);
        let dist = 1.05 * r / half.sin();
        let target = bounds.center();
        Camera {
            position: target + AUTO_VIEW_FROM.normalize() * dist,
            target,
            up: Vec3::Y,
            fov_y_deg,
            near: dist * 1e-3,
        }
    }

    /// `view_from_world`. If `up` is parallel to the viewing direction, +z (or +x) is
    /// used as up instead, so the matrix is always finite for distinct position and target.
    pub fn view_from_world(&self) -> Mat4 {
        let fwd = (self.target - self.position).normalize_or(Vec3::NEG_Z);
        let mut up = self.up.normalize_or(Vec3::Y);
        if fwd.cross(up).length_squared() < 1e-12 {
            up = if fwd.cross(Vec3::Z).length_squared() < 1e-12 {
                Vec3::X
            } else {
                Vec3::Z
            };
        }
        Mat4::look_to_rh(self.position, fwd, up)
    }

    /// `clip_from_view` for a target of the given aspect ratio.
    pub fn clip_from_view(&self, aspect: f32) -> Mat4 {
        Mat4::perspective_infinite_reverse_rh(self.fov_y_deg.to_radians(), aspect, self.near)
    }
}
