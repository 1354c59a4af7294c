//! Shadow separation (`shaders/separate_shadows.wgsl`), run in place of demodulation when the
//! engine gives a shadow input, after the G-buffer packing (it reads the object ids): writes
//! the demodulated frame, without the dynamic casters' shadows on static receivers when they
//! are tracked, and the shadow layer, the share of light those shadows take away; and counts
//! the pixels whose inputs it sanitised (the flow's pyramid reads the mask itself).

use ash::vk;

use crate::passes::pack_gbuffer::EngineObjects;
use crate::passes::{CounterRange, Texture};
use crate::shaders::separate_shadows::{binding, Params};
use crate::vk::image::OwnedImage;
use crate::vk::recorder::{Pass, Recorder};

pub struct SeparationInputs {
    pub color: Texture,
    pub color_without_dynamic_shadows: Texture,
    pub mask: Texture,
    pub base_color: Texture,
    /// `None`: Unreal's default material; `placeholder` is bound.
    pub material: Option<Texture>,
    pub placeholder: Texture,
}

pub struct SeparationOutputs<'a> {
    /// Frame t's object ids (read).
    pub source_objects: EngineObjects,
    pub shading: &'a OwnedImage,
    pub shadow_layer: &'a OwnedImage,
}

/// `tracked`: frame t-1's shadows were tracked, so the extrapolation moves the layer; without,
/// the frame keeps its shadows and the layer is zero.
pub fn record(
    rec: &mut Recorder,
    pass: Pass,
    extent: vk::Extent2D,
    inputs: &SeparationInputs,
    outputs: &SeparationOutputs,
    counters: &CounterRange,
    tracked: bool,
) {
    let material = inputs.material.unwrap_or(inputs.placeholder);
    let unshadowed = inputs.color_without_dynamic_shadows;
    let bound = rec.bind(pass, |writes| {
        writes
            .image(binding::COLOR, inputs.color)
            .image(binding::COLOR_WITHOUT_DYNAMIC_SHADOWS, unshadowed)
            .image(binding::SHADOW_MASK, inputs.mask)
            .image(binding::BASE_COLOR, inputs.base_color)
            .image(binding::MATERIAL, material)
            .image(binding::SHADING, outputs.shading)
            .image(binding::SHADOW_LAYER, outputs.shadow_layer)
            .image(binding::SOURCE_STENCIL, outputs.source_objects.stencil)
            .buffer(binding::COUNTERS, counters)
    });
    let params = Params {
        extent: [extent.width, extent.height],
        has_material: inputs.material.is_some() as u32,
        tracked: tracked as u32,
        has_stencil: outputs.source_objects.has_stencil,
        ..Default::default()
    };
    rec.dispatch(&bound, &params, extent);
}
