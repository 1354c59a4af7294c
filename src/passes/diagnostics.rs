//! Copies holes, regions and the LBP map into the engine's diagnostics image
//! (`shaders/write_diagnostics.wgsl`; channel meanings in `PatchexDiagnostics`), and the shadow
//! sub-task's flow and layers into the shadow diagnostics image
//! (`shaders/write_shadow_diagnostics.wgsl`, `PatchexShadowDiagnostics`).

use ash::vk;

use crate::passes::Texture;
use crate::shaders::{write_diagnostics, write_shadow_diagnostics};
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
    use write_diagnostics::{binding, Params};
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

pub struct ShadowDiagnosticsInputs<'a> {
    pub flow: &'a OwnedImage,
    pub shadow_layer: &'a OwnedImage,
    pub warped_layer: &'a OwnedImage,
}

pub fn record_shadows(
    pipeline: &ComputePipeline,
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    set: vk::DescriptorSet,
    extent: vk::Extent2D,
    inputs: &ShadowDiagnosticsInputs,
    diagnostics: Texture,
) {
    use write_shadow_diagnostics::{binding, Params};
    let general = vk::ImageLayout::GENERAL;
    DescriptorWrites::new(pipeline)
        .image(binding::FLOW, inputs.flow.view, general)
        .image(binding::SHADOW_LAYER, inputs.shadow_layer.view, general)
        .image(binding::WARPED_LAYER, inputs.warped_layer.view, general)
        .image(binding::DIAGNOSTICS, diagnostics.view, diagnostics.layout)
        .update(device, set);
    let params = Params {
        extent: [extent.width, extent.height],
    };
    pipeline.dispatch(device, cmd, set, &params, extent);
}
