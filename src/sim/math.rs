//! The small linear algebra the CPU reference runs on, generic over `f32` (the GPU's
//! precision) and `f64` (the converged oracle): scalars, 3-vectors, 3×3 matrices and
//! the head transform.

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
    fn from_f32(v: f32) -> Self;
    fn from_f64(v: f64) -> Self;
    fn to_f64(self) -> f64;
    fn sqrt(self) -> Self;
}

impl Real for f32 {
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    const HALF: Self = 0.5;
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

    pub fn scale(self, s: T) -> Self {
        Self(self.0 * s, self.1 * s, self.2 * s)
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

/// A 3×3 matrix stored as columns.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct M3<T>(pub [V3<T>; 3]);

impl<T: Real> M3<T> {
    pub fn mul_vec(&self, v: V3<T>) -> V3<T> {
        let [a, b, c] = self.0;
        a.scale(v.0) + b.scale(v.1) + c.scale(v.2)
    }

    /// `selfᵀ · v`.
    pub fn transpose_mul_vec(&self, v: V3<T>) -> V3<T> {
        V3(self.0[0].dot(v), self.0[1].dot(v), self.0[2].dot(v))
    }

    pub fn transpose(&self) -> Self {
        let [a, b, c] = self.0;
        Self([V3(a.0, b.0, c.0), V3(a.1, b.1, c.1), V3(a.2, b.2, c.2)])
    }

    pub fn mul_mat(&self, o: &Self) -> Self {
        Self(o.0.map(|col| self.mul_vec(col)))
    }

    /// The rotation that takes the x axis to the unit vector `u` along the shortest arc.
    pub fn rotation_from_x(u: V3<T>) -> Self {
        let c = u.0;
        if c < T::from_f32(-0.9999) {
            // Half turn about z: any rotation taking +x to -x will do, this one is fixed.
            return Self([
                V3(-T::ONE, T::ZERO, T::ZERO),
                V3(T::ZERO, -T::ONE, T::ZERO),
                V3(T::ZERO, T::ZERO, T::ONE),
            ]);
        }
        // Rodrigues with k = x × u = (0, -u.z, u.y): R = I + [k]ₓ + [k]ₓ² / (1 + c).
        let f = T::ONE / (T::ONE + c);
        let (y, z) = (u.1, u.2);
        Self([
            V3(c, y, z),
            V3(-y, T::ONE - y * y * f, -y * z * f),
            V3(-z, -y * z * f, T::ONE - z * z * f),
        ])
    }
}

/// Smallest segment length that still has a direction.
pub fn min_length<T: Real>() -> T {
    T::from_f32(1e-20)
}

/// The head transform split into rotation and translation.
#[derive(Clone, Copy, Debug)]
pub struct Head<T> {
    pub rotation: M3<T>,
    pub translation: V3<T>,
}

impl<T: Real> Head<T> {
    pub fn new(m: glam::Mat4) -> Self {
        let col = |c: glam::Vec4| V3::from_vec3(c.truncate());
        Self {
            rotation: M3([col(m.x_axis), col(m.y_axis), col(m.z_axis)]),
            translation: col(m.w_axis),
        }
    }

    pub fn point(&self, p: V3<T>) -> V3<T> {
        self.rotation.mul_vec(p) + self.translation
    }
}
