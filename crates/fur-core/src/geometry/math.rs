//! Scalars and 3-vectors generic over `f32` (the GPU's precision) and `f64` (the
//! converged oracle): what the CPU reference and the distance field's sampler compute
//! with.

use std::ops::{Add, Div, Mul, Neg, Sub};

use glam::Vec3;

/// A floating-point scalar the reference runs on.
pub trait Real:
    Copy
    + PartialOrd
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + std::fmt::Debug
    + Send
    + Sync
    + 'static
{
    const ZERO: Self;
    const ONE: Self;
    const HALF: Self;
    /// The gap between 1 and the next representable number.
    const EPSILON: Self;
    fn from_f32(v: f32) -> Self;
    fn from_f64(v: f64) -> Self;
    fn to_f64(self) -> f64;
    fn sqrt(self) -> Self;
}

impl Real for f32 {
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    const HALF: Self = 0.5;
    const EPSILON: Self = f32::EPSILON;
    fn from_f32(v: f32) -> Self {
        v
    }
    fn from_f64(v: f64) -> Self {
        v as f32
    }
    fn to_f64(self) -> f64 {
        f64::from(self)
    }
    fn sqrt(self) -> Self {
        f32::sqrt(self)
    }
}

impl Real for f64 {
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    const HALF: Self = 0.5;
    const EPSILON: Self = f64::EPSILON;
    fn from_f32(v: f32) -> Self {
        f64::from(v)
    }
    fn from_f64(v: f64) -> Self {
        v
    }
    fn to_f64(self) -> f64 {
        self
    }
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
}

/// A 3-vector over [`Real`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct V3<T>(pub T, pub T, pub T);

impl<T: Real> V3<T> {
    pub const ZERO: Self = Self(T::ZERO, T::ZERO, T::ZERO);

    pub fn from_vec3(v: Vec3) -> Self {
        Self(T::from_f32(v.x), T::from_f32(v.y), T::from_f32(v.z))
    }

    pub fn to_vec3(self) -> Vec3 {
        Vec3::new(
            self.0.to_f64() as f32,
            self.1.to_f64() as f32,
            self.2.to_f64() as f32,
        )
    }

    pub fn dot(self, o: Self) -> T {
        self.0 * o.0 + self.1 * o.1 + self.2 * o.2
    }

    pub fn length(self) -> T {
        self.dot(self).sqrt()
    }

    /// `self × o`, as GLSL's `cross`.
    pub fn cross(self, o: Self) -> Self {
        Self(
            self.1 * o.2 - self.2 * o.1,
            self.2 * o.0 - self.0 * o.2,
            self.0 * o.1 - self.1 * o.0,
        )
    }

    pub fn scale(self, s: T) -> Self {
        Self(self.0 * s, self.1 * s, self.2 * s)
    }

    /// The largest absolute component (the Chebyshev norm).
    pub fn max_abs(self) -> T {
        let abs = |c: T| if c < T::ZERO { -c } else { c };
        let (x, y, z) = (abs(self.0), abs(self.1), abs(self.2));
        let xy = if y > x { y } else { x };
        if z > xy {
            z
        } else {
            xy
        }
    }

    pub fn is_finite(self) -> bool {
        [self.0, self.1, self.2]
            .iter()
            .all(|c| c.to_f64().is_finite())
    }
}

impl<T: Real> Add for V3<T> {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self(self.0 + o.0, self.1 + o.1, self.2 + o.2)
    }
}

impl<T: Real> Sub for V3<T> {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Self(self.0 - o.0, self.1 - o.1, self.2 - o.2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cross product and the Chebyshev norm, worked out by hand: (1, 2, 3) × (4, 5,
    /// 6) = (2·6 − 3·5, 3·4 − 1·6, 1·5 − 2·4); the largest absolute component wherever
    /// it stands and whatever its sign. Seen failing with each product and difference
    /// of the cross product changed, and with the norm's last comparison made `==`.
    #[test]
    fn cross_and_max_abs_are_the_textbooks() {
        let c = V3::<f64>(1.0, 2.0, 3.0).cross(V3(4.0, 5.0, 6.0));
        assert_eq!((c.0, c.1, c.2), (-3.0, 6.0, -3.0));
        let c = V3::<f32>(0.0, 0.0, 2.0).cross(V3(3.0, 0.0, 0.0));
        assert_eq!((c.0, c.1, c.2), (0.0, 6.0, 0.0));
        for (v, m) in [
            (V3::<f64>(-3.0, 1.0, 2.0), 3.0),
            (V3(1.0, -4.0, 2.0), 4.0),
            (V3(1.0, 2.0, -5.0), 5.0),
            (V3(0.0, 0.0, 0.0), 0.0),
        ] {
            assert_eq!(v.max_abs(), m, "{v:?}");
        }
    }
}
