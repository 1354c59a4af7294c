//! Per-frame resources reused round-robin over the engine's frames in flight.
//!
//! Frame F uses slot F % frames_in_flight. The engine promises (API contract) that when it
//! submits frame F, the GPU has finished everything recorded for frame F - frames_in_flight, so
//! that slot's descriptor sets, queries and counters can be rewritten, and plugin images retired
//! at that frame can be destroyed.

use ash::vk;
use gpu_allocator::vulkan::Allocator;

use crate::abi::{
    PatchexResetReason, PatchexShadowHistory, PATCHEX_MAX_EXTRAPOLATIONS_PER_FRAME,
    PATCHEX_STAGE_SLOTS,
};
use crate::error::Result;
use crate::vk::access::StageRecord;
use crate::vk::buffer::{Buffer, BufferRole, CounterRange};
use crate::vk::device::Gpu;
use crate::vk::image::OwnedImage;
use crate::vk::pipeline::DescriptorPool;
use crate::vk::timestamps::StageTimer;

/// Region 0 of a slot belongs to `patchex_submit_gbuffers`, region 1 + i to extrapolation i.
pub const REGIONS_PER_SLOT: usize = 1 + PATCHEX_MAX_EXTRAPOLATIONS_PER_FRAME;
const QUERIES_PER_REGION: u32 = 2 * PATCHEX_STAGE_SLOTS as u32;

/// What was recorded into one region, to read its results back later.
#[derive(Clone, Debug, Default)]
pub struct RegionRecord {
    pub stages: Vec<StageRecord>,
    pub alpha: f32,
    /// The target was a camera cut from frame t.
    pub camera_cut: bool,
    /// The FI network ran over the whole frame (`PatchexNetworkSettings.whole_frame`).
    pub whole_frame: bool,
}

#[derive(Clone, Debug)]
pub struct FrameRecord {
    pub frame_index: u64,
    /// The context's submit count at this frame; slots and retirement go by it.
    pub serial: u64,
    pub extent: vk::Extent2D,
    pub reset_reason: PatchexResetReason,
    pub shadow_history: PatchexShadowHistory,
    pub submit: RegionRecord,
    pub extrapolations: Vec<RegionRecord>,
}

pub struct FrameSlot {
    pub record: Option<FrameRecord>,
}

pub struct FrameRing {
    /// Each region's sets in turn, slot by slot (`Pipelines::set_layouts`).
    descriptors: Option<DescriptorPool>,
    sets_per_region: usize,
    pub slots: Vec<FrameSlot>,
    pub timer: Option<StageTimer>,
    /// What the passes count and list, in device memory.
    pub counters: Buffer,
    /// Each call's counters, copied at its end for the host to read.
    pub readback: Buffer,
    /// One region's counters.
    counter_bytes: u64,
    counter_stride: u64,
    /// Images replaced by larger ones, with the frame index after which no GPU work uses them.
    retired: Vec<(u64, OwnedImage)>,
}

impl FrameRing {
    /// Each region has a set of each of `set_layouts` (`pool_sizes` counts their descriptors
    /// together) and `counter_bytes` of counters.
    pub fn new(
        gpu: &Gpu,
        allocator: &mut Allocator,
        frames_in_flight: usize,
        set_layouts: &[vk::DescriptorSetLayout],
        pool_sizes: &[vk::DescriptorPoolSize],
        counter_bytes: u64,
    ) -> Result<Self> {
        // Each region's counters start at an offset the device can bind.
        let counter_stride = counter_bytes.next_multiple_of(gpu.min_buffer_offset_alignment.max(1));
        let counters_size = counter_stride * (frames_in_flight * REGIONS_PER_SLOT) as u64;
        let counters = Buffer::new(
            gpu,
            allocator,
            "patchex frame counters",
            counters_size,
            BufferRole::Counters,
        )?;
        let readback = match Buffer::new(
            gpu,
            allocator,
            "patchex frame counters readback",
            counters_size,
            BufferRole::Readback,
        ) {
            Ok(readback) => readback,
            Err(error) => {
                let mut counters = counters;
                counters.destroy(gpu, allocator);
                return Err(error);
            }
        };
        let mut ring = Self {
            descriptors: None,
            sets_per_region: set_layouts.len(),
            slots: Vec::new(),
            timer: None,
            counters,
            readback,
            counter_bytes,
            counter_stride,
            retired: Vec::new(),
        };
        // On failure everything made so far is destroyed.
        let built = (|| -> Result<()> {
            let regions = frames_in_flight * REGIONS_PER_SLOT;
            ring.descriptors = Some(DescriptorPool::new(gpu, set_layouts, pool_sizes, regions)?);
            ring.slots = (0..frames_in_flight)
                .map(|_| FrameSlot { record: None })
                .collect();
            ring.timer = StageTimer::new(gpu, QUERIES_PER_REGION * regions as u32)?;
            Ok(())
        })();
        match built {
            Ok(()) => Ok(ring),
            Err(error) => {
                ring.destroy(gpu, allocator);
                Err(error.during("creating the frame ring's descriptor sets and queries"))
            }
        }
    }

