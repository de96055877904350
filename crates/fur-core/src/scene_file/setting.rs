//! What a setting is: its section and key in a scene file, its command-line flag, its
//! type and range, its units and help, what changing it costs, and how the viewer's
//! panel shows it. Every setting is defined once, in one of the group files of
//! `keys/`; the command line (the application's `SettingArgs`), the scene file's reader and
//! writer, the viewer's panel, `fur settings` and the scene-file docs all come from
//! those definitions.

use super::value::{short, Value};
use super::Scene;

/// One setting of a [`Scene`].
#[derive(Clone, Copy)]
pub struct Setting {
    /// The key in its section of a scene file.
    pub key: &'static str,
    /// How the command line sets it.
    pub flag: Flag,
    /// Its name in prose and error messages ("hair length").
    pub label: &'static str,
    /// What it does, for `--help`, `fur settings` and the docs (the default and the
    /// range are added from the definition).
    pub help: &'static str,
    /// Its units, if any ("bounding radii", "px", "°").
    pub units: &'static str,
    pub kind: Kind,
    /// Whether it may be left unset, and what unset means ("framed").
    pub unset: Option<&'static str>,
    /// What a change costs in a running viewer.
    pub effect: Effect,
    pub panel: Panel,
    pub get: fn(&Scene) -> Value,
    pub set: fn(&mut Scene, Value),
}

impl std::fmt::Debug for Setting {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Setting({} / --{})", self.key, self.flag.name())
    }
}

/// A section of a scene file: a group of settings under one heading.
pub struct Group {
    /// The TOML table's name (`render`).
    pub section: &'static str,
    /// The heading in `--help`, the panel and the docs.
    pub heading: &'static str,
    pub settings: &'static [Setting],
}

/// How the command line sets a setting.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Flag {
    /// `--name VALUE`.
    Long(&'static str),
    /// `--name` alone sets the value given (`--no-loop` sets `loop` to false).
    Switch(&'static str, bool),
}

impl Flag {
    pub fn name(self) -> &'static str {
        match self {
            Flag::Long(n) | Flag::Switch(n, _) => n,
        }
    }
}

/// A setting's type and the values it accepts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Kind {
    /// A finite number in [min, max]; `min_open` excludes the minimum (a positive
    /// number). `double` keeps 64 bits (else the value is an `f32`).
    Number {
        min: f64,
        max: f64,
        min_open: bool,
        double: bool,
    },
    /// A whole number in min..=max, or 0 when `zero` (0 = chosen from the model).
    Integer {
        min: u32,
        max: u32,
        zero: bool,
    },
    /// One of these whole numbers.
    OneOf(&'static [u32]),
    Bool,
    /// One of these names.
    Choice(&'static [&'static str]),
    /// Three finite numbers of magnitude at most `max`, not all zero when `nonzero`;
    /// `down` also accepts a single number g, meaning (0, −g, 0).
    Vector {
        max: f64,
        nonzero: bool,
        down: bool,
    },
    /// Linear RGB, each channel in [0, max].
    Colour {
        max: f64,
    },
    /// Any text.
    Text,
    /// Where on the model: `auto`, an axis end (`+x`…`-z`) or a point `x,y,z`
    /// ([`crate::scene::FlowFrom`]).
    Place,
}

impl Kind {
    /// A finite `f32` in [min, max].
    pub const fn within(min: f64, max: f64) -> Self {
        Kind::Number {
            min,
            max,
            min_open: false,
            double: false,
        }
    }

    /// A finite `f32` above zero, at most `max`.
    pub const fn positive(max: f64) -> Self {
        Kind::Number {
            min: 0.0,
            max,
            min_open: true,
            double: false,
        }
    }

    /// A finite `f32` in what the value's own type accepts ([`crate::span`]).
    pub const fn span(span: crate::span::Span) -> Self {
        Kind::Number {
            min: span.min,
            max: span.max,
            min_open: span.min_open,
            double: false,
        }
    }

    /// A finite `f64` in what the value's own type accepts.
    pub const fn span_f64(span: crate::span::Span) -> Self {
        Kind::Number {
            min: span.min,
            max: span.max,
            min_open: span.min_open,
            double: true,
        }
    }

    /// A whole number in min..=max.
    pub const fn integer(min: u32, max: u32) -> Self {
        Kind::Integer {
            min,
            max,
            zero: false,
        }
    }
}

/// What a change costs in a running viewer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Effect {
    /// Taken by the next frame (uniforms, pipeline variants).
    Frame,
    /// The simulation's parameters change.
    Simulation,
    /// The master hairs are grown again.
    Regrow,
    /// Needs a new run (the image size, the clip, the scripted motion).
    Restart,
}

/// How the viewer's panel shows a setting.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Panel {
    /// Not in the panel (set by the scene file and the command line only, or by a
    /// control of its own).
    Hidden,
    /// A slider over [min, max], logarithmic when `log`.
    Slider { min: f64, max: f64, log: bool },
    /// A checkbox, a radio row, a colour button: chosen from the kind.
    Plain,
}

