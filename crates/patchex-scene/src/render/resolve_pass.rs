//! Lights the G-buffer and writes every dataset layer into the host-visible planes buffer.

use super::pipelines::Pipelines;
use crate::gpu::{Buffer, Gpu};
use ash::vk;

pub(crate) fn record_resolve_pass(
    gpu: &Gpu,
    command_buffer: vk::CommandBuffer,
    pipelines: &Pipelines,
    resolve_set: vk::DescriptorSet,
    planes: &Buffer,
    (width, height): (u32, u32),
    lighting: bool,
) {
    let buffer_barrier = |src_stage, src_access, dst_stage, dst_access| {
        let barrier = vk::BufferMemoryBarrier::default()
            .src_access_mask(src_access)
            .dst_access_mask(dst_access)
            .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
            .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
            .buffer(planes.handle)
            .offset(0)
            .size(vk::WHOLE_SIZE);
        // SAFETY: recording; the buffer is alive.
        unsafe {
            gpu.device.cmd_pipeline_barrier(
                command_buffer,
                src_stage,
                dst_stage,
                vk::DependencyFlags::empty(),
                &[],
                &[barrier],
                &[],
            );
        }
    };
    // The previous frame's dispatch wrote the same buffer.
    buffer_barrier(
        vk::PipelineStageFlags::COMPUTE_SHADER,
        vk::AccessFlags::SHADER_WRITE,
        vk::PipelineStageFlags::COMPUTE_SHADER,
        vk::AccessFlags::SHADER_WRITE,
    );
    let options = [u32::from(lighting)];
    // SAFETY: recording; pipeline, layout and set are alive.
    unsafe {
        let device = &gpu.device;
        device.cmd_bind_pipeline(
            command_buffer,
            vk::PipelineBindPoint::COMPUTE,
            pipelines.resolve,
        );
        device.cmd_bind_descriptor_sets(
            command_buffer,
            vk::PipelineBindPoint::COMPUTE,
            pipelines.resolve_pipeline_layout,
            0,
            &[resolve_set],
            &[],
        );
        device.cmd_push_constants(
            command_buffer,
            pipelines.resolve_pipeline_layout,
            vk::ShaderStageFlags::COMPUTE,
            0,
            bytemuck::cast_slice(&options),
        );
        device.cmd_dispatch(command_buffer, width.div_ceil(8), height.div_ceil(8), 1);
    }
    buffer_barrier(
        vk::PipelineStageFlags::COMPUTE_SHADER,
        vk::AccessFlags::SHADER_WRITE,
        vk::PipelineStageFlags::HOST,
        vk::AccessFlags::HOST_READ,
    );
}
