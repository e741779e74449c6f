//! The window and its event loop (winit), the framebuffer presented to it (softbuffer),
//! and what happens when: input to [`Action`]s, a job per change, refinement when still,
//! the script's clock, and the end (screenshot, scene file, counters).
//!
//! Rendering never runs here: jobs go to two [`worker`] threads (the fast one for every
//! change, the refinement one for the still view), and their frames come back as user
//! events, so input is handled while a frame renders and closing the window ends the
//! process at once (workers are not waited for).
//!
//! Why this file stays whole (~550 lines): it is one struct, [`App`], and winit's
//! `ApplicationHandler` on it; every method reads and changes the same fields (the view's
//! generation, the frame shown, the refinement in flight, the script's clock), and split
//! apart they would each need all of them.

use super::input::{self, Action};
use super::script::{Script, ScriptInput};
use super::state::ViewState;
use super::stats::Counters;
use super::worker::{self, Frame, Job, Reply};
use super::{overlay, scene_toml, ViewConfig};
use crate::error::{Error, Result};
use std::num::NonZeroU32;
use std::rc::Rc;
use std::sync::mpsc::Sender;
use std::time::{Duration, Instant};
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoopProxy};
use winit::keyboard::{Key, ModifiersState, NamedKey};
use winit::window::{Window, WindowId};

/// How long the view must stay unchanged before refinement starts.
pub const STILL: Duration = Duration::from_millis(300);

type Surface = softbuffer::Surface<Rc<Window>, Rc<Window>>;

/// The application (module doc).
pub struct App {
    cfg: ViewConfig,
    state: ViewState,
    /// Counts changes of the view; frames of older generations are not shown.
    generation: u64,
    last_change: Instant,
    window: Option<Rc<Window>>,
    surface: Option<Surface>,
    fast: Sender<Job>,
    refine: Sender<Job>,
    refine_busy: bool,
    shown: Option<Box<Frame>>,
    /// The last worker error, shown on the status line.
    failure: Option<String>,
    cursor: Option<(f64, f64)>,
    dragging: bool,
    modifiers: ModifiersState,
    script: Option<Script>,
    next_event: usize,
    started: Option<Instant>,
    /// How long `await-refined` lines have held the script's clock.
    held: Duration,
    /// Quit once the current view's exact frame is shown (end of a script).
    quitting: bool,
    counters: Counters,
    /// The last window contents presented (for `--window-shot`).
    presented: Option<(u32, u32, Vec<u32>)>,
    /// When the status line is next redrawn for its frames/s.
    status_tick: Instant,
    /// The result `run` returns.
    pub outcome: Result<()>,
}

impl App {
    pub fn new(cfg: ViewConfig, state: ViewState, proxy: EventLoopProxy<Reply>) -> App {
        let threads = state.file.render.threads;
        let deliver = |p: EventLoopProxy<Reply>| move |r: Reply| p.send_event(r).is_ok();
        let fast = worker::spawn(
            "view-fast",
            threads,
            cfg.cache.clone(),
            deliver(proxy.clone()),
        );
        let refine = worker::spawn("view-refine", threads, cfg.cache.clone(), deliver(proxy));
        let script = cfg.script.clone();
        App {
            cfg,
            state,
            generation: 0,
            last_change: Instant::now(),
            window: None,
            surface: None,
            fast,
            refine,
            refine_busy: false,
            shown: None,
            failure: None,
            cursor: None,
            dragging: false,
            modifiers: ModifiersState::empty(),
            script,
            next_event: 0,
            started: None,
            quitting: false,
            held: Duration::ZERO,
            counters: Counters::new(Instant::now()),
            status_tick: Instant::now(),
            presented: None,
            outcome: Ok(()),
        }
    }

    /// A new view: the next generation, rendered by the fast worker as refinement step 0
    /// ([`super::refine::step_file`]: under `[env] method = "auto"` its method where a frame
    /// takes milliseconds, a transfer table; where it would be seconds-per-frame light cuts,
    /// the reflection table for Blinn-Phong, else the document's delta light set).
    fn changed(&mut self) {
        self.generation += 1;
        self.last_change = Instant::now();
        let _ = self.fast.send(Job {
            generation: self.generation,
            step: 0,
            file: super::refine::step_file(&self.state.file, 0, self.cfg.refine_steps),
            aov: self.state.aov,
            preview: true,
            refine: false,
            background: self.state.background,
        });
    }

