//! A validated camera of one instant, and the quantities the passes derive from it.

use glam::{DVec2, DVec3, DVec4, Mat4, Vec2, Vec3, Vec4Swizzles};

use crate::abi::{
    PatchexCamera, PatchexDepthConvention, PATCHEX_DEPTH_HARDWARE_REVERSED,
    PATCHEX_DEPTH_LINEAR_VIEW_Z,
};
use crate::error::{bail, Result};

/// `Camera::pixel_rays`.
#[derive(Clone, Copy, Debug)]
pub struct PixelRays {
    pub position: Vec3,
    pub at_origin: Vec3,
    pub per_x: Vec3,
    pub per_y: Vec3,
}

impl PixelRays {
    /// The surface at linear `depth` seen through pixel (x, y), as the warps rebuild it.
    pub fn surface(&self, x: f32, y: f32, depth: f32) -> Vec3 {
        let ray = self.at_origin + x * self.per_x + y * self.per_y;
        self.position + depth * ray
    }
}

struct PixelRaysF64 {
    position: DVec3,
    at_origin: DVec3,
    per_x: DVec3,
    per_y: DVec3,
}

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
        // In f64, and each matrix on its own: a camera 1e7 units from the world's origin has a
        // view-projection whose f32 inverse loses every digit.
        for (matrix, what) in [(camera.view, "view"), (camera.projection, "projection")] {
            let determinant = matrix.as_dmat4().determinant();
            if !determinant.is_finite() || determinant.abs() < 1e-30 {
                bail!(ErrorInvalidArgument, "{name}.{what} is not invertible");
            }
        }
        camera.check_near_plane(name)?;
        Ok(camera)
    }

    /// `near_plane` must be where the projection puts depth 0 (PATCHEX_DEPTH_HARDWARE) or 1
    /// (PATCHEX_DEPTH_HARDWARE_REVERSED), within 1%: a mismatch means the depth was written with
    /// another projection than the one given. With linear depth the projection may be either
    /// kind, so either plane is taken.
    fn check_near_plane(&self, name: &str) -> Result<()> {
        let near_depths: &[f64] = match self.depth_convention {
            PATCHEX_DEPTH_HARDWARE_REVERSED => &[1.0],
            PATCHEX_DEPTH_LINEAR_VIEW_Z => &[0.0, 1.0],
            _ => &[0.0],
        };
        // Along the perspective axis, clip z = a * d + b and clip w = c * d at view depth d, so
        // depth z lies at d = b / (z * c - a).
        let axis = self.perspective_axis().as_dvec3().normalize();
        let projection = self.projection.as_dmat4();
        let clip = |d: f64| projection * (axis * d).extend(1.0);
        let (at_zero, at_one) = (clip(0.0), clip(1.0));
        let (a, b, c) = (at_one.z - at_zero.z, at_zero.z, at_one.w - at_zero.w);
        let given = self.near as f64;
        let planes = near_depths.iter().map(|&z| b / (z * c - a));
        let agrees = |near: f64| near.is_finite() && ((near - given) / given).abs() <= 0.01;
        if !planes.clone().any(agrees) {
            let planes: Vec<String> = planes.map(|near| format!("{near:.6}")).collect();
            bail!(
                ErrorInvalidArgument,
                "{name}.near_plane {given} disagrees with the projection, whose near plane \
                 (depth {near_depths:?}) is at {}",
                planes.join(" or ")
            );
        }
        Ok(())
    }

    /// The view-space axis along which clip w grows: -z for right-handed views, +z for
    /// left-handed ones.
    fn perspective_axis(&self) -> Vec3 {
        self.projection.row(3).xyz()
    }

    /// The camera's position in the world, in f64.
    pub fn position(&self) -> DVec3 {
        self.view.as_dmat4().inverse().w_axis.truncate()
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

    /// The rays through the pixel centres of an `extent` frame, scaled to unit linear depth
    /// (`Cameras` in shaders/include/cameras.wgsl): the surface at linear depth d seen through pixel
    /// (x, y) lies at position + d * (at_origin + x * per_x + y * per_y). Linear depth runs along
    /// the perspective axis, so the scaled ray is affine in the pixel, for any perspective
    /// projection. Computed in f64 from the inverse projection; `position` is relative to
    /// `origin`, so that positions near it keep their precision in f32.
    pub fn pixel_rays(&self, extent: ash::vk::Extent2D, origin: DVec3) -> PixelRays {
        let rays = self.pixel_rays_f64(extent);
        PixelRays {
            position: (rays.position - origin).as_vec3(),
            at_origin: rays.at_origin.as_vec3(),
            per_x: rays.per_x.as_vec3(),
            per_y: rays.per_y.as_vec3(),
        }
    }

    /// Where a static surface seen through this camera's pixel (x, y) at linear depth d lies in
    /// `earlier`'s frame: at (w.y, w.z) / w.x with
    /// w = offset + d * (at_origin + x * per_x + y * per_y), pixels as in `pixel_rays`. In the
    /// earlier camera's rays the point is P' + d' * (A' + x' X' + y' Y'), linear in
    /// (d', d' x', d' y'); the inverse of [A' X' Y'] brings this camera's affine rays into it.
    /// Computed in f64.
    pub fn reprojection_into(&self, earlier: &Camera, extent: ash::vk::Extent2D) -> PixelRays {
        let (now, then) = (self.pixel_rays_f64(extent), earlier.pixel_rays_f64(extent));
        let into = glam::DMat3::from_cols(then.at_origin, then.per_x, then.per_y).inverse();
        PixelRays {
            position: (into * (now.position - then.position)).as_vec3(),
            at_origin: (into * now.at_origin).as_vec3(),
            per_x: (into * now.per_x).as_vec3(),
            per_y: (into * now.per_y).as_vec3(),
        }
    }

    fn pixel_rays_f64(&self, extent: ash::vk::Extent2D) -> PixelRaysF64 {
        // Unprojected in view space, where the camera is the origin, then turned into the world:
        // nothing subtracts two far-away positions.
        let inverse_projection = self.projection.as_dmat4().inverse();
        let view_inverse = self.view.as_dmat4().inverse();
        let forward = self.forward().as_dvec3();
        let size = DVec2::new(extent.width as f64, extent.height as f64);
        let ray = |x: f64, y: f64| {
            let ndc = (DVec2::new(x, y) + 0.5) / size * 2.0 - 1.0;
            let on_ray = inverse_projection * DVec4::new(ndc.x, ndc.y, 0.5, 1.0);
            let direction = view_inverse.transform_vector3(on_ray.truncate() / on_ray.w);
            direction / direction.dot(forward)
        };
        // Differences over the whole frame, for precision.
        let (last_x, last_y) = ((size.x - 1.0).max(1.0), (size.y - 1.0).max(1.0));
        let at_origin = ray(0.0, 0.0);
        PixelRaysF64 {
            position: view_inverse.w_axis.truncate(),
            at_origin,
            per_x: (ray(last_x, 0.0) - at_origin) / last_x,
            per_y: (ray(0.0, last_y) - at_origin) / last_y,
        }
    }

    /// How hardware depth z at pixel (x, y) of an `extent` frame becomes linear depth:
    /// 1 / dot(curve, (z, 1, x, y)) (`linear_depth` in shaders/include/gbuffer.wgsl). Along a
    /// pixel's ray, the point at linear depth d is the camera plus d times the ray; its clip z is
    /// c + d * z(ray) and its clip w is d * w(ray), where c is the camera's own clip z and w(ray) is
    /// the same for every pixel (linear depth runs along the perspective axis), so z = c / (d w)
    /// + z(ray) / w, and z(ray) is affine in the pixel. c is not 0 for an invertible projection.
    pub fn depth_curve(&self, extent: ash::vk::Extent2D) -> [f32; 4] {
        let view_projection = self.projection.as_dmat4() * self.view.as_dmat4();
        let rays = self.pixel_rays_f64(extent);
        let clip = |ray: DVec3| view_projection * ray.extend(0.0);
        let own_z = (view_projection * rays.position.extend(1.0)).z;
        let w = clip(rays.at_origin).w;
        let z = |ray: DVec3| clip(ray).z;
        [
            w / own_z,
            -z(rays.at_origin) / own_z,
            -z(rays.per_x) / own_z,
            -z(rays.per_y) / own_z,
        ]
        .map(|v| v as f32)
    }

    /// Unit world-space direction of increasing linear depth.
    pub fn forward(&self) -> Vec3 {
        self.view
            .as_dmat4()
            .inverse()
            .transform_vector3(self.perspective_axis().as_dvec3())
            .normalize()
            .as_vec3()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::abi::PATCHEX_DEPTH_LINEAR_VIEW_Z;

    /// A camera at `eye` turned `yaw` radians about the vertical, with a right-handed
    /// perspective (vertical field of view 1 radian, 16:9, depth 0.1 to 100).
    fn camera(eye: Vec3, yaw: f32) -> Camera {
        let (f, aspect, near, far) = (1.0 / 0.5f32.tan(), 16.0 / 9.0, 0.1, 100.0);
        Camera {
            view: Mat4::from_rotation_y(-yaw) * Mat4::from_translation(-eye),
            projection: Mat4::from_cols_array(&[
                f / aspect,
                0.0,
                0.0,
                0.0,
                0.0,
                f,
                0.0,
                0.0,
                0.0,
                0.0,
                far / (near - far),
                -1.0,
                0.0,
                0.0,
                near * far / (near - far),
                0.0,
            ]),
            jitter: Vec2::ZERO,
            near: 0.1,
            far: 100.0,
            depth_convention: PATCHEX_DEPTH_LINEAR_VIEW_Z,
        }
    }

    /// A static point seen through a pixel of the later camera lands where the earlier camera's
    /// rays see it, after the camera both moved and turned.
    #[test]
    fn reprojection_lands_a_static_point_on_the_earlier_cameras_pixel() {
        let extent = ash::vk::Extent2D {
            width: 320,
            height: 180,
        };
        let now = camera(Vec3::new(0.3, 1.5, 5.0), 0.1);
        let then = camera(Vec3::new(0.0, 1.6, 5.4), 0.25);
        let reprojection = now.reprojection_into(&then, extent);
        let (rays_now, rays_then) = (
            now.pixel_rays(extent, DVec3::ZERO),
            then.pixel_rays(extent, DVec3::ZERO),
        );
        for (x, y, depth) in [(10.0, 20.0, 3.0), (200.5, 90.0, 7.5), (319.0, 179.0, 40.0)] {
            let world = rays_now.surface(x, y, depth);
            let w = reprojection.position
                + depth
                    * (reprojection.at_origin + x * reprojection.per_x + y * reprojection.per_y);
            let (x_then, y_then, depth_then) = (w.y / w.x, w.z / w.x, w.x);
            let seen_then = rays_then.surface(x_then, y_then, depth_then);
            assert!(
                (seen_then - world).length() < 1e-3 * depth,
                "pixel ({x}, {y}) at depth {depth}: {seen_then} against {world}"
            );
            assert!(
                (x_then - x).abs() > 1.0,
                "the camera moved: the pixel must move too"
            );
        }
    }
}
