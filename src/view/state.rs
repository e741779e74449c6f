//! The viewer's state: the scene file being looked at (the "document"), changed by
//! [`Action`]s, and the display-only choices beside it.
//!
//! Design rule: everything that changes the rendered pixels is a field of the document, a
//! [`SceneFile`], so a frame is exactly `brdfkit render` of the document (written as TOML
//! by [`super::scene_toml`]); only the AOV shown, the probe background and the status line
//! live beside it. The camera orbits its target about world up (+y): yaw about +y, pitch
//! towards +y, distance; the placed camera is written to `[camera]` (position, target, up,
//! field of view) and placed by [`crate::scene::resolve_camera`], as `render` places it.

use super::input::{Action, DRAG_PIXELS_PER_RADIAN, ENV_PIXELS_PER_DEGREE, ZOOM_PER_NOTCH};
use crate::aov::Aov;
use crate::env::schema::{EnvMethod, EnvSpec, MAX_LIGHTS};
use crate::error::Result;
use crate::mesh::Mesh;
use crate::scene::{resolve_camera, CameraSpec, MaterialSpec, SceneFile};
use crate::sh::Lookup;
use clap::ValueEnum;
use glam::DVec3;
use std::path::PathBuf;
use std::sync::Arc;

/// Largest pitch of the orbit (radians): just short of the poles, where yaw is undefined.
const MAX_PITCH: f64 = 1.55;

/// The orbit of a placed camera about its target.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Orbit {
    target: DVec3,
    /// Radians about +y, 0 looking from +z, increasing towards +x.
    yaw: f64,
    /// Radians above the target's horizontal plane.
    pitch: f64,
    /// Distance from the target (scene units).
    distance: f64,
}

impl Orbit {
    fn position(&self) -> DVec3 {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        self.target + self.distance * DVec3::new(cp * sy, sp, cp * cy)
    }
}

/// The viewer's state (module doc).
#[derive(Clone)]
pub struct ViewState {
    /// The state as opened (for reset).
    opened: Option<Box<ViewState>>,
    /// The document: what is rendered.
    pub file: SceneFile,
    /// The mesh, for placing the camera on the first orbit (auto-framing needs it).
    mesh: Arc<Mesh>,
    orbit: Option<Orbit>,
    /// Materials M/N cycle through, and the index of the current one.
    pub materials: Vec<MaterialSpec>,
    material: usize,
    /// Probes P cycles through (`None`: the scene's own lights), and the current one.
    pub probes: Vec<Option<PathBuf>>,
    probe: usize,
    /// The environment settings a probe is shown with (kept across probes).
    env_settings: EnvSpec,
    /// The debug output shown instead of the shaded image.
    pub aov: Option<Aov>,
    pub background: bool,
    pub overlay: bool,
    /// A one-line note for the status line (what a key could not do).
    pub note: Option<String>,
}

/// A display name for a material spec.
pub fn material_name(m: &MaterialSpec) -> String {
    match m {
        MaterialSpec::Library { name, .. } => name.clone(),
        MaterialSpec::ShFile { path, .. }
        | MaterialSpec::DbrdfFile { path }
        | MaterialSpec::MerlFile { path }
        | MaterialSpec::RglFile { path } => path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default(),
        MaterialSpec::Lambert { .. } => "lambert".into(),
        MaterialSpec::BlinnPhong { .. } => "blinn-phong".into(),
    }
}

impl ViewState {
    /// The state for document `file` (paths absolute), mesh `mesh`, the extra probes to
    /// cycle through (`--env`'s and `--probe`'s, then the shipped ones) and the AOV to show.
    pub fn new(
        file: SceneFile,
        mesh: Arc<Mesh>,
        extra_probes: &[PathBuf],
        aov: Option<Aov>,
    ) -> ViewState {
        let mut materials = vec![file.material.clone()];
        for e in crate::library::LIBRARY.iter() {
            if !matches!(&file.material, MaterialSpec::Library { name, .. } if name == e.name) {
                materials.push(MaterialSpec::Library {
                    name: e.name.to_string(),
                    lookup: None,
                });
            }
        }
        // Library materials in the library's order, the scene's own in its place (or first).
        let own = materials.remove(0);
        let at = crate::library::LIBRARY
            .iter()
            .position(|e| matches!(&own, MaterialSpec::Library { name, .. } if name == e.name))
            .unwrap_or(0);
        materials.insert(at, own);
        let mut probes: Vec<Option<PathBuf>> = Vec::new();
        let mut push = |p: Option<PathBuf>| {
            let same = |q: &Option<PathBuf>| match (q, &p) {
                (Some(a), Some(b)) => {
                    a == b || std::fs::canonicalize(a).ok() == std::fs::canonicalize(b).ok()
                }
                (None, None) => true,
                _ => false,
            };
            if !probes.iter().any(same) {
                probes.push(p);
            }
        };
        if let Some(e) = &file.env {
            push(Some(e.file.clone()));
        }
        for p in extra_probes {
            push(Some(p.clone()));
        }
        push(None);
        let current = file.env.as_ref().map(|e| e.file.clone());
        let probe = probes.iter().position(|p| *p == current).unwrap_or(0);
        let env_settings = file
            .env
            .clone()
            .unwrap_or_else(|| EnvSpec::new(PathBuf::new()));
        let mut s = ViewState {
            opened: None,
            file,
            mesh,
            orbit: None,
            materials,
            material: at,
            probes,
            probe,
            env_settings,
            aov,
            background: false,
            overlay: true,
            note: None,
        };
        s.opened = Some(Box::new(s.clone()));
        s
    }

