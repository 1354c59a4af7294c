//! Camera state at an instant: Vulkan-convention matrices (right-handed view looking down -z,
//! clip y pointing down, depth 0..1).

use super::projection::{look_at, perspective};
use glam::{Mat4, Vec3};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraState {
    pub position: Vec3,
    pub view: Mat4,
    pub proj: Mat4,
    pub near: f32,
    pub far: f32,
}

impl CameraState {
    pub fn look_at(
        position: Vec3,
        target: Vec3,
        fov_y_deg: f32,
        aspect: f32,
        near: f32,
        far: f32,
    ) -> Self {
        let forward = (target - position).normalize_or(Vec3::NEG_Z);
        let up = if forward.y.abs() > 0.999 {
            Vec3::Z
        } else {
            Vec3::Y
        };
        let view = look_at(position, position + forward, up);
        let proj = perspective(fov_y_deg.to_radians(), aspect, near, far);
        Self {
            position,
            view,
            proj,
            near,
            far,
        }
    }

    pub fn view_proj(&self) -> Mat4 {
        self.proj * self.view
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_above_the_view_centre_land_in_the_top_half_with_depth_in_zero_one() {
        let camera = CameraState::look_at(
            Vec3::new(0.0, 1.0, 5.0),
            Vec3::new(0.0, 1.0, 0.0),
            60.0,
            1.5,
            0.1,
            100.0,
        );
        let above = camera.view_proj().project_point3(Vec3::new(0.0, 2.0, 0.0));
        assert!(above.y < 0.0, "clip y must point down, got {above}");
        assert!((0.0..1.0).contains(&above.z));
        let near = camera.view_proj().project_point3(Vec3::new(0.0, 1.0, 4.9));
        assert!(
            near.z.abs() < 1e-4,
            "near plane maps to depth 0, got {}",
            near.z
        );
    }
}
