//! The shading frame at a surface point and the rule that turns it about the normal (module
//! doc of `conventions`: "Shading frame", "Frame of isotropic tabulated materials"), kept
//! beside the other conventions and re-exported from there.

use super::wrap_azimuth;
use glam::{DVec3, Vec3};
use std::f32::consts::TAU;

/// A right-handed orthonormal shading frame at a surface point (see the module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadingFrame {
    /// Tangent (azimuth 0): world up projected onto the tangent plane
    /// ([`ShadingFrame::from_normal`]), or the mesh's tangent projected
    /// ([`ShadingFrame::from_normal_tangent`]), turned about `n` by a [`FrameRule`].
    pub t: Vec3,
    /// Bitangent `n x t` (azimuth pi/2).
    pub b: Vec3,
    /// Unit normal (polar 0, local +z).
    pub n: Vec3,
}

impl ShadingFrame {
    /// Builds the frame for a unit normal `n`.
    ///
    /// Fails by documented fallback: a zero or non-finite `n` is replaced by +z (whose frame
    /// is `t = +y`, `b = -x`); a non-unit `n` is normalised first.
    #[inline]
    pub fn from_normal(n: Vec3) -> Self {
        let n = n.try_normalize().unwrap_or(Vec3::Z);
        let s2 = n.x * n.x + n.z * n.z;
        let t = if s2 > 0.0 {
            let s = s2.sqrt();
            let inv = 1.0 / s;
            Vec3::new(-n.x * n.y * inv, s, -n.z * n.y * inv)
        } else {
            Vec3::new(0.0, 0.0, -n.y.signum())
        };
        let b = n.cross(t);
        ShadingFrame { t, b, n }
    }

    /// The frame of unit normal `n` whose tangent is `tangent` projected onto the tangent
    /// plane ("Frame of anisotropic materials" in the module doc): `t = normalize(tangent -
    /// n (n . tangent))`, `b = n x t`.
    ///
    /// Fails by documented fallback: where `tangent` is zero or non-finite, or its part in
    /// the tangent plane is below [`MIN_TANGENT_SIN`] of its length, the world-up frame
    /// [`ShadingFrame::from_normal`] of `n`.
    #[inline]
    pub fn from_normal_tangent(n: Vec3, tangent: Vec3) -> Self {
        let up = Self::from_normal(n);
        let n = up.n;
        let along = tangent - n * n.dot(tangent);
        let (l2, t2) = (along.length_squared(), tangent.length_squared());
        if !(l2 > MIN_TANGENT_SIN * MIN_TANGENT_SIN * t2 && l2.is_finite()) {
            return up;
        }
        let t = along / l2.sqrt();
        ShadingFrame {
            t,
            b: n.cross(t),
            n,
        }
    }

    /// World direction to local coordinates (local +z is the normal): `local_from_world`.
    #[inline]
    pub fn to_local(&self, d: Vec3) -> Vec3 {
        Vec3::new(d.dot(self.t), d.dot(self.b), d.dot(self.n))
    }

    /// Local coordinates back to a world direction: `world_from_local`.
    #[inline]
    pub fn to_world(&self, l: Vec3) -> Vec3 {
        self.t * l.x + self.b * l.y + self.n * l.z
    }

    /// The frame turned about `n` by the angle whose cosine and sine are `(c, s)`
    /// (right-handed: `t' = c t + s b`, `b' = c b - s t`), so a direction of azimuth `a`
    /// here has azimuth `a - angle` in the result. Exact rotation up to f32 rounding;
    /// `(c, s)` must be a unit pair.
    #[inline]
    pub fn turned(&self, c: f32, s: f32) -> ShadingFrame {
        ShadingFrame {
            t: self.t * c + self.b * s,
            b: self.b * c - self.t * s,
            n: self.n,
        }
    }

    /// The frame turned about `n` so that world direction `v` (unit) has the azimuth of
    /// the unit pair `(cos, sin)` in it (see "Frame of isotropic tabulated materials" in
    /// the module doc). Unchanged when `v` is within 1e-6 of the normal's axis, where its
    /// azimuth is not defined.
    #[inline]
    pub fn turned_to_view(&self, v: Vec3, cos: f32, sin: f32) -> ShadingFrame {
        let (x, y) = (v.dot(self.t), v.dot(self.b));
        let h = (x * x + y * y).sqrt();
        if !(h > VIEW_TURN_MIN_SIN) {
            return *self;
        }
        // The view's azimuth phi here: (cos phi, sin phi) = (x, y) / h; turn by phi - a.
        let (cp, sp) = (x / h, y / h);
        self.turned(cp * cos + sp * sin, sp * cos - cp * sin)
    }

    /// The frame of a surface point under `rule`: [`ShadingFrame::from_normal`] of `n`,
    /// then (for [`FrameRule::view_azimuth`]) turned so that the world view `v` (unit, from
    /// the point to the eye) lies at that azimuth ([`ShadingFrame::turned_to_view`]).
    #[inline]
    pub fn at(n: Vec3, v: Vec3, rule: &FrameRule) -> ShadingFrame {
        rule.apply(ShadingFrame::from_normal(n), v)
    }
}

