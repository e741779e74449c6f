//! Scripts (`brdfkit view --script FILE`): timed input, so a test or a measurement drives
//! the viewer as a person would.
//!
//! Format: one event per line, `MS ACTION ARGS...`, where `MS` is milliseconds from the
//! window's first frame request (non-decreasing down the file); `#` starts a comment.
//! Actions, each mapped through [`super::input`] exactly as the window's events are:
//!
//! | line | meaning |
//! |---|---|
//! | `100 drag DX DY` | mouse drag by (DX, DY) window pixels: orbit |
//! | `100 shift-drag DX` | shift-drag by DX pixels: turn the environment |
//! | `100 wheel N` | N wheel notches (positive: towards the target) |
//! | `100 key K` | key K of the controls table (`m`, `p`, `]`, `escape`, ...) |
//! | `100 resize W H` | ask the window for an inner size of W x H pixels |
//! | `100 await-refined` | hold the script until the view's last refinement step is shown |
//! | `100 quit` | stop reading; quit once the current view's frame is shown |
//!
//! After the last line the viewer quits as at `quit`: it waits for the frame of the final
//! view (never an older or previewed one), writes `--screenshot` and `--write-scene`, and
//! exits.

use super::input::{self, Action};
use crate::error::{Error, Result};
use std::path::Path;
use std::time::Duration;

/// One scripted event.
#[derive(Clone, Debug, PartialEq)]
pub enum ScriptInput {
    Act(Action),
    Resize {
        width: u32,
        height: u32,
    },
    /// Wait (the script's clock included) until the last refinement step is shown.
    AwaitRefined,
    Quit,
}

/// A script: events in time order.
#[derive(Clone, Debug, Default)]
pub struct Script {
    pub events: Vec<(Duration, ScriptInput)>,
}

impl Script {
    /// Reads a script file; errors name the file and line.
    pub fn load(path: &Path) -> Result<Script> {
        let text = crate::image_io::read_regular_text(path, 1 << 24, "script")?;
        Script::parse(&text).map_err(|m| Error::format(path, m))
    }

    /// Parses script text; the error names the line.
    pub fn parse(text: &str) -> std::result::Result<Script, String> {
        let mut events = Vec::new();
        let mut last = 0u64;
        for (i, raw) in text.lines().enumerate() {
            let line = raw.split('#').next().unwrap_or("").trim();
            if line.is_empty() {
                continue;
            }
            let err = |m: String| format!("line {}: {m}", i + 1);
            let words: Vec<&str> = line.split_whitespace().collect();
            let ms: u64 = words[0]
                .parse()
                .map_err(|_| err(format!("{:?} is not a time in milliseconds", words[0])))?;
            if ms < last {
                return Err(err(format!(
                    "time {ms} ms is before the line above ({last} ms)"
                )));
            }
            last = ms;
            let num = |k: usize| -> std::result::Result<f64, String> {
                let w = words
                    .get(k)
                    .ok_or_else(|| err(format!("{} needs {} number(s)", words[1], k - 1)))?;
                w.parse::<f64>()
                    .ok()
                    .filter(|x| x.is_finite())
                    .ok_or_else(|| err(format!("{w:?} is not a finite number")))
            };
            let Some(&action) = words.get(1) else {
                return Err(err("no action after the time".into()));
            };
            let (input, arity) = match action {
                "drag" => (
                    ScriptInput::Act(input::drag_action(num(2)?, num(3)?, false)),
                    2,
                ),
                "shift-drag" => (ScriptInput::Act(input::drag_action(num(2)?, 0.0, true)), 1),
                "wheel" => (ScriptInput::Act(Action::Zoom { notches: num(2)? }), 1),
                "key" => {
                    let k = words
                        .get(2)
                        .ok_or_else(|| err("key needs a key name".into()))?;
                    let a = input::key_action(k)
                        .ok_or_else(|| err(format!("{k:?} is no key of the controls table")))?;
                    (ScriptInput::Act(a), 1)
                }
                "resize" => {
                    let (w, h) = (num(2)?, num(3)?);
                    if !(1.0..=crate::scene::MAX_SIDE as f64).contains(&w)
                        || !(1.0..=crate::scene::MAX_SIDE as f64).contains(&h)
                    {
                        return Err(err(format!("resize {w} {h} is out of range")));
                    }
                    (
                        ScriptInput::Resize {
                            width: w as u32,
                            height: h as u32,
                        },
                        2,
                    )
                }
                "await-refined" => (ScriptInput::AwaitRefined, 0),
                "quit" => (ScriptInput::Quit, 0),
                other => {
                    return Err(err(format!(
                        "unknown action {other:?} (drag, shift-drag, wheel, key, resize, await-refined, quit)"
                    )))
                }
            };
            if words.len() > 2 + arity {
                return Err(err(format!("{action} takes {arity} argument(s)")));
            }
            events.push((Duration::from_millis(ms), input));
        }
        Ok(Script { events })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_each_action_and_names_bad_lines() {
        let s = Script::parse(
            "# orbit then swap\n0 drag 10 -5\n10 shift-drag 4\n20 wheel 2\n30 key m\n40 resize 320 240\n45 await-refined\n50 quit\n",
        )
        .unwrap();
        assert_eq!(s.events.len(), 7);
        assert_eq!(s.events[5].1, ScriptInput::AwaitRefined);
        assert_eq!(
            s.events[0],
            (
                Duration::ZERO,
                ScriptInput::Act(Action::Orbit { dx: 10.0, dy: -5.0 })
            )
        );
        assert_eq!(s.events[3].1, ScriptInput::Act(Action::NextMaterial));
        for (bad, what) in [
            ("10 drag 1 2\n5 key m", "line 2"),
            ("0 key x", "no key"),
            ("0 fly 1", "unknown action"),
            ("0 drag 1", "needs"),
            ("0 wheel nan", "finite"),
            ("zero key m", "milliseconds"),
            ("0 key m extra", "argument"),
        ] {
            let e = Script::parse(bad).unwrap_err();
            assert!(e.contains(what), "{bad:?}: {e}");
        }
    }
}
