//! Demodulation of frame t: reads its colour and material G-buffer, writes the shading the
//! rest of the pipeline warps, and counts the pixels whose inputs it had to sanitise.

use ash::vk;

use crate::passes::{CounterRange, Texture};
use crate::shaders::demodulate::{binding, Params};
use crate::vk::image::OwnedImage;
use crate::vk::pipeline::{ComputePipeline, DescriptorWrites};

pub struct DemodulateInputs {
    pub color: Texture,
    pub base_color: Texture,
    /// `None`: Unreal's default material (metallic 0, specular 0.5); `placeholder` is bound.
    pub material: Option<Texture>,
    pub placeholder: Texture,
}

#[allow(clippy::too_many_arguments)]
pub fn record(
    pipeline: &ComputePipeline,
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    set: vk::DescriptorSet,
    extent: vk::Extent2D,
    inputs: &DemodulateInputs,
    shading: &OwnedImage,
    counters: &CounterRange,
) {
    let material = inputs.material.unwrap_or(inputs.placeholder);
    DescriptorWrites::new(pipeline)
        .image(binding::COLOR, inputs.color.view, inputs.color.layout)
        .image(
            binding::BASE_COLOR,
            inputs.base_color.view,
            inputs.base_color.layout,
        )
        .image(binding::MATERIAL, material.view, material.layout)
        .image(binding::DEMODULATED, shading.view, vk::ImageLayout::GENERAL)
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
