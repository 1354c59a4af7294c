//! Renders casters into a sun shadow map and leaves it readable by the resolve and forward
//! passes.

use super::gpu_batch::GpuBatch;
use super::pipelines::Pipelines;
use super::uniforms::light_constants;
use crate::gpu::{image_barrier, Gpu, Image, ImageTransition};
use ash::vk;
use glam::Mat4;

/// The stages that read the shadow maps: the resolve pass and the forward pass.
pub(crate) const SHADOW_READERS: vk::PipelineStageFlags = vk::PipelineStageFlags::from_raw(
    vk::PipelineStageFlags::COMPUTE_SHADER.as_raw()
        | vk::PipelineStageFlags::FRAGMENT_SHADER.as_raw(),
);

/// `previous_reader` is the stage that last read the map (its contents are discarded).
pub(crate) fn record_shadow_pass(
    gpu: &Gpu,
    command_buffer: vk::CommandBuffer,
    pipelines: &Pipelines,
    map: &Image,
    casters: &[&GpuBatch],
    light_view_proj: Mat4,
    previous_reader: vk::PipelineStageFlags,
) {
    let depth_stages =
        vk::PipelineStageFlags::EARLY_FRAGMENT_TESTS | vk::PipelineStageFlags::LATE_FRAGMENT_TESTS;
    image_barrier(
        gpu,
        command_buffer,
        &[map],
        ImageTransition {
            from: (
                vk::ImageLayout::UNDEFINED,
                previous_reader,
                vk::AccessFlags::empty(),
            ),
            to: (
                vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
                depth_stages,
                vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_READ
                    | vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_WRITE,
            ),
        },
    );
    let extent = vk::Extent2D {
        width: map.desc.width,
        height: map.desc.height,
    };
    let depth_attachment = vk::RenderingAttachmentInfo::default()
        .image_view(map.view)
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
        .depth_attachment(&depth_attachment);
    let constants = light_constants(light_view_proj);
    // SAFETY: recording into a command buffer; pipeline, layout and map are alive.
    unsafe {
        let device = &gpu.device;
        device.cmd_begin_rendering(command_buffer, &rendering);
        device.cmd_bind_pipeline(
            command_buffer,
            vk::PipelineBindPoint::GRAPHICS,
            pipelines.shadow,
        );
        set_viewport(gpu, command_buffer, extent);
        device.cmd_push_constants(
            command_buffer,
            pipelines.shadow_layout,
            vk::ShaderStageFlags::VERTEX,
            0,
            bytemuck::cast_slice(&constants),
        );
        for batch in casters {
            batch.draw_opaque(gpu, command_buffer, |_| {});
        }
        device.cmd_end_rendering(command_buffer);
    }
    image_barrier(
        gpu,
        command_buffer,
        &[map],
        ImageTransition {
            from: (
                vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
                depth_stages,
                vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_WRITE,
            ),
            to: (
                vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                SHADOW_READERS,
                vk::AccessFlags::SHADER_READ,
            ),
        },
    );
}

pub(crate) fn set_viewport(gpu: &Gpu, command_buffer: vk::CommandBuffer, extent: vk::Extent2D) {
    let viewport = vk::Viewport {
        x: 0.0,
        y: 0.0,
        width: extent.width as f32,
        height: extent.height as f32,
        min_depth: 0.0,
        max_depth: 1.0,
    };
    // SAFETY: recording; the bound pipeline declares viewport and scissor dynamic.
    unsafe {
        gpu.device.cmd_set_viewport(command_buffer, 0, &[viewport]);
        gpu.device
            .cmd_set_scissor(command_buffer, 0, &[extent.into()]);
    }
}