    fn act(&mut self, event_loop: &ActiveEventLoop, a: &Action) {
        if *a == Action::Quit {
            self.finish(event_loop);
            return;
        }
        match self.state.apply(a) {
            Ok(true) => self.changed(),
            Ok(false) => {}
            Err(e) => self.state.note = Some(e.to_string()),
        }
        self.redraw();
    }

    fn redraw(&self) {
        if let Some(w) = &self.window {
            w.request_redraw();
        }
    }

    /// The status lines: frame time, frames/s, size, material, method, lights, step.
    fn status(&self) -> Vec<String> {
        let mut lines = Vec::new();
        // The method and light count of the frame shown (a refinement step's, when still).
        let file = self.shown.as_ref().map_or(&self.state.file, |f| &f.file);
        let method = match &file.env {
            None => "scene lights".to_string(),
            Some(e) => {
                let probe = e.file.file_name().unwrap_or_default().to_string_lossy();
                format!("{probe} {}", e.method.status_words(e))
            }
        };
        match &self.shown {
            Some(f) => {
                let step = match (f.generation == self.generation, f.exact) {
                    (false, _) => "updating".to_string(),
                    (true, false) => "preview".to_string(),
                    (true, true) => format!("step {}/{}", f.step, self.cfg.refine_steps),
                };
                lines.push(format!(
                    "{:.1} ms  {} fps  {}x{}  {}  {}  {}  {} lights{}",
                    f.frame_ms,
                    self.counters.fps_now(),
                    f.image.width,
                    f.image.height,
                    step,
                    self.state.material_name(),
                    method,
                    f.lights,
                    f.aov
                        .map(|a| format!("  aov {}", a.name()))
                        .unwrap_or_default()
                ));
            }
            None => lines.push(format!(
                "rendering...  {}  {method}",
                self.state.material_name()
            )),
        }
        if let Some(n) = self.state.note.as_ref().or(self.failure.as_ref()) {
            lines.push(n.clone());
        }
        lines
    }

    /// Draws the shown frame (scaled to the window, nearest pixel) and the status line.
    fn present(&mut self) {
        let status = self.state.overlay.then(|| self.status());
        let (Some(window), Some(surface)) = (&self.window, self.surface.as_mut()) else {
            return;
        };
        let size = window.inner_size();
        let (Some(w), Some(h)) = (NonZeroU32::new(size.width), NonZeroU32::new(size.height)) else {
            return;
        };
        if surface.resize(w, h).is_err() {
            return;
        }
        let Ok(mut buf) = surface.buffer_mut() else {
            return;
        };
        let (w, h) = (size.width as usize, size.height as usize);
        match &self.shown {
            Some(f) => {
                let (fw, fh) = (f.image.width as usize, f.image.height as usize);
                for y in 0..h {
                    let sy = y * fh / h;
                    let row = &mut buf[y * w..(y + 1) * w];
                    if fw == w {
                        row.copy_from_slice(&f.pixels[sy * fw..(sy + 1) * fw]);
                    } else {
                        for (x, px) in row.iter_mut().enumerate() {
                            *px = f.pixels[sy * fw + x * fw / w];
                        }
                    }
                }
            }
            None => buf.fill(0x0020_2020),
        }
        if let Some(lines) = status {
            let scale = if w >= 1200 { 2 } else { 1 };
            overlay::draw_lines(&mut buf, w, h, &lines, scale);
        }
        if self.cfg.window_shot.is_some() {
            self.presented = Some((w as u32, h as u32, buf.to_vec()));
        }
        let _ = buf.present();
    }

    /// Writes the screenshot and the scene file of the shown frame, prints the counters,
    /// and ends the event loop.
    fn finish(&mut self, event_loop: &ActiveEventLoop) {
        if let Err(e) = self.write_outputs() {
            self.outcome = Err(e);
        }
        if self.cfg.stats {
            eprint!("{}", self.counters.report());
        }
        event_loop.exit();
    }

