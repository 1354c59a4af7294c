//! One-shot command buffers and the barrier helper every pass uses.

use super::{Gpu, Image};
use crate::error::{Result, VkContext};
use ash::vk;

impl Gpu {
    /// Records with `record`, submits, and waits for completion. The renderer runs one frame at
    /// a time, so a blocking submit keeps host-side reuse of buffers trivially safe.
    pub(crate) fn submit_and_wait(&self, record: impl FnOnce(vk::CommandBuffer)) -> Result<()> {
        let allocate_info = vk::CommandBufferAllocateInfo::default()
            .command_pool(self.command_pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: the command buffer and fence are created, used and destroyed within this call,
        // and the fence wait guarantees the GPU is done with both before they are released.
        unsafe {
            let command_buffer = self
                .device
                .allocate_command_buffers(&allocate_info)
                .vk("vkAllocateCommandBuffers")?[0];
            let begin = vk::CommandBufferBeginInfo::default()
                .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
            self.device
                .begin_command_buffer(command_buffer, &begin)
                .vk("vkBeginCommandBuffer")?;
            record(command_buffer);
            self.device
                .end_command_buffer(command_buffer)
                .vk("vkEndCommandBuffer")?;
            let fence = self
                .device
                .create_fence(&vk::FenceCreateInfo::default(), None)
                .vk("vkCreateFence")?;
            let command_buffers = [command_buffer];
            let submit = vk::SubmitInfo::default().command_buffers(&command_buffers);
            let result = self
                .device
                .queue_submit(self.queue, &[submit], fence)
                .vk("vkQueueSubmit")
                .and_then(|()| {
                    self.device
                        .wait_for_fences(&[fence], true, u64::MAX)
                        .vk("vkWaitForFences")
                });
            self.device.destroy_fence(fence, None);
            self.device
                .free_command_buffers(self.command_pool, &command_buffers);
            result
        }
    }
}

/// One layout transition with its execution and memory dependency.
pub(crate) struct ImageTransition {
    pub from: (vk::ImageLayout, vk::PipelineStageFlags, vk::AccessFlags),
    pub to: (vk::ImageLayout, vk::PipelineStageFlags, vk::AccessFlags),
}

pub(crate) fn image_barrier(
    gpu: &Gpu,
    command_buffer: vk::CommandBuffer,
    images: &[&Image],
    transition: ImageTransition,
) {
    let barriers: Vec<vk::ImageMemoryBarrier> = images
        .iter()
        .map(|image| {
            vk::ImageMemoryBarrier::default()
                .old_layout(transition.from.0)
                .new_layout(transition.to.0)
                .src_access_mask(transition.from.2)
                .dst_access_mask(transition.to.2)
                .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
                .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
                .image(image.handle)
                .subresource_range(image.full_range())
        })
        .collect();
    // SAFETY: `command_buffer` is recording and every image is alive.
    unsafe {
        gpu.device.cmd_pipeline_barrier(
            command_buffer,
            transition.from.1,
            transition.to.1,
            vk::DependencyFlags::empty(),
            &[],
            &[],
            &barriers,
        );
    }
}
