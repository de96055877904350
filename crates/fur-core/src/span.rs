//! A range of accepted numbers, stated once beside the value it bounds: the type that
//! holds the value checks itself against it, and the scene's setting for the value
//! takes its range from it (`scene_file`'s `Kind::span`), so its flag, scene-file key,
//! panel and docs accept what the type does.

/// Finite numbers in [min, max], or in (min, max] when `min_open`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Span {
    pub min: f64,
    pub max: f64,
    pub min_open: bool,
}

impl Span {
    /// Finite numbers in [min, max].
    pub const fn within(min: f64, max: f64) -> Self {
        Self {
            min,
            max,
            min_open: false,
        }
    }

    /// Finite `f32`s above zero.
    pub const fn positive() -> Self {
        Self {
            min: 0.0,
            max: f32::MAX as f64,
            min_open: true,
        }
    }

    /// Finite `f32`s at least zero.
    pub const fn non_negative() -> Self {
        Self::within(0.0, f32::MAX as f64)
    }

    pub fn contains(self, v: f64) -> bool {
        let above = if self.min_open {
            v > self.min
        } else {
            v >= self.min
        };
        v.is_finite() && above && v <= self.max
    }

    /// [`Span::contains`] for an `f32`, against the ends as `f32`s: the `f32` nearest
    /// 0.1 is in (0, 0.1], though it is a little more than 0.1.
    pub fn contains_f32(self, v: f32) -> bool {
        let (min, max) = (self.min as f32, self.max as f32);
        let above = if self.min_open { v > min } else { v >= min };
        v.is_finite() && above && v <= max
    }

    /// Checks the value `v` of what `name` names: the message says what is wanted and
    /// what was given.
    pub fn check(self, name: &str, v: f64) -> Result<(), String> {
        if self.contains(v) {
            return Ok(());
        }
        Err(self.refusal(name, v))
    }

    /// The `f32` `v` of what `name` names, checked ([`Span::contains_f32`]): an
    /// impossible parameter is the core's [`crate::Error::Parameter`], naming it.
    pub fn require(self, name: &str, v: f32) -> crate::Result<()> {
        if self.contains_f32(v) {
            return Ok(());
        }
        Err(crate::Error::Parameter(self.refusal(name, f64::from(v))))
    }

    fn refusal(self, name: &str, v: f64) -> String {
        let unbounded = self.max >= f64::from(f32::MAX);
        match (self.min_open, unbounded) {
            (true, true) if self.min == 0.0 => {
                format!("{name} must be positive and finite, got {v}")
            }
            (false, true) => format!("{name} must be finite and at least {}, got {v}", self.min),
            (true, _) => format!("{name} must be in ({}, {}], got {v}", self.min, self.max),
            (false, false) => format!("{name} must be in [{}, {}], got {v}", self.min, self.max),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Span;

    #[test]
    fn a_span_refuses_its_open_end_infinities_and_nan_and_names_the_value() {
        let positive = Span::positive();
        assert!(positive.contains(1e-30) && positive.contains(f64::from(f32::MAX)));
        for v in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert!(!positive.contains(v), "{v}");
        }
        let unit = Span::within(0.0, 1.0);
        assert!(unit.contains(0.0) && unit.contains(1.0) && !unit.contains(1.0 + 1e-9));
        let refusal = unit.check("cull margin", 2.0).unwrap_err();
        assert_eq!(refusal, "cull margin must be in [0, 1], got 2");
        let refusal = positive.check("density", 0.0).unwrap_err();
        assert_eq!(refusal, "density must be positive and finite, got 0");
        // An f32 at a decimal end is in the span, though its f64 is past it.
        let dt = Span::within(0.01, 0.1);
        assert!(!dt.contains(f64::from(0.1f32)) && !dt.contains(f64::from(0.01f32)));
        assert!(dt.contains_f32(0.1) && dt.contains_f32(0.01));
        assert!(!dt.contains_f32(0.100_001) && !dt.contains_f32(0.009_999));
    }
}
