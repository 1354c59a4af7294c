//! Remodulation: multiplies the extrapolated shading by the target instant's own material and
//! writes the engine's output image.

use ash::vk;

use crate::passes::Texture;
use crate::shaders::remodulate::{binding, Params};
use crate::vk::pipeline::{ComputePipeline, DescriptorWrites};

pub struct RemodulateInputs {
    pub shading: Texture,
    pub base_color: Texture,
    pub material: Option<Texture>,
    pub placeholder: Texture,
}

pub fn record(
    pipeline: &ComputePipeline,
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    set: vk::DescriptorSet,
    extent: vk::Extent2D,
    inputs: &RemodulateInputs,
    output: Texture,
) {
    let material = inputs.material.unwrap_or(inputs.placeholder);
    DescriptorWrites::new(pipeline)
        .image(binding::SHADING, inputs.shading.view, inputs.shading.layout)
        .image(
            binding::BASE_COLOR,
            inputs.base_color.view,
            inputs.base_color.layout,
        )
        .image(binding::MATERIAL, material.view, material.layout)
        .image(binding::OUTPUT, output.view, output.layout)
        .update(device, set);
    let params = Params {
        extent: [extent.width, extent.height],
        has_material: inputs.material.is_some() as u32,
        ..Default::default()
    };
    pipeline.dispatch(device, cmd, set, &params, extent);
}
