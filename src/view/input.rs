//! Input mapping: what a key, a drag or a wheel notch does, as one [`Action`] each.
//!
//! The window's events (`app.rs`) and the script's lines ([`super::script`]) both go
//! through here, so a script drives the viewer exactly as a person does. The controls table
//! of docs/viewer.md ("Controls") is this file's [`CONTROLS`].

/// One change a person asks for.
#[derive(Clone, Debug, PartialEq)]
pub enum Action {
    /// Orbit the camera about its target: a mouse drag by `(dx, dy)` window pixels
    /// (right and down positive).
    Orbit {
        dx: f64,
        dy: f64,
    },
    /// Turn the environment about world up (+y): a shift-drag by `dx` window pixels.
    TurnEnvironment {
        dx: f64,
    },
    /// Move the camera towards its target (positive) or away: wheel notches.
    Zoom {
        notches: f64,
    },
    NextMaterial,
    PreviousMaterial,
    NextProbe,
    /// `[env] method`: lights -> transfer -> lightcuts -> lights.
    NextMethod,
    /// `[env] count` times 2.
    MoreLights,
    /// `[env] count` divided by 2.
    FewerLights,
    /// `render.band_skip`: an SH data set's declared band threshold on or off.
    ToggleBandSkip,
    /// `material.lookup`: nearest <-> bilinear (SH materials).
    ToggleLookup,
    /// `output.exposure` plus or minus this many stops.
    Exposure(f32),
    /// The debug output shown: none -> normal -> depth -> ... -> none.
    NextAov,
    /// The probe behind the object on or off (display only).
    ToggleBackground,
    /// The status line on or off (display only).
    ToggleOverlay,
    /// Back to the scene as the viewer opened it.
    Reset,
    Quit,
}

/// Pixels of drag per radian of orbit (yaw and pitch).
pub const DRAG_PIXELS_PER_RADIAN: f64 = 200.0;
/// Pixels of shift-drag per degree of environment turn.
pub const ENV_PIXELS_PER_DEGREE: f64 = 2.0;
/// Camera distance factor per wheel notch towards the target.
pub const ZOOM_PER_NOTCH: f64 = 0.9;

/// The controls: (input, what it does), in the order docs/viewer.md's table lists them.
pub const CONTROLS: [(&str, &str); 17] = [
    ("drag", "orbit the camera about its target"),
    ("wheel", "zoom (camera distance x0.9 per notch)"),
    ("shift + drag", "turn the environment about +y"),
    (
        "m / n",
        "next / previous material (library, and the scene's own)",
    ),
    (
        "p",
        "next probe (the scene's, --env, --probe, the shipped ones, none)",
    ),
    ("e", "environment method: lights -> transfer -> lightcuts"),
    ("] / [", "environment light count x2 / /2"),
    ("b", "SH band skip (declared band threshold) on / off"),
    ("l", "SH coefficient lookup nearest / bilinear"),
    ("+ / -", "exposure +0.5 / -0.5 stop"),
    ("a", "next AOV (debug output), then the shaded image"),
    ("g", "probe background behind the object on / off"),
    ("h", "status line on / off"),
    ("r", "reset to the opening view"),
    ("q / Esc", "quit"),
    (
        "(still)",
        "refine: more lights, nothing dropped, every band",
    ),
    (
        "(status)",
        "frame ms, frames/s, size, material, method, lights, refine step",
    ),
];

/// The action of key `name` (a character as typed, or `escape`), if any.
pub fn key_action(name: &str) -> Option<Action> {
    Some(match name.to_ascii_lowercase().as_str() {
        "m" => Action::NextMaterial,
        "n" => Action::PreviousMaterial,
        "p" => Action::NextProbe,
        "e" => Action::NextMethod,
        "]" => Action::MoreLights,
        "[" => Action::FewerLights,
        "b" => Action::ToggleBandSkip,
        "l" => Action::ToggleLookup,
        "+" | "=" => Action::Exposure(0.5),
        "-" => Action::Exposure(-0.5),
        "a" => Action::NextAov,
        "g" => Action::ToggleBackground,
        "h" => Action::ToggleOverlay,
        "r" => Action::Reset,
        "q" | "esc" | "escape" => Action::Quit,
        _ => return None,
    })
}

/// The action of a drag by `(dx, dy)` window pixels, with shift held or not.
pub fn drag_action(dx: f64, dy: f64, shift: bool) -> Action {
    if shift {
        Action::TurnEnvironment { dx }
    } else {
        Action::Orbit { dx, dy }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_listed_key_maps_to_an_action() {
        let mouse = ["drag", "wheel", "shift + drag"];
        let keys = CONTROLS
            .iter()
            .filter(|(k, _)| !mouse.contains(k) && !k.starts_with('('));
        for (keys, _) in keys {
            for k in keys.split(" / ") {
                assert!(key_action(k).is_some(), "{k}");
            }
        }
        assert_eq!(key_action("x"), None);
        assert_eq!(key_action("M"), Some(Action::NextMaterial));
    }
}