    fn write_outputs(&self) -> Result<()> {
        if let (Some(p), Some((w, h, px))) = (&self.cfg.window_shot, &self.presented) {
            let rgb = px
                .iter()
                .flat_map(|&c| [(c >> 16) as u8, (c >> 8) as u8, c as u8])
                .collect();
            crate::image_io::write_png_bytes(p, *w, *h, rgb)?;
            eprintln!("wrote {} ({w}x{h}, the window)", p.display());
        }
        if self.cfg.screenshot.is_none() && self.cfg.write_scene.is_none() {
            return Ok(());
        }
        let Some(f) = &self.shown else {
            return Err(Error::Message(
                "view: closed before the first frame was shown: no screenshot written".into(),
            ));
        };
        if !(f.exact && f.generation == self.generation) {
            eprintln!(
                "warning: view: the screenshot is the last frame shown, which is not yet the final view's"
            );
        }
        if let Some(p) = &self.cfg.screenshot {
            match f.aov {
                None => crate::image_io::write_png(
                    p,
                    &f.image,
                    f.file.output.exposure,
                    f.file.output.tonemap,
                )?,
                Some(a) => crate::image_io::write_png_bytes(
                    p,
                    f.image.width,
                    f.image.height,
                    crate::aov::png_bytes(&f.image, a),
                )?,
            }
            eprintln!(
                "wrote {} ({}x{}, the frame without the status line)",
                p.display(),
                f.image.width,
                f.image.height
            );
        }
        if let Some(p) = &self.cfg.write_scene {
            scene_toml::write_scene(p, &f.file)?;
            eprintln!(
                "wrote {}: `brdfkit render {}{}` renders the same pixels",
                p.display(),
                p.display(),
                f.aov
                    .map(|a| format!(
                        " --aov {}",
                        clap::ValueEnum::to_possible_value(&a)
                            .map(|v| v.get_name().to_string())
                            .unwrap_or_default()
                    ))
                    .unwrap_or_default()
            );
        }
        Ok(())
    }

    /// Runs the script's events that are due; returns when the next one is.
    fn run_script(&mut self, event_loop: &ActiveEventLoop) -> Option<Instant> {
        let started = self.started?;
        let events = self.script.as_ref()?.events.clone();
        while self.next_event < events.len() && !self.quitting {
            let (at, input) = &events[self.next_event];
            if started + *at + self.held > Instant::now() {
                return Some(started + *at + self.held);
            }
            if *input == ScriptInput::AwaitRefined && !self.refined() {
                // Held: the script's clock stops until the last step is shown.
                self.held = Instant::now() - (started + *at);
                return Some(Instant::now() + Duration::from_millis(20));
            }
            self.next_event += 1;
            match input {
                ScriptInput::Act(a) => self.act(event_loop, a),
                ScriptInput::Resize { width, height } => {
                    if let Some(w) = &self.window {
                        let _ = w.request_inner_size(PhysicalSize::new(*width, *height));
                    }
                }
                ScriptInput::AwaitRefined => {}
                ScriptInput::Quit => self.quitting = true,
            }
        }
        self.quitting = true;
        None
    }
}

