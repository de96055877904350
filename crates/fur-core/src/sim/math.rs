//! The rest of the small linear algebra the CPU reference runs on: 3×3 matrices and
//! the head transform, over the scalars and 3-vectors of [`crate::geometry::math`].

pub use crate::geometry::math::{Real, V3};

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

/// GLSL's max: `b` when `a < b`, else `a` (the kernel's operand order, so the CPU
/// reference picks the same value when one is NaN).
pub fn max<T: Real>(a: T, b: T) -> T {
    if a < b {
        b
    } else {
        a
    }
}

/// GLSL's min: `b` when `b < a`, else `a`.
pub fn min<T: Real>(a: T, b: T) -> T {
    if b < a {
        b
    } else {
        a
    }
}

/// Smallest segment length that still has a direction (`MIN_LENGTH` in the kernels).
pub const MIN_LENGTH: f32 = 1e-20;

/// [`MIN_LENGTH`] as `T`.
pub fn min_length<T: Real>() -> T {
    T::from_f32(MIN_LENGTH)
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
