//! Packs one instant's engine G-buffer into the plugin's canonical images: linear depth (R32F),
//! and the unit world normal with the object id in 32 bits (R32UI; `shaders/include/gbuffer.wgsl`).
//! World positions are rebuilt from depth where they are needed (`Camera::pixel_rays`).
//! Runs for frame t at submit, and counts the pixels whose geometry is NaN or infinite.

use ash::vk;

use crate::abi::PatchexNormalEncoding;
use crate::camera::Camera;
use crate::passes::Texture;
use crate::shaders::pack_gbuffer::{binding, Params};
use crate::vk::buffer::CounterRange;
use crate::vk::image::OwnedImage;
use crate::vk::recorder::{Pass, Recorder};

/// One instant's engine G-buffer, as passes bind it: frame t's for the packing, the target's for
/// the warps, which read it through the same functions (`shaders/include/gbuffer.wgsl`).
#[derive(Clone, Copy)]
pub struct EngineGbuffer {
    pub depth: Texture,
    pub normal: Texture,
    pub normal_encoding: PatchexNormalEncoding,
    /// `None`: every pixel is static geometry (id 0); a placeholder is bound instead.
    pub stencil: Option<Texture>,
    pub camera: Camera,
}

impl EngineGbuffer {
    /// The object ids alone, for the passes that read them without waiting for the packing.
    pub fn objects(&self, placeholder_uint: Texture) -> EngineObjects {
        EngineObjects {
            stencil: self.stencil.unwrap_or(placeholder_uint),
            has_stencil: self.stencil.is_some() as u32,
        }
    }
}

/// An engine's stencil as object ids (`stencil_object_id` in shaders/include/gbuffer.wgsl).
#[derive(Clone, Copy)]
pub struct EngineObjects {
    /// The stencil, or a placeholder without one.
    pub stencil: Texture,
    /// The shaders' `has_stencil`: 0 reads every pixel as static geometry.
    pub has_stencil: u32,
}

pub struct PackOutputs<'a> {
    pub depth: &'a OwnedImage,
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
) -> Params {
    Params {
        depth_curve: camera.depth_curve(extent),
        far: camera.far,
        depth_convention: camera.depth_convention,
        extent: [extent.width, extent.height],
        normal_encoding,
        has_stencil: has_stencil as u32,
        ..Default::default()
    }
}

pub fn record(
    rec: &mut Recorder,
    pass: Pass,
    extent: vk::Extent2D,
    gbuffer: &EngineGbuffer,
    placeholder_uint: Texture,
    outputs: &PackOutputs,
) {
    let bound = rec.bind(pass, |writes| {
        writes
            .image(binding::DEPTH, gbuffer.depth)
            .image(binding::NORMAL, gbuffer.normal)
            .image(
                binding::STENCIL,
                gbuffer.stencil.unwrap_or(placeholder_uint),
            )
            .image(binding::PACKED_DEPTH, outputs.depth)
            .image(binding::NORMAL_ID, outputs.normal_id)
            .buffer(binding::COUNTERS, &outputs.counters)
    });
    let params = params(
        &gbuffer.camera,
        extent,
        gbuffer.normal_encoding,
        gbuffer.stencil.is_some(),
    );
    rec.dispatch(&bound, &params, extent);
}
