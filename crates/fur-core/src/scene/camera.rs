//! An orbit camera around a target point.

use glam::{Mat4, Vec3};

/// Orbit camera: yaw and pitch in degrees around `target`, at `distance`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub target: Vec3,
    pub yaw_deg: f32,
    pub pitch_deg: f32,
    pub distance: f32,
    pub fov_y_deg: f32,
}

impl Default for Camera {
    fn default() -> Self {
        Self {
            target: Vec3::ZERO,
            yaw_deg: 25.0,
            pitch_deg: 15.0,
            distance: 5.0,
            fov_y_deg: 40.0,
        }
    }
}

impl Camera {
    pub fn eye(&self) -> Vec3 {
        let (yaw, pitch) = (self.yaw_deg.to_radians(), self.pitch_deg.to_radians());
        self.target
            + self.distance
                * Vec3::new(
                    yaw.sin() * pitch.cos(),
                    pitch.sin(),
                    yaw.cos() * pitch.cos(),
                )
    }

    pub fn view(&self) -> Mat4 {
        let eye = self.eye();
        let up = if (eye - self.target).normalize_or_zero().dot(Vec3::Y).abs() > 0.999 {
            Vec3::Z
        } else {
            Vec3::Y
        };
        Mat4::look_at_rh(eye, self.target, up)
    }

    /// The near and far clipping distances. Both follow the distance, so a model of any
    /// size is framed alike.
    pub fn clip_planes(&self) -> (f32, f32) {
        (self.distance * 0.01, self.distance * 20.0)
    }

    /// Vulkan clip space: depth 0..1, y pointing down the framebuffer.
    pub fn projection(&self, aspect: f32) -> Mat4 {
        let (near, far) = self.clip_planes();
        let mut proj = Mat4::perspective_rh(self.fov_y_deg.to_radians(), aspect, near, far);
        proj.y_axis.y = -proj.y_axis.y;
        proj
    }

    /// World size of one pixel of an image `height` pixels tall, at distance 1.
    pub fn pixel_at_unit_distance(&self, height: u32) -> f32 {
        2.0 * (self.fov_y_deg.to_radians() * 0.5).tan() / height.max(1) as f32
    }

    pub fn view_projection(&self, aspect: f32) -> Mat4 {
        self.projection(aspect) * self.view()
    }
}
