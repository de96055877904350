//! Scripted input for the viewer, so tests (and demos) can drive it without a person:
//! `"10:resize=320x240; 30:orbit=40,-10; 50:wind=on; 90:screenshot=shot.png"`.

use std::path::PathBuf;

use fur_gpu::error::{Error, Result};

/// One scripted action.
#[derive(Clone, Debug, PartialEq)]
pub enum Action {
    /// Ask the window system for a new inner size.
    Resize(u32, u32),
    /// Orbit the camera by (yaw, pitch) degrees.
    Orbit(f32, f32),
    /// Zoom by a factor on the camera distance.
    Zoom(f32),
    /// Move the model by (x, y, z) scene units.
    Move(f64, f64, f64),
    Wind(bool),
    Shake(bool),
    Pause(bool),
    /// A character key pressed, as the keyboard would (`key=n`: one simulation step).
    Key(String),
    Minimize(bool),
    Screenshot(PathBuf),
    /// A setting changed as the panel would change it (`set=render.raster=compute`):
    /// its scene-file name and the value, checked when the script is read.
    Set(String, fur_core::scene_file::Value),
}

/// Actions keyed by the frame they run before.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Script {
    pub events: Vec<(u64, Action)>,
}

fn numbers<T: std::str::FromStr>(text: &str, count: usize, separators: &[char]) -> Option<Vec<T>> {
    let parts: Vec<T> = text
        .split(separators)
        .map(|p| p.trim().parse().ok())
        .collect::<Option<_>>()?;
    (parts.len() == count).then_some(parts)
}

fn on_off(text: &str) -> Option<bool> {
    match text {
        "on" | "true" | "1" => Some(true),
        "off" | "false" | "0" => Some(false),
        _ => None,
    }
}

impl Script {
    pub fn parse(text: &str) -> Result<Self> {
        let mut events = Vec::new();
        for item in text.split(';').map(str::trim).filter(|s| !s.is_empty()) {
            let error = || {
                Error::parameter(format!(
                    "bad script event `{item}` (expected FRAME:ACTION[=ARGS], e.g. 10:resize=320x240, \
                     20:orbit=30,-10, 25:zoom=0.8, 30:move=0.1,0,0, 40:wind=on, 45:shake=on, 50:pause=off, 55:key=n, \
                     60:minimize=on, 70:set=render.raster=compute, 90:screenshot=shot.png)"
                ))
            };
            let (frame, action) = item.split_once(':').ok_or_else(error)?;
            let frame: u64 = frame.trim().parse().map_err(|_| error())?;
            let (name, args) = action.split_once('=').unwrap_or((action, ""));
            let action = match name.trim() {
                "resize" => numbers::<u32>(args, 2, &['x', ','])
                    .filter(|v| v[0] > 0 && v[1] > 0)
                    .map(|v| Action::Resize(v[0], v[1])),
                "orbit" => numbers::<f32>(args, 2, &[',']).map(|v| Action::Orbit(v[0], v[1])),
                "zoom" => numbers::<f32>(args, 1, &[','])
                    .filter(|v| v[0] > 0.0)
                    .map(|v| Action::Zoom(v[0])),
                "move" => numbers::<f64>(args, 3, &[',']).map(|v| Action::Move(v[0], v[1], v[2])),
                "wind" => on_off(args.trim()).map(Action::Wind),
                "shake" => on_off(args.trim()).map(Action::Shake),
                "pause" => on_off(args.trim()).map(Action::Pause),
                "key" if args.trim().chars().count() == 1 => {
                    Some(Action::Key(args.trim().to_string()))
                }
                "minimize" => on_off(args.trim()).map(Action::Minimize),
                "screenshot" if !args.trim().is_empty() => {
                    Some(Action::Screenshot(PathBuf::from(args.trim())))
                }
                "set" => {
                    let (name, text) = args.split_once('=').ok_or_else(error)?;
                    let (setting, value) = crate::setting_args::setting_value(name.trim(), text)?;
                    if setting.effect == fur_core::scene_file::Effect::Restart {
                        return Err(Error::parameter(format!(
                            "bad script event `{item}`: `{}` takes effect only when the viewer \
                             starts; give it as --{} instead",
                            name.trim(),
                            setting.flag.name()
                        )));
                    }
                    Some(Action::Set(name.trim().to_string(), value))
                }
                _ => None,
            }
            .ok_or_else(error)?;
            events.push((frame, action));
        }
        events.sort_by_key(|(frame, _)| *frame);
        Ok(Self { events })
    }

