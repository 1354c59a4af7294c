//! Draws the blended surfaces after the G-buffer, back to front over the G-buffer's depth, into
//! the forward targets, and copies them to the host, which composites them over the lit frame
//! (`translucent_layer.rs`).

use super::gpu_batch::{draw_indexed, GpuBatch};
use super::materials::GpuMaterials;
use super::pipelines::Pipelines;
use super::shadow_pass::set_viewport;
use super::targets::{cleared_attachments, ForwardTargets, GBufferTargets};
use crate::asset::Material;
use crate::gpu::{image_barrier, Gpu, ImageTransition};
use ash::vk;
use glam::Vec3;

pub(crate) struct ForwardInputs<'a> {
    pub pipelines: &'a Pipelines,
    pub gbuffer: &'a GBufferTargets,
    pub targets: &'a ForwardTargets,
    pub frame_set: vk::DescriptorSet,
    pub shadow_maps_set: vk::DescriptorSet,
    pub gpu_materials: &'a GpuMaterials,
    pub materials: &'a [Material],
    pub batches: [&'a GpuBatch; 2],
    pub camera_position: Vec3,
}

pub(crate) fn record_forward_pass(
    gpu: &Gpu,
    command_buffer: vk::CommandBuffer,
    inputs: &ForwardInputs<'_>,
) {
    let targets: Vec<&crate::gpu::Image> = inputs.targets.color.iter().collect();
    // The previous frame's copy read these targets; their contents are discarded.
    image_barrier(
        gpu,
        command_buffer,
        &targets,
        ImageTransition {
            from: (
                vk::ImageLayout::UNDEFINED,
                vk::PipelineStageFlags::TRANSFER,
                vk::AccessFlags::empty(),
            ),
            to: (
                vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT,
                vk::AccessFlags::COLOR_ATTACHMENT_READ | vk::AccessFlags::COLOR_ATTACHMENT_WRITE,
            ),
        },
    );
    let depth_stages =
        vk::PipelineStageFlags::EARLY_FRAGMENT_TESTS | vk::PipelineStageFlags::LATE_FRAGMENT_TESTS;
    let depth = &inputs.gbuffer.depth;
    image_barrier(
        gpu,
        command_buffer,
        &[depth],
        ImageTransition {
            from: (
                vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
                depth_stages,
                vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_WRITE,
            ),
            to: (
                vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
                depth_stages,
                vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_READ,
            ),
        },
    );

    let extent = vk::Extent2D {
        width: depth.desc.width,
        height: depth.desc.height,
    };
    let color_attachments = cleared_attachments(&inputs.targets.color);
    let depth_attachment = vk::RenderingAttachmentInfo::default()
        .image_view(depth.view)
        .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
        .load_op(vk::AttachmentLoadOp::LOAD)
        .store_op(vk::AttachmentStoreOp::NONE);
    let rendering = vk::RenderingInfo::default()
        .render_area(extent.into())
        .layer_count(1)
        .color_attachments(&color_attachments)
        .depth_attachment(&depth_attachment);

    // "Over" needs back to front: each draw sorted by the distance of its centre, as engines
    // sort their translucent objects.
    let mut draws: Vec<(usize, &crate::scene::Draw, f32)> = inputs
        .batches
        .iter()
        .enumerate()
        .flat_map(|(batch, b)| {
            b.blended
                .iter()
                .map(move |(draw, centre)| (batch, draw, centre.distance(inputs.camera_position)))
        })
        .collect();
    draws.sort_by(|a, b| b.2.total_cmp(&a.2));

    let pipelines = inputs.pipelines;
    let layout = pipelines.forward_layout;
    // SAFETY: recording; every bound object is owned by the renderer and alive.
    unsafe {
        let device = &gpu.device;
        device.cmd_begin_rendering(command_buffer, &rendering);
        device.cmd_bind_pipeline(
            command_buffer,
            vk::PipelineBindPoint::GRAPHICS,
            pipelines.forward,
        );
        set_viewport(gpu, command_buffer, extent);
        device.cmd_bind_descriptor_sets(
            command_buffer,
            vk::PipelineBindPoint::GRAPHICS,
            layout,
            0,
            &[inputs.frame_set],
            &[],
        );
        device.cmd_bind_descriptor_sets(
            command_buffer,
            vk::PipelineBindPoint::GRAPHICS,
            layout,
            2,
            &[inputs.shadow_maps_set],
            &[],
        );
        let mut bound = None;
        for (batch, draw, _) in draws {
            if bound != Some(batch) {
                inputs.batches[batch].bind(gpu, command_buffer);
                bound = Some(batch);
            }
            inputs
                .gpu_materials
                .bind(gpu, command_buffer, layout, inputs.materials, draw);
            draw_indexed(gpu, command_buffer, draw);
        }
        device.cmd_end_rendering(command_buffer);
    }

    image_barrier(
        gpu,
        command_buffer,
        &targets,
        ImageTransition {
            from: (
                vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT,
                vk::AccessFlags::COLOR_ATTACHMENT_WRITE,
            ),
            to: (
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                vk::PipelineStageFlags::TRANSFER,
                vk::AccessFlags::TRANSFER_READ,
            ),
        },
    );
    let readback = &inputs.targets.readback;
    let target_bytes = 16 * extent.width as u64 * extent.height as u64;
    for (index, image) in targets.iter().enumerate() {
        let region = vk::BufferImageCopy::default()
            .buffer_offset(index as u64 * target_bytes)
            .image_subresource(
                vk::ImageSubresourceLayers::default()
                    .aspect_mask(vk::ImageAspectFlags::COLOR)
                    .layer_count(1),
            )
            .image_extent(vk::Extent3D {
                width: extent.width,
                height: extent.height,
                depth: 1,
            });
        // SAFETY: recording; the image is in TRANSFER_SRC_OPTIMAL and the buffer holds both.
        unsafe {
            gpu.device.cmd_copy_image_to_buffer(
                command_buffer,
                image.handle,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                readback.handle,
                &[region],
            );
        }
    }
    let to_host = vk::BufferMemoryBarrier::default()
        .src_access_mask(vk::AccessFlags::TRANSFER_WRITE)
        .dst_access_mask(vk::AccessFlags::HOST_READ)
        .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .buffer(readback.handle)
        .offset(0)
        .size(vk::WHOLE_SIZE);
    // SAFETY: recording; the buffer is alive.
    unsafe {
        gpu.device.cmd_pipeline_barrier(
            command_buffer,
            vk::PipelineStageFlags::TRANSFER,
            vk::PipelineStageFlags::HOST,
            vk::DependencyFlags::empty(),
            &[],
            &[to_host],
            &[],
        );
    }
}
