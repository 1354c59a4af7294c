//! Remodulation: multiplies the extrapolated shading by the target instant's own material and
//! writes the engine's output image, counting the pixels whose inputs or result it had to
//! sanitise. With a shadow input, the warped shadow layer is added back to the shading first.

use ash::vk;

use crate::passes::{CounterRange, Texture};
use crate::shaders::remodulate::{binding, Params};
use crate::vk::pipeline::{ComputePipeline, DescriptorWrites};

pub struct RemodulateInputs {
    pub shading: Texture,
    pub base_color: Texture,
    pub material: Option<Texture>,
    /// The warped shadow layer, added to the shading first; `None` without a shadow input.
    pub shadow_layer: Option<Texture>,
    pub placeholder: Texture,
}

#[allow(clippy::too_many_arguments)]
pub fn record(
    pipeline: &ComputePipeline,
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    set: vk::DescriptorSet,
    extent: vk::Extent2D,
    inputs: &RemodulateInputs,
    output: Texture,
    counters: &CounterRange,
) {
    let material = inputs.material.unwrap_or(inputs.placeholder);
    let shadow_layer = inputs.shadow_layer.unwrap_or(inputs.placeholder);
    DescriptorWrites::new(pipeline)
        .image(binding::SHADING, inputs.shading.view, inputs.shading.layout)
        .image(
            binding::BASE_COLOR,
            inputs.base_color.view,
            inputs.base_color.layout,
        )
        .image(binding::MATERIAL, material.view, material.layout)
        .image(
            binding::SHADOW_LAYER,
            shadow_layer.view,
            shadow_layer.layout,
        )
        .image(binding::OUTPUT, output.view, output.layout)
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
        has_shadow_layer: inputs.shadow_layer.is_some() as u32,
    };
    pipeline.dispatch(device, cmd, set, &params, extent);
}
