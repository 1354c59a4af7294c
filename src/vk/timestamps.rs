//! Per-stage GPU time from timestamp queries: two queries (begin, end) per stage.

use ash::vk;

use crate::error::Result;
use crate::vk::device::Gpu;

pub struct StageTimer {
    pool: vk::QueryPool,
    period_ns: f64,
    valid_mask: u64,
}

impl StageTimer {
    /// `None` when the queue family writes no timestamps; stage times then read as zero.
    pub fn new(gpu: &Gpu, query_count: u32) -> Result<Option<Self>> {
        let Some(period_ns) = gpu.timestamp_period_ns else {
            return Ok(None);
        };
        let info = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::TIMESTAMP)
            .query_count(query_count);
        // SAFETY: valid device.
        let pool = unsafe { gpu.device.create_query_pool(&info, None)? };
        Ok(Some(Self {
            pool,
            period_ns,
            valid_mask: gpu.timestamp_valid_mask,
        }))
    }

    pub fn reset(&self, device: &ash::Device, cmd: vk::CommandBuffer, first: u32, count: u32) {
        // SAFETY: cmd is recording, outside a render pass.
        unsafe { device.cmd_reset_query_pool(cmd, self.pool, first, count) };
    }

    /// Marks the start (`end == false`) or end of the stage whose queries start at `first`.
    /// Both are written once every earlier command has finished: a start written at the top of
    /// the pipe lands while the previous stage still runs (a GPU overlaps them up to the next
    /// barrier), which would count that stage's tail twice. So a stage's time is what it adds to
    /// the call, and the stages' times sum to the call's.
    pub fn write(&self, device: &ash::Device, cmd: vk::CommandBuffer, first: u32, end: bool) {
        // SAFETY: the query was reset earlier in this command buffer.
        unsafe {
            device.cmd_write_timestamp(
                cmd,
                vk::PipelineStageFlags::BOTTOM_OF_PIPE,
                self.pool,
                first + end as u32,
            )
        };
    }

    /// Milliseconds between the two queries at `first`, or `None` while they are unavailable.
    pub fn read_ms(&self, device: &ash::Device, first: u32) -> Result<Option<f32>> {
        // (value, availability) pairs.
        let mut data = [[0u64; 2]; 2];
        // SAFETY: the queries were reset and written by a recorded command buffer.
        let result = unsafe {
            device.get_query_pool_results(
                self.pool,
                first,
                &mut data,
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WITH_AVAILABILITY,
            )
        };
        match result {
            Ok(()) | Err(vk::Result::NOT_READY) => {}
            Err(error) => return Err(error.into()),
        }
        if data[0][1] == 0 || data[1][1] == 0 {
            return Ok(None);
        }
        let ticks = (data[1][0] & self.valid_mask).wrapping_sub(data[0][0] & self.valid_mask)
            & self.valid_mask;
        Ok(Some((ticks as f64 * self.period_ns * 1e-6) as f32))
    }

    pub fn destroy(&mut self, device: &ash::Device) {
        // SAFETY: no pending work uses the pool (destroy contract).
        unsafe { device.destroy_query_pool(self.pool, None) };
    }
}
