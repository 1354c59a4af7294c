//! View and projection matrices in the renderer's conventions: right-handed view space looking
//! down -z, Vulkan clip space (y down, depth 0..1).

use glam::{Mat4, Vec3, Vec4};

/// World to view for a camera at `eye` looking at `target`.
pub fn look_at(eye: Vec3, target: Vec3, up: Vec3) -> Mat4 {
    let forward = (target - eye).normalize();
    let side = forward.cross(up).normalize();
    let true_up = side.cross(forward);
    Mat4::from_cols(
        Vec4::new(side.x, true_up.x, -forward.x, 0.0),
        Vec4::new(side.y, true_up.y, -forward.y, 0.0),
        Vec4::new(side.z, true_up.z, -forward.z, 0.0),
        Vec4::new(-side.dot(eye), -true_up.dot(eye), forward.dot(eye), 1.0),
    )
}

/// Perspective projection; `near` maps to depth 0 and `far` to 1, view-space +y to clip -y.
pub fn perspective(fov_y_radians: f32, aspect: f32, near: f32, far: f32) -> Mat4 {
    let focal = 1.0 / (0.5 * fov_y_radians).tan();
    let range = near - far;
    Mat4::from_cols(
        Vec4::new(focal / aspect, 0.0, 0.0, 0.0),
        Vec4::new(0.0, -focal, 0.0, 0.0),
        Vec4::new(0.0, 0.0, far / range, -1.0),
        Vec4::new(0.0, 0.0, near * far / range, 0.0),
    )
}

/// Orthographic projection of the box [left, right] x [bottom, top] x [-near, -far] to depth 0..1.
pub fn orthographic(left: f32, right: f32, bottom: f32, top: f32, near: f32, far: f32) -> Mat4 {
    let (width, height, range) = (right - left, top - bottom, near - far);
    Mat4::from_cols(
        Vec4::new(2.0 / width, 0.0, 0.0, 0.0),
        Vec4::new(0.0, 2.0 / height, 0.0, 0.0),
        Vec4::new(0.0, 0.0, 1.0 / range, 0.0),
        Vec4::new(
            -(right + left) / width,
            -(top + bottom) / height,
            near / range,
            1.0,
        ),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn look_at_puts_the_target_straight_ahead() {
        let view = look_at(Vec3::new(1.0, 2.0, 3.0), Vec3::new(1.0, 2.0, -7.0), Vec3::Y);
        assert!(view
            .transform_point3(Vec3::new(1.0, 2.0, -7.0))
            .abs_diff_eq(Vec3::new(0.0, 0.0, -10.0), 1e-5));
        assert!(view
            .transform_point3(Vec3::new(2.0, 2.0, 3.0))
            .abs_diff_eq(Vec3::X, 1e-5));
    }

    #[test]
    fn orthographic_maps_the_box_to_the_unit_depth_range() {
        let proj = orthographic(-2.0, 2.0, -1.0, 1.0, 0.0, 10.0);
        assert!(proj
            .project_point3(Vec3::new(2.0, 1.0, 0.0))
            .abs_diff_eq(Vec3::new(1.0, 1.0, 0.0), 1e-6));
        assert!(proj
            .project_point3(Vec3::new(-2.0, -1.0, -10.0))
            .abs_diff_eq(Vec3::new(-1.0, -1.0, 1.0), 1e-6));
    }
}