impl Setting {
    /// Checks `value` against the setting's type and range; the message says what is
    /// wanted and what was given (the caller names the key or flag).
    pub fn check(&self, value: &Value) -> Result<(), String> {
        if *value == Value::Unset {
            return if self.unset.is_some() {
                Ok(())
            } else {
                Err("must be set".into())
            };
        }
        match (self.kind, value) {
            (
                Kind::Number {
                    min, max, min_open, ..
                },
                Value::Number(v),
            ) => {
                let v = *v;
                let span = crate::span::Span { min, max, min_open };
                if span.contains(v) {
                    Ok(())
                } else if min_open && min == 0.0 && max >= f64::from(f32::MAX) {
                    Err(format!("must be a positive number, got {v}"))
                } else if min_open {
                    Err(format!("must be in ({}, {}], got {v}", n(min), n(max)))
                } else {
                    Err(format!("must be in [{}, {}], got {v}", n(min), n(max)))
                }
            }
            (Kind::Integer { min, max, zero }, Value::Integer(v)) => {
                if (min..=max).contains(v) || (zero && *v == 0) {
                    Ok(())
                } else if zero {
                    Err(format!(
                        "must be 0 (from the model) or {min}..={max}, got {v}"
                    ))
                } else {
                    Err(format!("must be {min}..={max}, got {v}"))
                }
            }
            (Kind::OneOf(allowed), Value::Integer(v)) => {
                if allowed.contains(v) {
                    Ok(())
                } else {
                    Err(format!("must be {}, got {v}", list(allowed, "or")))
                }
            }
            (Kind::Bool, Value::Bool(_)) => Ok(()),
            (Kind::Choice(names), Value::Text(t)) => {
                if names.contains(&t.as_str()) {
                    Ok(())
                } else {
                    Err(format!(
                        "unknown value `{t}` (expected {})",
                        list(names, "or")
                    ))
                }
            }
            (Kind::Vector { max, nonzero, .. }, Value::Vector(v)) => {
                if !v.is_finite() || f64::from(v.length()) > max {
                    Err(format!("must be finite with magnitude ≤ {max:e}, got {v}"))
                } else if nonzero && v.length() < 1e-6 {
                    Err(format!("must be a finite, non-zero vector, got {v}"))
                } else {
                    Ok(())
                }
            }
            (Kind::Colour { max }, Value::Vector(v)) => {
                if v.is_finite() && v.min_element() >= 0.0 && f64::from(v.max_element()) <= max {
                    Ok(())
                } else {
                    Err(format!("must have channels in [0, {max}], got {v}"))
                }
            }
            (Kind::Text, Value::Text(_)) => Ok(()),
            (Kind::Place, Value::Text(t)) => t.parse::<crate::scene::FlowFrom>().map(|_| ()),
            (_, v) => Err(format!("expected {}, got {v:?}", self.kind.wanted())),
        }
    }

    /// The help text with its range, units and defaults (`[default: 0.2; sphere:
    /// 0.159]`).
    pub fn help_text(&self, blob: &Scene, sphere: &Scene) -> String {
        let mut text = self.help.to_string();
        match (self.kind.range_text(), self.units) {
            (Some(range), "") => text += &format!(", {range}"),
            (Some(range), units) => text += &format!(", {range} {units}"),
            (None, "") => {}
            (None, units) => text += &format!(", in {units}"),
        }
        if matches!(self.flag, Flag::Switch(..)) {
            return text;
        }
        let (a, b) = ((self.get)(blob), (self.get)(sphere));
        let shown = |v: &Value| match (v, self.unset) {
            (Value::Unset, Some(meaning)) => meaning.to_string(),
            (v, _) => v.to_string(),
        };
        text += &format!(" [default: {}", shown(&a));
        if a != b {
            text += &format!("; sphere: {}", shown(&b));
        }
        text + "]"
    }
}

impl Kind {
    /// What the kind accepts, in words.
    pub fn wanted(self) -> &'static str {
        match self {
            Kind::Number { .. } => "a number",
            Kind::Integer { .. } | Kind::OneOf(_) => "a whole number",
            Kind::Bool => "true or false",
            Kind::Choice(_) => "one of the names",
            Kind::Vector { down: true, .. } => "three numbers [x, y, z] or one (pointing down)",
            Kind::Vector { .. } | Kind::Colour { .. } => "three numbers [x, y, z]",
            Kind::Text => "text",
            Kind::Place => "auto, an axis end (+x, -z…) or a point x,y,z",
        }
    }

    /// The range for help texts and docs, if it is worth saying (a choice's names
    /// are listed where it is shown).
    pub fn range_text(self) -> Option<String> {
        match self {
            Kind::Number {
                min, max, min_open, ..
            } => Some(match (min_open, max >= 1e30) {
                (true, true) if min == 0.0 => "> 0".into(),
                (false, true) => format!("≥ {}", n(min)),
                (true, _) => format!("({}, {}]", n(min), n(max)),
                (false, false) => format!("{}..{}", n(min), n(max)),
            }),
            Kind::Integer { min, max, zero } => Some(if zero {
                format!("0 or {min}..={max}")
            } else {
                format!("{min}..={max}")
            }),
            Kind::OneOf(v) => Some(list(v, "or")),
            Kind::Colour { max } => Some(format!("linear RGB, 0..{}", n(max))),
            _ => None,
        }
    }
}

/// A range's end for messages: 1e6, not 1000000.
fn n(v: f64) -> String {
    if v.abs() >= 1e4 {
        format!("{v:e}")
    } else {
        short(v)
    }
}

/// `a, b or c`.
pub fn list<T: std::fmt::Display>(items: &[T], last: &str) -> String {
    let words: Vec<String> = items.iter().map(ToString::to_string).collect();
    match words.split_last() {
        Some((end, rest)) if !rest.is_empty() => format!("{} {last} {end}", rest.join(", ")),
        Some((end, _)) => end.clone(),
        None => String::new(),
    }
}

#[cfg(test)]
mod tests;
