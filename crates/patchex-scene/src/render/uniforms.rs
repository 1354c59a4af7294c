//! Host-side mirrors of the shader structs; field order and padding follow the WGSL layouts.

use crate::asset::{AlphaMode, Material};
use crate::scene::{CameraState, SunDescription, SunLight};
use bytemuck::{Pod, Zeroable};
use glam::Mat4;

/// `Frame` in shaders/include/frame.wgsl (the uniform buffer), mirrored by build.rs.
mod generated {
    include!(concat!(env!("OUT_DIR"), "/frame.rs"));
}
pub(crate) use generated::Frame as FrameUniforms;

impl FrameUniforms {
    pub fn new(
        camera: &CameraState,
        previous: &CameraState,
        sun: &SunLight,
        sky: &SunDescription,
        width: u32,
        height: u32,
    ) -> Self {
        let view_proj = camera.view_proj();
        let extend = |rgb: [f32; 3]| [rgb[0], rgb[1], rgb[2], 0.0];
        Self {
            view_proj: view_proj.to_cols_array_2d(),
            prev_view_proj: previous.view_proj().to_cols_array_2d(),
            view: camera.view.to_cols_array_2d(),
            inv_view_proj: view_proj.inverse().to_cols_array_2d(),
            light_view_proj: sun.light_view_proj.to_cols_array_2d(),
            camera_position: camera.position.extend(camera.far).to_array(),
            sun_direction: sun.direction.extend(0.0).to_array(),
            sun_radiance: sun.radiance.extend(0.0).to_array(),
            sky_zenith: extend(sky.sky_zenith),
            sky_horizon: extend(sky.sky_horizon),
            ground_ambient: extend(sky.ground_ambient),
            viewport: [width as f32, height as f32, camera.near, camera.far],
            shadow_params: [sun.depth_bias, 1.5 * sun.texel_size, 0.0, 0.0],
        }
    }
}

/// `Material` in gbuffer.wgsl (push constants; the WGSL struct is padded to 64 bytes).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub(crate) struct MaterialConstants {
    pub base_color: [f32; 4],
    pub emissive: [f32; 4],
    pub metallic: f32,
    pub roughness: f32,
    pub normal_scale: f32,
    pub alpha_cutoff: f32,
    pub specular: f32,
    pub stencil: f32,
    pub padding: [f32; 2],
}

impl MaterialConstants {
    pub fn new(material: &Material, stencil: u32) -> Self {
        Self {
            base_color: material.base_color.to_array(),
            emissive: material.emissive.extend(0.0).to_array(),
            metallic: material.metallic,
            roughness: material.roughness,
            normal_scale: material.normal_scale,
            alpha_cutoff: match material.alpha_mode {
                AlphaMode::Opaque => 0.0,
                AlphaMode::Mask(cutoff) => cutoff,
            },
            specular: material.specular,
            stencil: stencil as f32,
            padding: [0.0; 2],
        }
    }
}

/// `Light` in shadow.wgsl (push constants).
pub(crate) fn light_constants(light_view_proj: Mat4) -> [f32; 16] {
    light_view_proj.to_cols_array()
}
