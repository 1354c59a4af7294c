//! Local binary pattern of the warped frame (`shaders/lbp.wgsl`), an input of the networks.

use ash::vk;

use crate::shaders::lbp::{binding, Params};
use crate::vk::image::OwnedImage;
use crate::vk::pipeline::{ComputePipeline, DescriptorWrites};

pub fn record(
    pipeline: &ComputePipeline,
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    set: vk::DescriptorSet,
    extent: vk::Extent2D,
    warped: &OwnedImage,
    lbp: &OwnedImage,
) {
    let general = vk::ImageLayout::GENERAL;
    DescriptorWrites::new(pipeline)
        .image(binding::WARPED, warped.view, general)
        .image(binding::LBP, lbp.view, general)
        .update(device, set);
    let params = Params {
        extent: [extent.width, extent.height],
    };
    pipeline.dispatch(device, cmd, set, &params, extent);
}
