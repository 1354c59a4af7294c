//! Records passes into the engine's command buffer and places every barrier between them.
//!
//! A pass does not order itself. What it reads and writes comes from its descriptor writes and
//! the shader's reflection (a binding the shader may store through is a write; see build.rs).
//! Before each command the recorder compares what it touches with what the commands since the
//! last barrier touched, and places one barrier where they conflict: a read or write after a
//! write, or a write after a read. Commands that do not conflict run side by side, as the
//! method's sub-tasks do.

use ash::vk;

use crate::abi::PatchexStage;
use crate::passes::stage_position;
use crate::shaders::PushConstants;
use crate::vk::access::{
    self, Access, Commands, GpuShare, Resource, SharedTraffic, StageRecord, Traffic,
};
use crate::vk::barriers::{self, EngineImageAccess};
use crate::vk::buffer::CounterRange;
use crate::vk::frame_ring::FrameRing;
use crate::vk::image::{ImportedImage, OwnedImage, COLOR_SUBRESOURCE};
use crate::vk::pipeline::{ComputePipeline, DescriptorWrites};

/// A pass's pipeline and the descriptor set it uses in this region.
#[derive(Clone, Copy)]
pub struct Pass<'a> {
    pub pipeline: &'a ComputePipeline,
    pub set: vk::DescriptorSet,
}

/// A pass with its descriptor set written: what it reads and writes is known.
pub struct Bound<'a> {
    pass: Pass<'a>,
    accesses: Vec<Access>,
    /// The bytes one dispatch moves through each binding.
    per_binding: Vec<(u32, Traffic)>,
}

impl Bound<'_> {
    /// The bytes one dispatch moves through `bindings`, or through all of them.
    fn traffic(&self, bindings: Option<&[u32]>) -> Traffic {
        let mut total = Traffic::default();
        for (binding, traffic) in &self.per_binding {
            if bindings.is_none_or(|b| b.contains(binding)) {
                total += *traffic;
            }
        }
        total
    }
}

/// Every stage the barriers make earlier work visible to: the passes, the transfers (clears,
/// fills, copies) and the indirect dispatches' arguments.
const LATER_STAGES: vk::PipelineStageFlags = vk::PipelineStageFlags::from_raw(
    vk::PipelineStageFlags::COMPUTE_SHADER.as_raw()
        | vk::PipelineStageFlags::TRANSFER.as_raw()
        | vk::PipelineStageFlags::DRAW_INDIRECT.as_raw(),
);

/// Timestamps around each stage of one region of the frame ring.
struct StageTimes<'a> {
    ring: &'a FrameRing,
    slot: usize,
    region: usize,
}

/// The commands of one call (a submit or an extrapolation) in the engine's command buffer.
pub struct Recorder<'a> {
    device: &'a ash::Device,
    cmd: vk::CommandBuffer,
    /// Accesses since the last barrier.
    pending: Vec<Access>,
    times: Option<StageTimes<'a>>,
    stages: Vec<StageRecord>,
    /// What the stage being recorded has moved and recorded so far.
    traffic: Traffic,
    commands: Commands,
    shared: Vec<SharedTraffic>,
    /// A stage whose commands are left out (`context::TEST_FAULT_VARIABLE`).
    skipped: Option<PatchexStage>,
}

impl<'a> Recorder<'a> {
    /// Starts recording into `cmd`, after whatever was recorded there before: the first command
    /// that touches anything waits for it, unless `acquire`'s barrier has.
    pub fn new(device: &'a ash::Device, cmd: vk::CommandBuffer) -> Self {
        Self {
            device,
            cmd,
            pending: vec![Access {
                resource: Resource::Earlier,
                write: true,
                stage: vk::PipelineStageFlags::COMPUTE_SHADER | vk::PipelineStageFlags::TRANSFER,
            }],
            times: None,
            stages: Vec::new(),
            traffic: Traffic::default(),
            commands: Commands::default(),
            shared: Vec::new(),
            skipped: None,
        }
    }

    /// Leaves `stage`'s commands out of the call, as a broken pass would get it wrong.
    pub fn skipping(mut self, stage: Option<PatchexStage>) -> Self {
        self.skipped = stage;
        self
    }

    /// Times each `stage` into `region` of `slot` in the ring's queries (when the device has
    /// timestamps), resetting them first.
    pub fn timed(mut self, ring: &'a FrameRing, slot: usize, region: usize) -> Self {
        if let Some(timer) = &ring.timer {
            let (first, count) = ring.region_queries(slot, region);
            timer.reset(self.device, self.cmd, first, count);
        }
        self.times = Some(StageTimes { ring, slot, region });
        self
    }