/// Below this sine of the angle between a mesh tangent and the normal (or for a zero
/// tangent), [`ShadingFrame::from_normal_tangent`] falls back to the world-up frame.
pub const MIN_TANGENT_SIN: f32 = 1e-3;

/// Below this sine of the angle between the view and the normal's axis,
/// [`ShadingFrame::turned_to_view`] keeps the frame (the view's azimuth is undefined).
pub const VIEW_TURN_MIN_SIN: f32 = 1e-6;

/// How a material's shading frame is chosen about the normal (module doc, "Frame of
/// isotropic tabulated materials"). [`FrameRule::UP`] is the frame of [`ShadingFrame::from_normal`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameRule {
    /// `Some((cos a, sin a))`: turn the frame about the normal until the view lies at
    /// azimuth `a` (isotropic tabulated materials); `None`: the base frame's tangent.
    pub view_azimuth: Option<(f32, f32)>,
    /// The base frame's tangent is the mesh's ([`ShadingFrame::from_normal_tangent`]:
    /// anisotropic materials on a mesh with tangents) rather than world up
    /// ([`ShadingFrame::from_normal`]).
    pub mesh_tangent: bool,
    /// **Test only**: turn the world-up frame by a pseudo-random angle per normal first
    /// ([`scramble_angle`]), for the test that an isotropic material's image does not
    /// depend on the tangent frame. No scene setting or command-line option reaches it.
    pub scramble: bool,
}

impl FrameRule {
    /// The world-up tangent frame (anisotropic materials, analytic models).
    pub const UP: FrameRule = FrameRule {
        view_azimuth: None,
        mesh_tangent: false,
        scramble: false,
    };

    /// The mesh's tangent (anisotropic materials; module doc, "Frame of anisotropic
    /// materials").
    pub const MESH_TANGENT: FrameRule = FrameRule {
        view_azimuth: None,
        mesh_tangent: true,
        scramble: false,
    };

    /// The view-aligned frame with the view at `azimuth` (radians).
    pub fn view_at(azimuth: f32) -> FrameRule {
        let (s, c) = azimuth.sin_cos();
        FrameRule {
            view_azimuth: Some((c, s)),
            mesh_tangent: false,
            scramble: false,
        }
    }

    /// The frame this rule starts from at normal `n` with the surface's `tangent`
    /// ([`FrameRule::mesh_tangent`]), before [`FrameRule::apply`] turns it.
    #[inline]
    pub fn base(&self, n: Vec3, tangent: Vec3) -> ShadingFrame {
        if self.mesh_tangent {
            ShadingFrame::from_normal_tangent(n, tangent)
        } else {
            ShadingFrame::from_normal(n)
        }
    }

    /// `base` (the frame of [`FrameRule::base`]) under this rule, for the
    /// unit world view `v`: scrambled first when [`FrameRule::scramble`], then turned to the
    /// view's azimuth when the rule fixes one.
    #[inline]
    pub fn apply(&self, base: ShadingFrame, v: Vec3) -> ShadingFrame {
        let mut f = base;
        if self.scramble {
            let (s, c) = scramble_angle(f.n).sin_cos();
            f = f.turned(c, s);
        }
        match self.view_azimuth {
            Some((c, s)) => f.turned_to_view(v, c, s),
            None => f,
        }
    }

    /// The view's azimuth in the frame, radians, when the rule fixes it.
    pub fn azimuth(&self) -> Option<f32> {
        self.view_azimuth.map(|(c, s)| wrap_azimuth(s.atan2(c)))
    }
}

/// The test-only pseudo-random turn of [`FrameRule::scramble`], radians in [0, 2 pi): a
/// hash of the normal's bits, so neighbouring pixels get unrelated angles.
pub fn scramble_angle(n: Vec3) -> f32 {
    let mut h = n.x.to_bits() ^ n.y.to_bits().rotate_left(11) ^ n.z.to_bits().rotate_left(22);
    h ^= h >> 16;
    h = h.wrapping_mul(0x7feb_352d);
    h ^= h >> 15;
    h = h.wrapping_mul(0x846c_a68b);
    h ^= h >> 16;
    (h >> 8) as f32 / (1u32 << 24) as f32 * TAU
}

/// The isotropic material's frame at unit normal `n` for unit view `v`, in f64 (the
/// reference sums' form of "Frame of isotropic tabulated materials" in the module doc):
/// `(x, y, wo)` with `x` the view's direction in the tangent plane (azimuth 0), `y = n x x`,
/// and `wo = (v.x, 0, cos_o)` the view in that frame, `cos_o = n.v` clamped to [0, 1].
///
/// Fails by documented fallback: where `v` is within 1e-12 of the normal's axis (no
/// tangent direction), `x` is any unit vector orthogonal to `n`.
pub fn view_frame_f64(n: DVec3, v: DVec3) -> (DVec3, DVec3, DVec3) {
    let cos_o = n.dot(v).clamp(0.0, 1.0);
    let tangent = v - cos_o * n;
    let x = if tangent.length_squared() > 1e-24 {
        tangent.normalize()
    } else {
        n.any_orthonormal_vector()
    };
    let y = n.cross(x);
    (x, y, DVec3::new(v.dot(x), 0.0, cos_o))
}
