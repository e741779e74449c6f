//! The interactive viewer, `brdfkit view`: a window showing the scene rendered by the
//! renderer of `brdfkit render` ([`crate::render::render`]), turned with the mouse, its
//! material, probe, environment method and display changed with keys, refined towards the
//! converged reference while the view is still. A tool on top of [`crate::render`], like
//! [`crate::turntable`].
//!
//! Every frame is `brdfkit render` of a scene file (the viewer's document,
//! [`state::ViewState`]), so what the window shows can be reproduced headless:
//! `--write-scene` writes that file for the last frame and `--screenshot` its pixels
//! (without the status line); the Xvfb test (tests/viewer.rs) checks the two agree pixel for
//! pixel after a scripted orbit, material change and probe change.
//!
//! # Layout (one concept per file)
//! - `app.rs`: the window and event loop (winit), presenting (softbuffer), what happens when.
//! - `input.rs`: keys and drags to [`input::Action`]s; the controls table.
//! - `state.rs`: the document and the display choices, changed by actions.
//! - `worker.rs`: the render threads (scene file in, displayed frame out).
//! - `refine.rs`: the refinement steps of a still view.
//! - `script.rs`: `--script` files of timed input.
//! - `overlay.rs`: the status line.
//! - `background.rs`: the probe behind the object (display only).
//! - `stats.rs`: the counters `--stats` prints (frames per second, refinement times).
//! - `scene_toml.rs`: a frame's scene file as TOML.
//!
//! # Display
//! The window is X11 (Xlib and xcb loaded at run time, so nothing is needed to build;
//! Wayland desktops run it through XWayland). Without a display `run` fails with one line.

mod app;
mod background;
pub mod input;
mod overlay;
pub mod refine;
pub mod scene_toml;
pub mod script;
pub mod state;
mod stats;
mod worker;

use crate::env::lightset::prepare::CacheDir;
use crate::error::{Error, Result};
use crate::scene::SceneFile;
use std::path::PathBuf;
use std::sync::Arc;
use winit::event_loop::EventLoop;

/// What `brdfkit view` was asked to do.
#[derive(Clone, Debug)]
pub struct ViewConfig {
    /// The scene to open, every path in it absolute (the command line's options applied).
    pub file: SceneFile,
    /// Probes P cycles through after the scene's own (`--probe`, then the shipped ones).
    pub probes: Vec<PathBuf>,
    /// The debug output shown first (`--aov`).
    pub aov: Option<crate::aov::Aov>,
    pub script: Option<script::Script>,
    /// Where the last frame is written at the end (PNG, without the status line).
    pub screenshot: Option<PathBuf>,
    /// Where the last window contents (frame, background, status line) are written at the
    /// end (PNG).
    pub window_shot: Option<PathBuf>,
    /// Where the last frame's scene file is written at the end (TOML).
    pub write_scene: Option<PathBuf>,
    /// Show the probe behind the object from the start (display only).
    pub background: bool,
    /// Print the counters at the end.
    pub stats: bool,
    /// Refinement steps after the fast frame ([`refine`]).
    pub refine_steps: usize,
    /// The light-set cache.
    pub cache: CacheDir,
}

/// Opens the window and runs until it is closed or the script ends. Fails with one line
/// when there is no display.
pub fn run(cfg: ViewConfig) -> Result<()> {
    let event_loop = EventLoop::<worker::Reply>::with_user_event()
        .build()
        .map_err(|e| {
            // winit's text starts with its source location ("os error at FILE.rs:LINE: ").
            let text = e.to_string();
            let why = text
                .rsplit_once(".rs:")
                .and_then(|(_, r)| r.split_once(": "))
                .map_or(text.as_str(), |(_, m)| m);
            Error::Message(format!(
                "view: no display to open a window on ({}); `brdfkit render` renders without one",
                why.trim_end_matches('.')
            ))
        })?;
    let f = &cfg.file;
    let mesh = Arc::new(crate::scene::load_mesh(
        &f.mesh.source,
        f.mesh.segments.clamp(1, 256),
        std::path::Path::new("."),
    )?);
    let state = state::ViewState::new(cfg.file.clone(), mesh, &cfg.probes, cfg.aov)
        .with_background(cfg.background);
    let mut app = app::App::new(cfg, state, event_loop.create_proxy());
    event_loop
        .run_app(&mut app)
        .map_err(|e| Error::Message(format!("view: the window's event loop failed: {e}")))?;
    std::mem::replace(&mut app.outcome, Ok(()))
}