    /// Moves plugin images no command buffer has used yet to GENERAL.
    pub fn initialize(&mut self, images: &mut [&mut OwnedImage]) {
        barriers::initialize_owned(self.device, self.cmd, images);
    }

    /// Writes the call's `counters` (`contents`, or zeros without), then waits for the engine's
    /// work on its images and moves them to their pass layouts. That one barrier also orders the
    /// counters' write, and everything recorded before, ahead of the call's passes, which then
    /// need no barrier of their own for them. (The release that ended the call before made its
    /// writes available, so the counters' write need not wait for them.)
    pub fn acquire(
        &mut self,
        engine: &EngineImageAccess,
        counters: &CounterRange,
        contents: Option<&[u8]>,
    ) {
        self.traffic.bytes_written += counters.range;
        let CounterRange {
            buffer,
            offset,
            range,
        } = *counters;
        // SAFETY: cmd is recording; the range lies inside the buffer, which has TRANSFER_DST;
        // vkCmdUpdateBuffer's bytes fill the range, a multiple of 4 under 65536
        // (`frame::counters::REGION_BYTES`).
        unsafe {
            match contents {
                Some(bytes) => {
                    debug_assert_eq!(bytes.len() as u64, range);
                    self.device
                        .cmd_update_buffer(self.cmd, buffer, offset, bytes)
                }
                None => self
                    .device
                    .cmd_fill_buffer(self.cmd, buffer, offset, range, 0),
            }
        }
        engine.acquire(self.device, self.cmd, LATER_STAGES);
        self.pending.clear();
        self.commands.barriers += 1;
    }

    /// Records the commands of `stage`, with a timestamp before and after. Stages come in the
    /// order of `passes::STAGES`, each once a call.
    pub fn stage(&mut self, stage: PatchexStage, record: impl FnOnce(&mut Self)) {
        if let Some(last) = self.stages.last() {
            assert!(
                stage_position(last.stage) < stage_position(stage),
                "stage {stage} recorded after stage {}, against passes::STAGES",
                last.stage
            );
        }
        let query = self.times.as_ref().and_then(|t| {
            Some((
                t.ring.timer.as_ref()?,
                t.ring.query(t.slot, t.region, stage),
            ))
        });
        if let Some((timer, query)) = query {
            timer.write(self.device, self.cmd, query, false);
        }
        if self.skipped != Some(stage) {
            record(self);
        }
        if let Some((timer, query)) = query {
            timer.write(self.device, self.cmd, query, true);
        }
        self.stages.push(StageRecord {
            stage,
            traffic: std::mem::take(&mut self.traffic),
            commands: std::mem::take(&mut self.commands),
            shared: std::mem::take(&mut self.shared),
        });
    }