    /// This state with the probe background on or off, also after a reset.
    pub fn with_background(mut self, on: bool) -> ViewState {
        self.background = on;
        if let Some(o) = self.opened.as_mut() {
            o.background = on;
        }
        self
    }

    /// The render size (pixels), the window's inner size.
    pub fn set_size(&mut self, width: u32, height: u32) {
        self.file.render.width = width.clamp(1, crate::scene::MAX_SIDE);
        self.file.render.height = height.clamp(1, crate::scene::MAX_SIDE);
    }

    pub fn material_name(&self) -> String {
        material_name(&self.materials[self.material])
    }

    /// The current orbit, placing the camera first (as `render` would at this size) when
    /// no action has moved it yet.
    fn orbit(&mut self) -> Result<Orbit> {
        if let Some(o) = self.orbit {
            return Ok(o);
        }
        let r = &self.file.render;
        let aspect = r.width as f32 / r.height as f32;
        let spec = self.file.camera.clone().unwrap_or_default();
        let cam = resolve_camera(&spec, &self.mesh, aspect)?;
        let rel = (cam.position - cam.target).as_dvec3();
        let distance = rel.length();
        let o = Orbit {
            target: cam.target.as_dvec3(),
            yaw: rel.x.atan2(rel.z),
            pitch: (rel.y / distance).clamp(-1.0, 1.0).asin(),
            distance,
        };
        Ok(o)
    }

    /// Writes orbit `o` to the document's `[camera]`.
    fn place(&mut self, o: Orbit) {
        self.orbit = Some(o);
        let old = self.file.camera.clone().unwrap_or_default();
        self.file.camera = Some(CameraSpec {
            position: Some(o.position().as_vec3().to_array()),
            target: Some(o.target.as_vec3().to_array()),
            up: old.up.or(Some([0.0, 1.0, 0.0])),
            fov_y_deg: old.fov_y_deg,
            near: old.near,
        });
    }

    /// Applies `a`. Returns whether the rendered pixels may change (false for display-only
    /// actions and for what could not be done, which leaves a note).
    pub fn apply(&mut self, a: &Action) -> Result<bool> {
        self.note = None;
        match a {
            Action::Orbit { dx, dy } => {
                let mut o = self.orbit()?;
                o.yaw -= dx / DRAG_PIXELS_PER_RADIAN;
                o.pitch = (o.pitch + dy / DRAG_PIXELS_PER_RADIAN).clamp(-MAX_PITCH, MAX_PITCH);
                self.place(o);
            }
            Action::Zoom { notches } => {
                let mut o = self.orbit()?;
                o.distance *= ZOOM_PER_NOTCH.powf(*notches);
                self.place(o);
            }
            Action::TurnEnvironment { dx } => match self.file.env.as_mut() {
                Some(env) => {
                    let r = env.rotation + dx / ENV_PIXELS_PER_DEGREE;
                    env.rotation = r.rem_euclid(360.0);
                    self.env_settings.rotation = env.rotation;
                }
                None => return self.noted("no environment to turn (p: next probe)"),
            },
            Action::NextMaterial | Action::PreviousMaterial => {
                let n = self.materials.len();
                self.material = match a {
                    Action::NextMaterial => (self.material + 1) % n,
                    _ => (self.material + n - 1) % n,
                };
                self.file.material = self.materials[self.material].clone();
            }
            Action::NextProbe => {
                self.probe = (self.probe + 1) % self.probes.len();
                self.file.env = self.probes[self.probe].clone().map(|p| EnvSpec {
                    file: p,
                    ..self.env_settings.clone()
                });
            }
            Action::NextMethod => {
                let Some(env) = self.file.env.as_mut() else {
                    return self.noted("no environment (p: next probe)");
                };
                let all = EnvMethod::value_variants();
                let i = all.iter().position(|m| *m == env.method).unwrap_or(0);
                env.method = all[(i + 1) % all.len()];
                self.env_settings.method = env.method;
            }
            Action::MoreLights | Action::FewerLights => {
                let Some(env) = self.file.env.as_mut() else {
                    return self.noted("no environment (p: next probe)");
                };
                env.count = match a {
                    Action::MoreLights => (env.count * 2).min(MAX_LIGHTS),
                    _ => (env.count / 2).max(1),
                };
                self.env_settings.count = env.count;
            }
            Action::ToggleBandSkip => self.file.render.band_skip = !self.file.render.band_skip,
            Action::ToggleLookup => match &mut self.file.material {
                MaterialSpec::Library { lookup, name }
                    if !matches!(
                        crate::library::find(name).map(|e| e.representation),
                        Some(crate::library::Representation::Dbrdf)
                    ) =>
                {
                    *lookup = Some(match lookup {
                        Some(Lookup::Nearest) => Lookup::Bilinear,
                        _ => Lookup::Nearest,
                    });
                }
                MaterialSpec::ShFile { lookup, .. } => {
                    *lookup = Some(match lookup {
                        Some(Lookup::Nearest) => Lookup::Bilinear,
                        _ => Lookup::Nearest,
                    });
                }
                _ => return self.noted("the material is not an SH data set: no lookup"),
            },
            Action::Exposure(stops) => {
                let e = &mut self.file.output.exposure;
                *e = (*e + stops).clamp(-64.0, 64.0);
            }
            Action::NextAov => {
                let all = Aov::value_variants();
                self.aov = match self.aov {
                    None => Some(all[0]),
                    Some(a) => all
                        .iter()
                        .position(|x| *x == a)
                        .and_then(|i| all.get(i + 1).copied()),
                };
            }
            Action::ToggleBackground => self.background = !self.background,
            Action::ToggleOverlay => {
                self.overlay = !self.overlay;
                return Ok(false);
            }
            Action::Reset => {
                let (w, h) = (self.file.render.width, self.file.render.height);
                if let Some(opened) = self.opened.take() {
                    *self = (*opened).clone();
                    self.opened = Some(opened);
                }
                self.set_size(w, h);
            }
            Action::Quit => return Ok(false),
        }
        Ok(true)
    }