    /// The actions due at `frame`.
    /// Rejects steps that would never run in a viewer closing after `frames` frames
    /// (steps run before the frame they name, frames counting from 0).
    pub fn check_within(&self, frames: u64) -> Result<()> {
        match self.events.iter().find(|(f, _)| *f >= frames) {
            Some((f, action)) => Err(Error::parameter(format!(
                "script step at frame {f} ({action:?}) would never run: the viewer closes after \
                 {frames} frames (--frames); steps run at frames 0..{frames}"
            ))),
            None => Ok(()),
        }
    }

    pub fn due(&self, frame: u64) -> impl Iterator<Item = &Action> {
        self.events
            .iter()
            .filter(move |(f, _)| *f == frame)
            .map(|(_, a)| a)
    }
}

/// The viewer's scripted input and the frame count it is keyed by, with the count the
/// run closes at.
pub(super) struct Scripted {
    script: Script,
    /// Close after this many frames (`--frames`); None: run until closed.
    limit: Option<u64>,
    /// Frames begun so far (minimised ones too).
    pub frame_index: u64,
}

impl Scripted {
    pub fn new(script: Script, limit: Option<u64>) -> Self {
        Self {
            script,
            limit,
            frame_index: 0,
        }
    }

    /// The actions due before the next frame.
    pub fn due(&self) -> Vec<Action> {
        self.script.due(self.frame_index).cloned().collect()
    }

    /// Every frame the run was to show has begun: the viewer closes.
    pub fn finished(&self) -> bool {
        self.limit.is_some_and(|limit| self.frame_index >= limit)
    }

    /// The run counts its frames (tests, benchmarks): the simulation steps once per
    /// frame rather than by the clock.
    pub fn counted(&self) -> bool {
        self.limit.is_some()
    }

    /// A frame begins; returns its number (from 1).
    pub fn begin_frame(&mut self) -> u64 {
        self.frame_index += 1;
        self.frame_index
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_every_action_and_sorts_by_frame() {
        let s = Script::parse("30:orbit=40,-10; 10:resize=320x240; 40:wind=on; 50:screenshot=a.png; 5:minimize=on; 6:move=0.1,0,-0.2; 7:zoom=0.5").unwrap();
        assert_eq!(s.events[0], (5, Action::Minimize(true)));
        assert_eq!(s.events[3], (10, Action::Resize(320, 240)));
        assert_eq!(s.events[4], (30, Action::Orbit(40.0, -10.0)));
        assert_eq!(s.due(50).next(), Some(&Action::Screenshot("a.png".into())));
        assert_eq!(s.events[1], (6, Action::Move(0.1, 0.0, -0.2)));
    }

    #[test]
    fn rejects_nonsense() {
        for bad in [
            "x:wind=on",
            "10:wind=maybe",
            "10:resize=0x10",
            "10:fly",
            "10:orbit=1",
            "10:screenshot=",
            "10:set=render.nearest",
            "10:set=render.nearest=0",
            "10:set=render.nearest=17",
            "10:set=nearest=4",
            "10:set=render.raster=sideways",
            "10:set=shadows.enabled=maybe",
        ] {
            assert!(Script::parse(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn a_setting_is_set_by_its_scene_file_name() {
        use fur_core::scene_file::Value;
        let s = Script::parse("9:set=render.raster=compute; 8:set=render.nearest=4").unwrap();
        assert_eq!(
            s.events,
            [
                (8, Action::Set("render.nearest".into(), Value::Integer(4))),
                (
                    9,
                    Action::Set("render.raster".into(), Value::Text("compute".into()))
                ),
            ]
        );
    }
}
