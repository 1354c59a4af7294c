//! A validated camera of one instant, and the quantities the passes derive from it.

use glam::{Mat4, Vec2, Vec3, Vec4Swizzles};

use crate::abi::{PatchexCamera, PatchexDepthConvention, PATCHEX_DEPTH_HARDWARE_REVERSED};
use crate::error::{bail, Result};

#[derive(Clone, Copy, Debug)]
pub struct Camera {
    pub view: Mat4,
    pub projection: Mat4,
    pub jitter: Vec2,
    pub near: f32,
    pub far: f32,
    pub depth_convention: PatchexDepthConvention,
}

impl Camera {
    /// Checks the engine's camera; `name` prefixes error messages ("geometry.camera", ...).
    pub fn from_abi(camera: &PatchexCamera, name: &str) -> Result<Self> {
        let view = Mat4::from_cols_array(&camera.view);
        let projection = Mat4::from_cols_array(&camera.projection);
        if !view.is_finite() || !projection.is_finite() {
            bail!(
                ErrorInvalidArgument,
                "{name}: view or projection has a NaN or infinite entry"
            );
        }
        let jitter = Vec2::from(camera.jitter);
        if !jitter.is_finite() || jitter.abs().max_element() >= 1.0 {
            bail!(
                ErrorInvalidArgument,
                "{name}.jitter {jitter} must be finite and under 1 pixel"
            );
        }
        if !(camera.near_plane.is_finite() && camera.near_plane > 0.0) {
            bail!(
                ErrorInvalidArgument,
                "{name}.near_plane {} must be finite and positive",
                camera.near_plane
            );
        }
        if camera.far_plane.is_nan() || camera.far_plane <= camera.near_plane {
            bail!(
                ErrorInvalidArgument,
                "{name}.far_plane {} must exceed near_plane {} (+infinity allowed)",
                camera.far_plane,
                camera.near_plane
            );
        }
        if camera.depth_convention > PATCHEX_DEPTH_HARDWARE_REVERSED {
            bail!(
                ErrorInvalidArgument,
                "{name}.depth_convention {} is not a PATCHEX_DEPTH_* value",
                camera.depth_convention
            );
        }
        let camera = Self {
            view,
            projection,
            jitter,
            near: camera.near_plane,
            far: camera.far_plane,
            depth_convention: camera.depth_convention,
        };
        if camera.perspective_axis().length_squared() < 1e-12 {
            bail!(
                ErrorInvalidArgument,
                "{name}.projection is not a perspective projection"
            );
        }
        let determinant = (camera.projection * camera.view).determinant();
        if !determinant.is_finite()
            || determinant.abs() < 1e-30
            || !camera.inverse_view_projection().is_finite()
        {
            bail!(
                ErrorInvalidArgument,
                "{name}: projection * view is not invertible"
            );
        }
        Ok(camera)
    }

    /// The view-space axis along which clip w grows: -z for right-handed views, +z for
    /// left-handed ones.
    fn perspective_axis(&self) -> Vec3 {
        self.projection.row(3).xyz()
    }

    pub fn inverse_view_projection(&self) -> Mat4 {
        (self.projection * self.view).inverse()
    }

    pub fn position(&self) -> Vec3 {
        self.view.inverse().w_axis.xyz()
    }

    /// Radians one of `height` pixel rows spans at the image centre.
    pub fn pixel_angle(&self, height: u32) -> f32 {
        2.0 / (self.projection.y_axis.y.abs() * height as f32)
    }

    /// Whether `self` is a camera cut from `earlier`: it looks more than
    /// PATCHEX_CAMERA_CUT_DEGREES away, or zooms by more than PATCHEX_CAMERA_CUT_ZOOM. A cut by
    /// translation alone shows up as disocclusion instead.
    pub fn is_cut_from(&self, earlier: &Camera) -> bool {
        let turned = self.forward().dot(earlier.forward())
            < crate::abi::PATCHEX_CAMERA_CUT_DEGREES.to_radians().cos();
        let zoom = self.projection.y_axis.y.abs() / earlier.projection.y_axis.y.abs();
        turned || (zoom - 1.0).abs() > crate::abi::PATCHEX_CAMERA_CUT_ZOOM
    }

    /// Unit world-space direction of increasing linear depth.
    pub fn forward(&self) -> Vec3 {
        self.view
            .inverse()
            .transform_vector3(self.perspective_axis())
            .normalize()
    }
}
