//! Packs one instant's engine G-buffer into the plugin's canonical images:
//! geometry = (world position, linear depth), normal_id = (unit world normal, object id).
//! Runs for frame t at submit and for the target instant at extrapolation, and counts the
//! pixels whose geometry is NaN or infinite.

use ash::vk;

use crate::abi::PatchexNormalEncoding;
use crate::camera::Camera;
use crate::passes::Texture;
use crate::shaders::pack_gbuffer::{binding, Params};
use crate::vk::buffer::CounterRange;
use crate::vk::image::OwnedImage;
use crate::vk::recorder::{Pass, Recorder};

pub struct PackInputs {
    pub depth: Texture,
    pub normal: Texture,
    pub normal_encoding: PatchexNormalEncoding,
    /// `None`: every pixel is static geometry (id 0); `placeholder_uint` is bound.
    pub stencil: Option<Texture>,
    /// The target's motion vectors, checked for NaN and infinity; frame t's are not read.
    pub motion: Option<Texture>,
    pub placeholder: Texture,
    pub placeholder_uint: Texture,
}

pub struct PackOutputs<'a> {
    pub geometry: &'a OwnedImage,
    pub normal_id: &'a OwnedImage,
    /// `GeometryCounters`: one u32, the pixels with a NaN or infinite input.
    pub counters: CounterRange,
}

pub const COUNTER_BYTES: u64 = 4;

pub fn params(
    camera: &Camera,
    extent: vk::Extent2D,
    normal_encoding: u32,
    has_stencil: bool,
    has_motion: bool,
) -> Params {
    Params {
        inv_view_proj: camera.inverse_view_projection().to_cols_array_2d(),
        camera_position: camera.position().into(),
        far: camera.far,
        camera_forward: camera.forward().into(),
        depth_convention: camera.depth_convention,
        extent: [extent.width, extent.height],
        normal_encoding,
        has_stencil: has_stencil as u32,
        has_motion: has_motion as u32,
        ..Default::default()
    }
}

pub fn record(
    rec: &mut Recorder,
    pass: Pass,
    extent: vk::Extent2D,
    camera: &Camera,
    inputs: &PackInputs,
    outputs: &PackOutputs,
) {
    let stencil = inputs.stencil.unwrap_or(inputs.placeholder_uint);
    let motion = inputs.motion.unwrap_or(inputs.placeholder);
    let bound = rec.bind(pass, |writes| {
        writes
            .image(binding::DEPTH, inputs.depth)
            .image(binding::NORMAL, inputs.normal)
            .image(binding::STENCIL, stencil)
            .image(binding::GEOMETRY, outputs.geometry)
            .image(binding::NORMAL_ID, outputs.normal_id)
            .image(binding::MOTION, motion)
            .buffer(binding::COUNTERS, &outputs.counters)
    });
    let params = params(
        camera,
        extent,
        inputs.normal_encoding,
        inputs.stencil.is_some(),
        inputs.motion.is_some(),
    );
    rec.dispatch(&bound, &params, extent);
}