    fn noted(&mut self, note: &str) -> Result<bool> {
        self.note = Some(note.to_string());
        Ok(false)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn state() -> ViewState {
        let file = SceneFile::default();
        let mesh = Arc::new(crate::mesh::teapot::teapot(file.mesh.segments));
        ViewState::new(file, mesh, &[PathBuf::from("a.exr")], None)
    }

    #[test]
    fn a_full_turn_of_drag_returns_the_camera_and_pitch_stops_short_of_the_pole() {
        let mut s = state();
        s.apply(&Action::Orbit { dx: 0.0, dy: 0.0 }).unwrap();
        let start = s.orbit.unwrap().position();
        let turn = std::f64::consts::TAU * DRAG_PIXELS_PER_RADIAN;
        s.apply(&Action::Orbit { dx: turn, dy: 0.0 }).unwrap();
        assert!((s.orbit.unwrap().position() - start).length() < 1e-9);
        // Drag right: the camera moves towards -x (yaw decreases), so the object turns right.
        s.apply(&Action::Orbit { dx: 10.0, dy: 0.0 }).unwrap();
        assert!(s.orbit.unwrap().position().x < start.x);
        s.apply(&Action::Orbit { dx: 0.0, dy: 1e6 }).unwrap();
        assert_eq!(s.orbit.unwrap().pitch, MAX_PITCH);
        // The camera written is the orbit's, at the orbit's distance from the target.
        let c = s.file.camera.clone().unwrap();
        let d = (glam::Vec3::from(c.position.unwrap()) - glam::Vec3::from(c.target.unwrap()))
            .length() as f64;
        assert!((d - s.orbit.unwrap().distance).abs() < 1e-5 * d);
    }

    #[test]
    fn materials_and_probes_cycle_and_reset_restores_the_opened_scene() {
        let mut s = state();
        assert_eq!(s.materials.len(), crate::library::LIBRARY.len() + 1);
        // Probes: a.exr, then the scene's own lights (the default scene has no [env]).
        assert_eq!(s.probes, vec![Some(PathBuf::from("a.exr")), None]);
        s.apply(&Action::NextProbe).unwrap();
        assert_eq!(s.file.env.as_ref().unwrap().file, PathBuf::from("a.exr"));
        s.apply(&Action::MoreLights).unwrap();
        assert_eq!(s.file.env.as_ref().unwrap().count, 256);
        s.apply(&Action::NextMaterial).unwrap();
        assert_ne!(
            s.material_name(),
            material_name(&SceneFile::default().material)
        );
        s.apply(&Action::Reset).unwrap();
        assert!(s.file.env.is_none());
        assert_eq!(
            s.material_name(),
            material_name(&SceneFile::default().material)
        );
        // Nothing to turn without an environment: a note, no new frame.
        assert!(!s.apply(&Action::TurnEnvironment { dx: 5.0 }).unwrap());
        assert!(s.note.is_some());
    }
}