    /// Writes `pass`'s descriptor set with what `writes` binds; the pass's accesses are the
    /// bindings' resources.
    pub fn bind<'p>(
        &mut self,
        pass: Pass<'p>,
        writes: impl FnOnce(DescriptorWrites<'p>) -> DescriptorWrites<'p>,
    ) -> Bound<'p> {
        let writes = writes(DescriptorWrites::new(pass.pipeline));
        let accesses = writes.accesses();
        let per_binding = writes.traffic();
        writes.update(self.device, pass.set);
        Bound {
            pass,
            accesses,
            per_binding,
        }
    }

    /// One dispatch of `bound` covering `extent`.
    pub fn dispatch<P: PushConstants>(&mut self, bound: &Bound, params: &P, extent: vk::Extent2D) {
        self.record_dispatch(bound, bound.traffic(None), params, extent);
    }

    /// One dispatch of `bound` over one level of pyramid atlases (`shadow_flow::pyramid`). Of
    /// the atlases of `atlas` texels bound at `atlases` it moves only the level, so they count
    /// for the level's share; besides them it reads `other_bytes`, and none of its other
    /// bindings.
    pub fn dispatch_level<P: PushConstants>(
        &mut self,
        bound: &Bound,
        params: &P,
        (level, atlas): (vk::Extent2D, vk::Extent2D),
        atlases: &[u32],
        other_bytes: u64,
    ) {
        let texels = |e: vk::Extent2D| e.width as u64 * e.height as u64;
        let share = |bytes: u64| bytes * texels(level) / texels(atlas).max(1);
        let moved = bound.traffic(Some(atlases));
        let traffic = Traffic {
            bytes_read: share(moved.bytes_read) + other_bytes,
            bytes_written: share(moved.bytes_written),
            operations: 0,
        };
        self.record_dispatch(bound, traffic, params, level);
    }

    /// A dispatch after what it must wait for, counting `traffic` and its arithmetic.
    fn record_dispatch<P: PushConstants>(
        &mut self,
        bound: &Bound,
        traffic: Traffic,
        params: &P,
        extent: vk::Extent2D,
    ) {
        self.order(&bound.accesses);
        self.traffic += traffic;
        let Pass { pipeline, set } = bound.pass;
        let [group_x, group_y, _] = pipeline.shader.workgroup_size;
        let invocations = extent.width.next_multiple_of(group_x) as u64
            * extent.height.next_multiple_of(group_y) as u64;
        self.traffic.operations += invocations * pipeline.shader.arithmetic;
        self.commands.dispatches += 1;
        pipeline.dispatch(self.device, self.cmd, set, params, extent);
    }

    /// A dispatch of `bound` with the workgroup counts the GPU wrote into `args` (a
    /// VkDispatchIndirectCommand).
    pub fn dispatch_indirect<P: PushConstants>(
        &mut self,
        bound: &Bound,
        params: &P,
        args: &CounterRange,
    ) {
        self.record_indirect(bound, params, args);
        self.traffic += bound.traffic(None);
    }

    /// `dispatch_indirect` over a list of `capacity` entries whose length the GPU wrote into
    /// `count` (in the frame ring's counters), one invocation per entry: the bindings' traffic
    /// is reported for that length, the indirect arguments' whole.
    pub fn dispatch_listed<P: PushConstants>(
        &mut self,
        bound: &Bound,
        params: &P,
        args: &CounterRange,
        count: &CounterRange,
        capacity: u64,
    ) {
        self.record_indirect(bound, params, args);
        self.shared.push(SharedTraffic {
            traffic: Traffic {
                operations: capacity * bound.pass.pipeline.shader.arithmetic,
                ..bound.traffic(None)
            },
            share: GpuShare::Entries {
                count: count.offset,
                capacity,
            },
        });
    }

    /// `dispatch_indirect` over a patch the GPU planned: each group of bindings in `shares`
    /// counts the share of its resources that the patch spans (`GpuShare`), read back with the
    /// frame's counters; the other bindings count whole.
    pub fn dispatch_over_patch<P: PushConstants>(
        &mut self,
        bound: &Bound,
        params: &P,
        args: &CounterRange,
        shares: &[(&[u32], GpuShare)],
    ) {
        self.record_indirect(bound, params, args);
        self.count_shared(bound, shares);
    }

    /// `dispatch` covering `extent`, whose bindings in `shares` it reads only over patches the
    /// GPU planned: as `dispatch_over_patch` counts them.
    pub fn dispatch_sharing<P: PushConstants>(
        &mut self,
        bound: &Bound,
        params: &P,
        extent: vk::Extent2D,
        shares: &[(&[u32], GpuShare)],
    ) {
        self.record_dispatch(bound, Traffic::default(), params, extent);
        self.count_shared(bound, shares);
    }

    /// Counts each group of bindings in `shares` for its share, the other bindings whole.
    fn count_shared(&mut self, bound: &Bound, shares: &[(&[u32], GpuShare)]) {
        let shared: Vec<u32> = shares.iter().flat_map(|(b, _)| b.iter().copied()).collect();
        for (binding, traffic) in &bound.per_binding {
            if !shared.contains(binding) {
                self.traffic += *traffic;
            }
        }
        for (bindings, share) in shares {
            self.shared.push(SharedTraffic {
                traffic: bound.traffic(Some(bindings)),
                share: *share,
            });
        }
    }

    /// An indirect dispatch after what it must wait for, counting the arguments it reads (its
    /// bindings are the caller's to count).
    fn record_indirect<P: PushConstants>(
        &mut self,
        bound: &Bound,
        params: &P,
        args: &CounterRange,
    ) {
        let mut accesses = bound.accesses.clone();
        accesses.push(Access {
            resource: Resource::range(args),
            write: false,
            stage: vk::PipelineStageFlags::DRAW_INDIRECT,
        });
        self.order(&accesses);
        self.traffic.bytes_read += args.range;
        self.commands.dispatches += 1;
        let Pass { pipeline, set } = bound.pass;
        pipeline.dispatch_indirect(self.device, self.cmd, set, params, args.buffer, args.offset);
    }

    /// Writes `bytes` (a multiple of 4 under 65536, filling `range`) into `range` in the command
    /// stream (the call's counters and uniform blocks), after whatever the GPU still does with
    /// the range; a write from the host could race it.
    pub fn update_bytes(&mut self, range: &CounterRange, bytes: &[u8]) {
        debug_assert_eq!(bytes.len() as u64, range.range);
        self.order(&[transfer_write(Resource::range(range))]);
        self.traffic.bytes_written += range.range;
        // SAFETY: cmd is recording; the range lies inside the buffer, which has TRANSFER_DST,
        // and the bytes are a multiple of 4 under 65536, as every uniform block here is.
        unsafe {
            self.device
                .cmd_update_buffer(self.cmd, range.buffer, range.offset, bytes)
        };
    }

    /// Clears a plugin image (in GENERAL, with TRANSFER_DST usage) to zero.
    pub fn clear(&mut self, image: &OwnedImage) {
        self.order(&[transfer_write(Resource::Image(image.image))]);
        self.traffic.bytes_written += image.texel_bytes();
        let zero = vk::ClearColorValue { float32: [0.0; 4] };
        // SAFETY: cmd is recording; the image is in GENERAL and has TRANSFER_DST usage.
        unsafe {
            self.device.cmd_clear_color_image(
                self.cmd,
                image.image,
                vk::ImageLayout::GENERAL,
                &zero,
                &[COLOR_SUBRESOURCE],
            );
        }
    }

    /// Copies `extent` of a plugin image a pass wrote into an engine image of the same texel
    /// size, acquired for a transfer write; the plugin image returns to GENERAL after.
    pub fn copy(&mut self, from: &OwnedImage, to: &ImportedImage, extent: vk::Extent2D) {
        // The layout change waits for the pass that wrote `from` by itself.
        self.order(&[transfer_write(Resource::Image(to.image))]);
        self.traffic.bytes_read += from.texel_bytes();
        self.traffic.bytes_written += to.bytes;
        barriers::owned_for_copy(self.device, self.cmd, from, false);
        self.commands.barriers += 1;
        let layer = vk::ImageSubresourceLayers {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            mip_level: 0,
            base_array_layer: 0,
            layer_count: 1,
        };
        let region = vk::ImageCopy {
            src_subresource: layer,
            src_offset: vk::Offset3D::default(),
            dst_subresource: layer,
            dst_offset: vk::Offset3D::default(),
            extent: vk::Extent3D {
                width: extent.width,
                height: extent.height,
                depth: 1,
            },
        };
        // SAFETY: cmd is recording; both images are live, in the layouts named, of one texel
        // size, so the copy moves bits unchanged.
        unsafe {
            self.device.cmd_copy_image(
                self.cmd,
                from.image,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                to.image,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &[region],
            );
        }
        barriers::owned_for_copy(self.device, self.cmd, from, true);
        self.commands.barriers += 1;
    }

    /// Ends the call: its `counters` are copied to the same offset of `readback`, which the
    /// host reads after the engine's fence, and the engine's images return to their layouts.
    /// Returns the stages recorded.
    pub fn finish(
        mut self,
        engine: &EngineImageAccess,
        counters: &CounterRange,
        readback: vk::Buffer,
    ) -> Vec<StageRecord> {
        self.order(&[Access {
            resource: Resource::range(counters),
            write: false,
            stage: vk::PipelineStageFlags::TRANSFER,
        }]);
        let region = vk::BufferCopy {
            src_offset: counters.offset,
            dst_offset: counters.offset,
            size: counters.range,
        };
        // SAFETY: cmd is recording; both buffers are live and hold the range, the counters with
        // TRANSFER_SRC and the readback with TRANSFER_DST usage.
        unsafe {
            self.device
                .cmd_copy_buffer(self.cmd, counters.buffer, readback, &[region])
        };
        barriers::transfer_to_host(self.device, self.cmd);
        engine.release(self.device, self.cmd);
        self.stages
    }

    /// Places a barrier before a command with `accesses` when it conflicts with a command
    /// since the last one.
    fn order(&mut self, accesses: &[Access]) {
        if access::conflict(&self.pending, accesses) {
            let mut stages = vk::PipelineStageFlags::empty();
            let mut written = vk::AccessFlags::empty();
            for earlier in self.pending.drain(..) {
                stages |= earlier.stage;
                if earlier.write {
                    written |= write_access(earlier.stage);
                }
            }
            barriers::memory(self.device, self.cmd, stages, written, LATER_STAGES);
            self.commands.barriers += 1;
        }
        self.pending.extend_from_slice(accesses);
    }
}

fn transfer_write(resource: Resource) -> Access {
    Access {
        resource,
        write: true,
        stage: vk::PipelineStageFlags::TRANSFER,
    }
}

/// The write access of commands in `stages`.
fn write_access(stages: vk::PipelineStageFlags) -> vk::AccessFlags {
    let mut access = vk::AccessFlags::empty();
    if stages.contains(vk::PipelineStageFlags::COMPUTE_SHADER) {
        access |= vk::AccessFlags::SHADER_WRITE;
    }
    if stages.contains(vk::PipelineStageFlags::TRANSFER) {
        access |= vk::AccessFlags::TRANSFER_WRITE;
    }
    access
}
