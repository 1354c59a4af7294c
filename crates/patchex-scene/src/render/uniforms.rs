//! What the host writes into the shaders' structs. Their layouts are the shaders' own: build.rs
//! mirrors them from the WGSL, so a field added there is one that this file must fill in.

use crate::asset::{AlphaMode, Material};
use crate::scene::{CameraState, SunDescription, SunLight};
use glam::Mat4;

/// Mirrored by build.rs: `Frame` in shaders/include/frame.wgsl (the uniform buffer) and
/// `Material` in gbuffer.wgsl (push constants).
mod generated {
    include!(concat!(env!("OUT_DIR"), "/structs.rs"));
}
pub(crate) use generated::{Frame as FrameUniforms, Material as MaterialConstants};

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

impl MaterialConstants {
    pub fn new(material: &Material, stencil: u32) -> Self {
        Self {
            base_color: material.base_color.to_array(),
            emissive: material.emissive.extend(0.0).to_array(),
            metallic: material.metallic,
            roughness: material.roughness,
            normal_scale: material.normal_scale,
            alpha_cutoff: match material.alpha_mode {
                AlphaMode::Opaque | AlphaMode::Blend => 0.0,
                AlphaMode::Mask(cutoff) => cutoff,
            },
            specular: material.specular,
            stencil: stencil as f32,
            _pad_end: [0; 8],
        }
    }
}

/// `Light` in shadow.wgsl (push constants).
pub(crate) fn light_constants(light_view_proj: Mat4) -> [f32; 16] {
    light_view_proj.to_cols_array()
}
