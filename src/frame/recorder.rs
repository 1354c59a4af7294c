//! Records one region's passes (a submit or an extrapolation) into the engine's command buffer,
//! with a timestamp pair around each stage.

use ash::vk;

use crate::abi::PatchexStage;
use crate::vk::frame_ring::FrameRing;

/// Timestamps around each stage of one region, and the list of stages that ran.
pub struct TimedRegion<'a> {
    ring: &'a FrameRing,
    device: &'a ash::Device,
    cmd: vk::CommandBuffer,
    slot: usize,
    region: usize,
    pub stages: Vec<u32>,
}

impl<'a> TimedRegion<'a> {
    pub fn begin(
        ring: &'a FrameRing,
        device: &'a ash::Device,
        cmd: vk::CommandBuffer,
        slot: usize,
        region: usize,
    ) -> Self {
        if let Some(timer) = &ring.timer {
            let (first, count) = ring.region_queries(slot, region);
            timer.reset(device, cmd, first, count);
        }
        Self {
            ring,
            device,
            cmd,
            slot,
            region,
            stages: Vec::new(),
        }
    }

    pub fn stage(&mut self, stage: PatchexStage, record: impl FnOnce()) {
        let query = self.ring.query(self.slot, self.region, stage);
        if let Some(timer) = &self.ring.timer {
            timer.write(self.device, self.cmd, query, false);
        }
        record();
        if let Some(timer) = &self.ring.timer {
            timer.write(self.device, self.cmd, query, true);
        }
        self.stages.push(stage);
    }
}
