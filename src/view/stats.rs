//! The viewer's own counters (`brdfkit view --stats`): frames shown per wall-clock second,
//! their frame times, and the time from the last change of the view to each refinement
//! step's frame.

use std::fmt::Write;
use std::time::{Duration, Instant};

/// One frame shown.
#[derive(Clone, Copy, Debug)]
struct Shown {
    at: Duration,
    frame_ms: f64,
    render_ms: f64,
    step: usize,
    width: u32,
    height: u32,
}

/// The counters (module doc).
#[derive(Debug)]
pub struct Counters {
    start: Instant,
    shown: Vec<Shown>,
    /// (step, seconds from the last change of the view to the step's frame shown).
    refined: Vec<(usize, f64)>,
}

impl Counters {
    pub fn new(start: Instant) -> Counters {
        Counters {
            start,
            shown: Vec::new(),
            refined: Vec::new(),
        }
    }

    /// Counts a frame shown now.
    pub fn frame(&mut self, frame_ms: f64, render_ms: f64, step: usize, width: u32, height: u32) {
        self.shown.push(Shown {
            at: self.start.elapsed(),
            frame_ms,
            render_ms,
            step,
            width,
            height,
        });
    }

    /// Counts refinement step `step` shown `since_change` after the view last changed.
    pub fn refined(&mut self, step: usize, since_change: Duration) {
        self.refined.push((step, since_change.as_secs_f64()));
    }

    /// Frames shown in the second before now (the status line's frames/s).
    pub fn fps_now(&self) -> usize {
        let now = self.start.elapsed();
        self.shown
            .iter()
            .rev()
            .take_while(|s| now - s.at <= Duration::from_secs(1))
            .count()
    }

    /// The report: one line per wall-clock second with frames shown (step-0 frames, the
    /// ones shown while the view changes, and refinement frames), their mean frame time and
    /// size; then the refinement steps' times.
    pub fn report(&self) -> String {
        let mut out = String::new();
        let secs = self.shown.last().map_or(0, |s| s.at.as_secs() + 1);
        for s in 0..secs {
            let f: Vec<&Shown> = self.shown.iter().filter(|x| x.at.as_secs() == s).collect();
            let fast: Vec<&&Shown> = f.iter().filter(|x| x.step == 0).collect();
            let mean = |v: &[&&Shown], ms: fn(&Shown) -> f64| {
                v.iter().map(|x| ms(x)).sum::<f64>() / v.len() as f64
            };
            let size = f
                .first()
                .map(|x| format!("{}x{}", x.width, x.height))
                .unwrap_or_default();
            let _ = writeln!(
                out,
                "view: second {s}: {} frames/s ({} fast{}), {} refined, {size}",
                f.len(),
                fast.len(),
                if fast.is_empty() {
                    String::new()
                } else {
                    format!(
                        ", mean frame {:.1} ms of which render {:.1} ms",
                        mean(&fast, |x| x.frame_ms),
                        mean(&fast, |x| x.render_ms)
                    )
                },
                f.len() - fast.len(),
            );
        }
        for (step, t) in &self.refined {
            let _ = writeln!(
                out,
                "view: refinement step {step} shown {t:.2} s after the view stopped changing"
            );
        }
        out
    }
}
