//! GPU time of each pass of a frame, from timestamp queries around the passes.

use crate::error::{Result, VkContext};
use crate::gpu::Gpu;
use ash::vk;
use std::sync::Arc;

/// Milliseconds of GPU time per pass of the last rendered frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PassTimings {
    /// Dynamic-caster shadow map.
    pub shadow_ms: f64,
    /// G-buffer rasterization.
    pub gbuffer_ms: f64,
    /// Lighting and layer output.
    pub resolve_ms: f64,
}

/// The pass boundaries a frame writes a timestamp at, in order.
#[derive(Clone, Copy)]
pub(crate) enum Mark {
    Start = 0,
    ShadowDone = 1,
    GBufferDone = 2,
    ResolveDone = 3,
}

const MARKS: u32 = 4;

pub(crate) struct PassTimer {
    pool: vk::QueryPool,
    period_ns: f64,
    gpu: Arc<Gpu>,
}

impl PassTimer {
    /// `None` on devices whose queue cannot write timestamps.
    pub fn new(gpu: &Arc<Gpu>) -> Result<Option<Self>> {
        let Some(period_ns) = gpu.timestamp_period_ns else {
            return Ok(None);
        };
        let info = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::TIMESTAMP)
            .query_count(MARKS);
        // SAFETY: valid device and create info.
        let pool = unsafe { gpu.device.create_query_pool(&info, None) }.vk("vkCreateQueryPool")?;
        Ok(Some(Self {
            pool,
            period_ns: f64::from(period_ns),
            gpu: gpu.clone(),
        }))
    }

    pub fn reset(&self, command_buffer: vk::CommandBuffer) {
        // SAFETY: recording, outside any render pass.
        unsafe {
            self.gpu
                .device
                .cmd_reset_query_pool(command_buffer, self.pool, 0, MARKS)
        };
    }

    /// Writes the timestamp once all earlier commands have finished.
    pub fn mark(&self, command_buffer: vk::CommandBuffer, mark: Mark) {
        // SAFETY: recording; the query was reset earlier in this command buffer.
        unsafe {
            self.gpu.device.cmd_write_timestamp(
                command_buffer,
                vk::PipelineStageFlags::BOTTOM_OF_PIPE,
                self.pool,
                mark as u32,
            )
        };
    }

    /// Reads the marks of the frame just waited for.
    pub fn read(&self) -> Result<PassTimings> {
        let mut ticks = [0u64; MARKS as usize];
        // SAFETY: the submission that wrote all marks has completed.
        unsafe {
            self.gpu
                .device
                .get_query_pool_results(self.pool, 0, &mut ticks, vk::QueryResultFlags::TYPE_64)
                .vk("vkGetQueryPoolResults")?;
        }
        let ms = |from: Mark, to: Mark| {
            ticks[to as usize].wrapping_sub(ticks[from as usize]) as f64 * self.period_ns * 1e-6
        };
        Ok(PassTimings {
            shadow_ms: ms(Mark::Start, Mark::ShadowDone),
            gbuffer_ms: ms(Mark::ShadowDone, Mark::GBufferDone),
            resolve_ms: ms(Mark::GBufferDone, Mark::ResolveDone),
        })
    }
}

impl Drop for PassTimer {
    fn drop(&mut self) {
        // SAFETY: the renderer waits for the GPU before dropping its parts.
        unsafe { self.gpu.device.destroy_query_pool(self.pool, None) };
    }
}
