//! Shadow separation (`shaders/separate_shadows.wgsl`), run in place of demodulation when the
//! engine gives a shadow input, after the G-buffer packing (it reads the object ids): writes
//! the demodulated frame, the shadow layer and the mask the flow tracks, and counts the pixels
//! whose inputs it sanitised.

use ash::vk;

use crate::passes::{CounterRange, Texture};
use crate::shaders::separate_shadows::{binding, Params};
use crate::vk::image::OwnedImage;
use crate::vk::pipeline::{ComputePipeline, DescriptorWrites};

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
    /// Frame t's packed normal and object id (read).
    pub source_normal_id: &'a OwnedImage,
    pub shading: &'a OwnedImage,
    pub shadow_layer: &'a OwnedImage,
    pub flow_mask: &'a OwnedImage,
}

#[allow(clippy::too_many_arguments)]
pub fn record(
    pipeline: &ComputePipeline,
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    set: vk::DescriptorSet,
    extent: vk::Extent2D,
    inputs: &SeparationInputs,
    outputs: &SeparationOutputs,
    counters: &CounterRange,
) {
    let general = vk::ImageLayout::GENERAL;
    let material = inputs.material.unwrap_or(inputs.placeholder);
    let unshadowed = inputs.color_without_dynamic_shadows;
    DescriptorWrites::new(pipeline)
        .image(binding::COLOR, inputs.color.view, inputs.color.layout)
        .image(
            binding::COLOR_WITHOUT_DYNAMIC_SHADOWS,
            unshadowed.view,
            unshadowed.layout,
        )
        .image(binding::SHADOW_MASK, inputs.mask.view, inputs.mask.layout)
        .image(
            binding::BASE_COLOR,
            inputs.base_color.view,
            inputs.base_color.layout,
        )
        .image(binding::MATERIAL, material.view, material.layout)
        .image(binding::SHADING, outputs.shading.view, general)
        .image(binding::SHADOW_LAYER, outputs.shadow_layer.view, general)
        .image(binding::FLOW_MASK, outputs.flow_mask.view, general)
        .image(
            binding::SOURCE_NORMAL_ID,
            outputs.source_normal_id.view,
            general,
        )
        .buffer(
            binding::COUNTERS,
            counters.buffer,
            counters.offset,
            counters.range,
        )
        .update(device, set);
    let params = Params {
        extent: [extent.width, extent.height],
        has_material: inputs.material.is_some() as u32,
        ..Default::default()
    };
    pipeline.dispatch(device, cmd, set, &params, extent);
}
