//! What a setting is, whatever struct it sets: its key, flag, type and range, units,
//! help, what changing it costs, how the viewer's panel shows it, and how it reaches
//! its field ([`Setting`], [`Accessor`]); and a setting's value whatever its type
//! ([`Value`], [`FieldValue`]). A struct that has settings declares them beside its
//! fields (the drawing style's in `render/style.rs`); the scene file gathers them into
//! its sections (`scene_file`), and the command line, the scene file's reader and
//! writer, the viewer's panel, `fur settings` and the docs all come from those
//! declarations.

mod value;

pub use value::{short, FieldValue, Value};

/// The [`Accessor`] of the field at `$path` of a `$t` (`accessor!(FurStyle:
/// hair_width)`): it reads the field as a [`Value`] and writes a value of its type.
macro_rules! accessor {
    ($t:ty: $($path:ident).+) => {
        $crate::setting::Accessor::<$t> {
            get: |s: &$t| $crate::setting::FieldValue::to_value(&s.$($path).+),
            set: |s: &mut $t, v| {
                if let Some(v) = $crate::setting::FieldValue::from_value(v) {
                    s.$($path).+ = v;
                }
            },
        }
    };
}
pub(crate) use accessor;

/// One setting: its key in a scene file's section, its command-line flag, its type
/// and range, its units and help, what changing it costs, how the viewer's panel shows
/// it, and how it reaches the field it sets (`access`: an [`Accessor`] of the struct
/// that holds the field, or the scene's way to one).
#[derive(Clone, Copy)]
pub struct Setting<A> {
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
    /// How it reads and writes its field.
    pub access: A,
}

impl<A> std::fmt::Debug for Setting<A> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Setting({} / --{})", self.key, self.flag.name())
    }
}

/// How a setting reads and writes its field of a `T`.
pub struct Accessor<T: 'static> {
    pub get: fn(&T) -> Value,
    pub set: fn(&mut T, Value),
}

impl<T> Clone for Accessor<T> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<T> Copy for Accessor<T> {}

impl<A> Setting<A> {
    /// A setting reaching its field by `access`, the rest placeholders that every
    /// definition overrides (`..Setting::reaching(access)`; the `field!` macros).
    pub const fn reaching(access: A) -> Self {
        Setting {
            key: "",
            flag: Flag::Long(""),
            label: "",
            help: "",
            units: "",
            kind: Kind::Text,
            unset: None,
            effect: Effect::Frame,
            panel: Panel::Hidden,
            access,
        }
    }
}

impl<A: Copy> Setting<A> {
    /// The same setting, reaching its field another way (a struct's setting, as the
    /// scene that holds the struct reaches it).
    pub const fn through<B>(&self, access: B) -> Setting<B> {
        Setting {
            key: self.key,
            flag: self.flag,
            label: self.label,
            help: self.help,
            units: self.units,
            kind: self.kind,
            unset: self.unset,
            effect: self.effect,
            panel: self.panel,
            access,
        }
    }
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

impl Panel {
    /// A linear slider over [min, max].
    pub const fn slider(min: f64, max: f64) -> Self {
        Panel::Slider {
            min,
            max,
            log: false,
        }
    }

    /// A logarithmic slider over [min, max].
    pub const fn log_slider(min: f64, max: f64) -> Self {
        Panel::Slider {
            min,
            max,
            log: true,
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

impl<A> Setting<A> {
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
