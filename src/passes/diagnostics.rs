//! Copies holes, regions and the LBP map into the engine's diagnostics image
//! (`shaders/write_diagnostics.wgsl`; channel meanings in `PatchexDiagnostics`).

use ash::vk;

use crate::passes::Texture;
use crate::shaders::write_diagnostics::{binding, Params};
use crate::vk::image::OwnedImage;
use crate::vk::pipeline::{ComputePipeline, DescriptorWrites};

pub struct DiagnosticsInputs<'a> {
    pub warped: &'a OwnedImage,
    pub regions: &'a OwnedImage,
    pub lbp: &'a OwnedImage,
}

pub fn record(
    pipeline: &ComputePipeline,
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    set: vk::DescriptorSet,
    extent: vk::Extent2D,
    inputs: &DiagnosticsInputs,
    diagnostics: Texture,
) {
    let general = vk::ImageLayout::GENERAL;
    DescriptorWrites::new(pipeline)
        .image(binding::WARPED, inputs.warped.view, general)
        .image(binding::REGIONS, inputs.regions.view, general)
        .image(binding::LBP, inputs.lbp.view, general)
        .image(binding::DIAGNOSTICS, diagnostics.view, diagnostics.layout)
        .update(device, set);
    let params = Params {
        extent: [extent.width, extent.height],
    };
    pipeline.dispatch(device, cmd, set, &params, extent);
}