impl ApplicationHandler<Reply> for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_some() {
            return;
        }
        let r = &self.state.file.render;
        let attrs = Window::default_attributes()
            .with_title("brdfkit view")
            .with_inner_size(PhysicalSize::new(r.width, r.height));
        let made = event_loop
            .create_window(attrs)
            .map_err(|e| format!("cannot open a window: {e}"))
            .and_then(|w| {
                let w = Rc::new(w);
                let ctx = softbuffer::Context::new(w.clone())
                    .map_err(|e| format!("cannot present to the display: {e}"))?;
                let s = Surface::new(&ctx, w.clone())
                    .map_err(|e| format!("cannot present to the window: {e}"))?;
                Ok((w, s))
            });
        match made {
            Ok((w, s)) => {
                let size = w.inner_size();
                self.state.set_size(size.width, size.height);
                self.window = Some(w);
                self.surface = Some(s);
                self.started = Some(Instant::now());
                self.counters = Counters::new(Instant::now());
                self.changed();
            }
            Err(m) => {
                self.outcome = Err(Error::Message(format!("view: {m}")));
                event_loop.exit();
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        match event {
            WindowEvent::CloseRequested | WindowEvent::Destroyed => self.finish(event_loop),
            WindowEvent::Resized(size) => {
                let r = &self.state.file.render;
                if size.width > 0
                    && size.height > 0
                    && (size.width, size.height) != (r.width, r.height)
                {
                    self.state.set_size(size.width, size.height);
                    self.changed();
                }
                self.redraw();
            }
            WindowEvent::RedrawRequested => self.present(),
            WindowEvent::ModifiersChanged(m) => self.modifiers = m.state(),
            WindowEvent::MouseInput {
                state,
                button: MouseButton::Left,
                ..
            } => self.dragging = state == ElementState::Pressed,
            WindowEvent::CursorMoved { position, .. } => {
                let now = (position.x, position.y);
                if let (true, Some(was)) = (self.dragging, self.cursor) {
                    let shift = self.modifiers.shift_key();
                    let a = input::drag_action(now.0 - was.0, now.1 - was.1, shift);
                    self.act(event_loop, &a);
                }
                self.cursor = Some(now);
            }
            WindowEvent::MouseWheel { delta, .. } => {
                let notches = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y as f64,
                    MouseScrollDelta::PixelDelta(p) => p.y / 40.0,
                };
                self.act(event_loop, &Action::Zoom { notches });
            }
            WindowEvent::KeyboardInput { event, .. } if event.state == ElementState::Pressed => {
                let a = match &event.logical_key {
                    Key::Character(s) => input::key_action(s),
                    Key::Named(NamedKey::Escape) => Some(Action::Quit),
                    _ => None,
                };
                if let Some(a) = a {
                    self.act(event_loop, &a);
                }
            }
            _ => {}
        }
    }

    fn user_event(&mut self, _: &ActiveEventLoop, reply: Reply) {
        match reply {
            Reply::Frame(f) => {
                if f.refine {
                    self.refine_busy = false;
                }
                let newer = self.shown.as_ref().is_none_or(|s| {
                    f.generation > s.generation
                        || (f.generation == s.generation && (f.step > s.step || !s.exact))
                });
                if !newer {
                    return;
                }
                if f.generation == self.generation {
                    self.failure = None;
                    if f.refine && f.step > 0 {
                        self.counters.refined(f.step, self.last_change.elapsed());
                    }
                }
                self.counters.frame(
                    f.frame_ms,
                    f.render_ms,
                    f.step,
                    f.image.width,
                    f.image.height,
                );
                self.shown = Some(f);
                self.redraw();
            }
            Reply::Failed {
                generation,
                refine,
                message,
            } => {
                if refine {
                    self.refine_busy = false;
                }
                if generation == self.generation {
                    eprintln!("view: {message}");
                    if self.script.is_some() {
                        self.outcome = Err(Error::Message(format!("view: {message}")));
                        self.quitting = true;
                    }
                    self.failure = Some(message);
                    self.redraw();
                }
            }
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        let next_script = self.run_script(event_loop);
        let current = self
            .shown
            .as_ref()
            .filter(|f| f.generation == self.generation)
            .map(|f| (f.exact, f.step));
        if self.quitting && self.script.is_some() {
            if self.outcome.is_err() {
                event_loop.exit();
                return;
            }
            match current {
                Some((true, _)) => {
                    self.finish(event_loop);
                    return;
                }
                // A preview (the environment turned rigidly): render the exact frame.
                Some((false, _)) if !self.refine_busy => self.send_refine(0),
                _ => {}
            }
        }
        let still_at = self.last_change + STILL;
        let mut wake = next_script;
        if !self.quitting {
            if let Some((exact, step)) = current {
                let next = if exact { step + 1 } else { 0 };
                // An AOV does not depend on the lights: nothing to refine.
                let steps = if self.state.aov.is_some() {
                    0
                } else {
                    self.cfg.refine_steps
                };
                if next <= steps && !self.refine_busy {
                    if Instant::now() >= still_at {
                        self.send_refine(next);
                    } else {
                        wake = Some(wake.map_or(still_at, |t| t.min(still_at)));
                    }
                }
            }
        }
        // Keep the status line's frames/s current (4 times a second) while frames arrive.
        if self.counters.fps_now() > 0 {
            if Instant::now() >= self.status_tick {
                self.status_tick = Instant::now() + Duration::from_millis(250);
                self.redraw();
            }
            wake = Some(wake.map_or(self.status_tick, |w| w.min(self.status_tick)));
        }
        event_loop.set_control_flow(match wake {
            Some(t) => ControlFlow::WaitUntil(t),
            None => ControlFlow::Wait,
        });
    }
}

impl App {
    /// Whether the current view's last refinement step is shown.
    fn refined(&self) -> bool {
        let steps = if self.state.aov.is_some() {
            0
        } else {
            self.cfg.refine_steps
        };
        self.shown
            .as_ref()
            .is_some_and(|f| f.generation == self.generation && f.exact && f.step == steps)
    }

    fn send_refine(&mut self, step: usize) {
        self.refine_busy = true;
        let _ = self.refine.send(Job {
            generation: self.generation,
            step,
            file: super::refine::step_file(&self.state.file, step, self.cfg.refine_steps),
            aov: self.state.aov,
            preview: false,
            refine: true,
            background: self.state.background,
        });
    }
}
