//! Rasterizes static and dynamic geometry into the G-buffer targets.

use super::gpu_batch::GpuBatch;
use super::materials::GpuMaterials;
use super::pipelines::Pipelines;
use super::shadow_pass::set_viewport;
use super::targets::{cleared_attachments, GBufferTargets};
use crate::asset::Material;
use crate::gpu::{image_barrier, Gpu, ImageTransition};
use ash::vk;

pub(crate) struct GBufferInputs<'a> {
    pub pipelines: &'a Pipelines,
    pub targets: &'a GBufferTargets,
    pub frame_set: vk::DescriptorSet,
    pub gpu_materials: &'a GpuMaterials,
    pub materials: &'a [Material],
    pub batches: [&'a GpuBatch; 2],
}

pub(crate) fn record_gbuffer_pass(
    gpu: &Gpu,
    command_buffer: vk::CommandBuffer,
    inputs: &GBufferInputs<'_>,
) {
    let targets = inputs.targets;
    let colors: Vec<&crate::gpu::Image> = targets.color.iter().collect();
    // The resolve pass of the previous frame read these targets; their contents are discarded.
    image_barrier(
        gpu,
        command_buffer,
        &colors,
        ImageTransition {
            from: (
                vk::ImageLayout::UNDEFINED,
                vk::PipelineStageFlags::COMPUTE_SHADER,
                vk::AccessFlags::empty(),
            ),
            to: (
                vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT,
                vk::AccessFlags::COLOR_ATTACHMENT_WRITE,
            ),
        },
    );
    let depth_stages =
        vk::PipelineStageFlags::EARLY_FRAGMENT_TESTS | vk::PipelineStageFlags::LATE_FRAGMENT_TESTS;
    let depth_access = vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_READ
        | vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_WRITE;
    image_barrier(
        gpu,
        command_buffer,
        &[&targets.depth],
        ImageTransition {
            from: (vk::ImageLayout::UNDEFINED, depth_stages, depth_access),
            to: (
                vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
                depth_stages,
                depth_access,
            ),
        },
    );

    let extent = vk::Extent2D {
        width: targets.depth.desc.width,
        height: targets.depth.desc.height,
    };
    let color_attachments = cleared_attachments(&targets.color);
    let depth_attachment = vk::RenderingAttachmentInfo::default()
        .image_view(targets.depth.view)
        .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
        .load_op(vk::AttachmentLoadOp::CLEAR)
        .store_op(vk::AttachmentStoreOp::STORE)
        .clear_value(vk::ClearValue {
            depth_stencil: vk::ClearDepthStencilValue {
                depth: 1.0,
                stencil: 0,
            },
        });
    let rendering = vk::RenderingInfo::default()
        .render_area(extent.into())
        .layer_count(1)
        .color_attachments(&color_attachments)
        .depth_attachment(&depth_attachment);
    let pipelines = inputs.pipelines;
    // SAFETY: recording; every bound object is owned by the renderer and alive.
    unsafe {
        let device = &gpu.device;
        device.cmd_begin_rendering(command_buffer, &rendering);
        device.cmd_bind_pipeline(
            command_buffer,
            vk::PipelineBindPoint::GRAPHICS,
            pipelines.gbuffer,
        );
        set_viewport(gpu, command_buffer, extent);
        device.cmd_bind_descriptor_sets(
            command_buffer,
            vk::PipelineBindPoint::GRAPHICS,
            pipelines.gbuffer_layout,
            0,
            &[inputs.frame_set],
            &[],
        );
        for batch in inputs.batches {
            batch.draw_opaque(gpu, command_buffer, |draw| {
                inputs.gpu_materials.bind(
                    gpu,
                    command_buffer,
                    pipelines.gbuffer_layout,
                    inputs.materials,
                    draw,
                );
            });
        }
        device.cmd_end_rendering(command_buffer);
    }
    image_barrier(
        gpu,
        command_buffer,
        &colors,
        ImageTransition {
            from: (
                vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT,
                vk::AccessFlags::COLOR_ATTACHMENT_WRITE,
            ),
            to: (
                vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                vk::PipelineStageFlags::COMPUTE_SHADER,
                vk::AccessFlags::SHADER_READ,
            ),
        },
    );
}