    /// The slot of the context's `serial`th submit.
    pub fn slot_of(&self, serial: u64) -> usize {
        (serial % self.slots.len() as u64) as usize
    }

    /// Set `set` (`Pipelines::set_index`) of `region` in `slot`.
    pub fn descriptor_set(&self, slot: usize, region: usize, set: usize) -> vk::DescriptorSet {
        let descriptors = self.descriptors.as_ref().expect("made with the ring");
        descriptors.sets[(slot * REGIONS_PER_SLOT + region) * self.sets_per_region + set]
    }

    /// First query of `stage` in `region` of `slot`.
    pub fn query(&self, slot: usize, region: usize, stage: u32) -> u32 {
        ((slot * REGIONS_PER_SLOT + region) as u32) * QUERIES_PER_REGION + 2 * stage
    }

    pub fn region_queries(&self, slot: usize, region: usize) -> (u32, u32) {
        (self.query(slot, region, 0), QUERIES_PER_REGION)
    }

    /// `bytes` of counters at `offset` within the counters of `region` in `slot`.
    pub fn counter_range(
        &self,
        slot: usize,
        region: usize,
        offset: u64,
        bytes: u64,
    ) -> CounterRange {
        CounterRange {
            buffer: self.counters.buffer,
            offset: self.counter_offset(slot, region) + offset,
            range: bytes,
        }
    }

    /// All counters of `region` in `slot`, zeroed at the start of its call.
    pub fn region_counters(&self, slot: usize, region: usize) -> CounterRange {
        CounterRange {
            buffer: self.counters.buffer,
            offset: self.counter_offset(slot, region),
            range: self.counter_bytes,
        }
    }

    /// Byte offset of the counters of `region` in `slot`.
    pub fn counter_offset(&self, slot: usize, region: usize) -> u64 {
        self.counter_stride * (slot * REGIONS_PER_SLOT + region) as u64
    }

    /// Keeps `image` alive until the GPU can no longer use it: submits up to serial
    /// `last_serial_using_it` may still run, so it goes at submit `last + frames_in_flight`.
    pub fn retire(&mut self, last_serial_using_it: u64, image: OwnedImage) {
        self.retired.push((last_serial_using_it, image));
    }

    /// Destroys retired images no frame in flight can still use, at submit `serial`.
    pub fn collect(&mut self, gpu: &Gpu, allocator: &mut Allocator, serial: u64) {
        let frames_in_flight = self.slots.len() as u64;
        let (done, alive): (Vec<_>, Vec<_>) = std::mem::take(&mut self.retired)
            .into_iter()
            .partition(|(last, _)| serial >= last.saturating_add(frames_in_flight));
        self.retired = alive;
        for (_, mut image) in done {
            image.destroy(gpu, allocator);
        }
    }

    pub fn retired_bytes(&self) -> u64 {
        self.retired
            .iter()
            .map(|(_, image)| image.size_bytes())
            .sum()
    }

    pub fn destroy(&mut self, gpu: &Gpu, allocator: &mut Allocator) {
        for (_, mut image) in self.retired.drain(..) {
            image.destroy(gpu, allocator);
        }
        if let Some(timer) = &mut self.timer {
            timer.destroy(&gpu.device);
        }
        self.counters.destroy(gpu, allocator);
        self.readback.destroy(gpu, allocator);
        if let Some(mut descriptors) = self.descriptors.take() {
            descriptors.destroy(&gpu.device);
        }
    }
}
