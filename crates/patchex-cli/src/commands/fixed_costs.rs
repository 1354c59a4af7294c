//! What a dispatch and a barrier cost on the device however little they do: the fixed costs the
//! bench's bound adds per command (`costs::SECONDS_PER_DISPATCH`, `SECONDS_PER_BARRIER`),
//! measured on the device the bench runs on.
//!
//! One command buffer, timed with timestamp queries:
//! 1. `CHAIN` one-workgroup dispatches, each behind a barrier on the one before: each waits for
//!    the last to finish, as a pass waits for the pass whose output it reads;
//! 2. `CHAIN` such dispatches with no barrier between them, free to overlap.
//!
//! The second section's time per dispatch is what the front end pays for one; the first's, less
//! the second's, what a barrier adds. Every dispatch adds one to its own counter, and the counts
//! are checked after each run, so a driver that skipped work would fail rather than measure
//! nothing.

use std::time::{Duration, Instant};

use ash::vk;
use patchex::vk::pipeline::create_compute_pipeline;
use patchex_harness::Engine;

/// Dispatches in each section: enough that the time per dispatch dwarfs a timestamp's tick.
pub const CHAIN: u32 = 256;
/// Measured runs after the warm-up; the median of each section is reported.
pub const RUNS: usize = 5;

/// Invocation 0 of the one workgroup adds one to the counter bound at this dispatch's offset.
const SHADER: &str = "
@group(0) @binding(0) var<storage, read_write> count: atomic<u32>;

@compute @workgroup_size(64)
fn main(@builtin(local_invocation_index) lane: u32) {
    if lane == 0u {
        atomicAdd(&count, 1u);
    }
}
";

/// Microseconds, per command, on the measured device.
#[derive(Clone, Copy, Debug)]
pub struct FixedCosts {
    /// One dispatch among independent dispatches.
    pub dispatch_us: f64,
    /// What a barrier on the dispatch before adds to a dispatch; where that is next to nothing,
    /// the noise can make it read below zero.
    pub barrier_us: f64,
}

/// Measures on `engine`'s device, after repeating the work back to back for `warm_up` so that
/// the GPU runs at its working clock.
pub fn measure(engine: &Engine, warm_up: Duration) -> Result<FixedCosts, String> {
    let probe = Probe::new(engine)?;
    let started = Instant::now();
    while started.elapsed() < warm_up {
        engine.run_repeated(16, |cmd| probe.record(cmd));
    }
    let mut chained = Vec::with_capacity(RUNS);
    let mut free = Vec::with_capacity(RUNS);
    for _ in 0..RUNS {
        engine.run(|cmd| probe.record(cmd));
        probe.check_counts()?;
        let [start, after_chain, after_free] = probe.read_timestamps()?;
        chained.push(after_chain - start);
        free.push(after_free - after_chain);
    }
    let per_dispatch_us = |mut seconds: Vec<f64>| {
        seconds.sort_by(f64::total_cmp);
        1e6 * seconds[RUNS / 2] / f64::from(CHAIN)
    };
    let (chained_us, dispatch_us) = (per_dispatch_us(chained), per_dispatch_us(free));
    Ok(FixedCosts {
        dispatch_us,
        barrier_us: chained_us - dispatch_us,
    })
}

/// The probe's pipeline, its counters and its queries, destroyed on drop.
struct Probe<'a> {
    engine: &'a Engine,
    /// Bytes between two dispatches' counters: the device's storage-buffer offset alignment.
    stride: u32,
    buffer: vk::Buffer,
    memory: vk::DeviceMemory,
    counts: *const u32,
    set_layout: vk::DescriptorSetLayout,
    pool: vk::DescriptorPool,
    set: vk::DescriptorSet,
    layout: vk::PipelineLayout,
    pipeline: vk::Pipeline,
    queries: vk::QueryPool,
    period_seconds: f64,
    valid_mask: u64,
}

impl<'a> Probe<'a> {
    fn new(engine: &'a Engine) -> Result<Self, String> {
        let instance = &engine.instance;
        // SAFETY: queries on the engine's live physical device.
        let (properties, family) = unsafe {
            (
                instance.get_physical_device_properties(engine.physical_device),
                instance.get_physical_device_queue_family_properties(engine.physical_device)
                    [engine.queue_family_index as usize],
            )
        };
        if family.timestamp_valid_bits == 0 || properties.limits.timestamp_period <= 0.0 {
            return Err(format!(
                "{}: its queue writes no timestamps",
                engine.device_name
            ));
        }
        let stride = (properties.limits.min_storage_buffer_offset_alignment as u32).max(4);
        let spirv = patchex::network::codegen::compile(SHADER, "the fixed-cost probe")
            .map_err(|e| e.to_string())?;
        let mut probe = Self {
            engine,
            stride,
            buffer: vk::Buffer::null(),
            memory: vk::DeviceMemory::null(),
            counts: std::ptr::null(),
            set_layout: vk::DescriptorSetLayout::null(),
            pool: vk::DescriptorPool::null(),
            set: vk::DescriptorSet::null(),
            layout: vk::PipelineLayout::null(),
            pipeline: vk::Pipeline::null(),
            queries: vk::QueryPool::null(),
            period_seconds: f64::from(properties.limits.timestamp_period) * 1e-9,
            valid_mask: match family.timestamp_valid_bits {
                64.. => u64::MAX,
                bits => (1u64 << bits) - 1,
            },
        };
        // SAFETY: objects on the engine's live device; what was made before a failure is
        // destroyed by Drop, which skips null handles.
        unsafe { probe.build(&spirv) }.map_err(|e| format!("the fixed-cost probe: {e}"))?;
        Ok(probe)
    }

    /// Counters: one for the chain, then one per free dispatch.
    fn buffer_bytes(&self) -> u64 {
        u64::from(self.stride) * u64::from(CHAIN + 1)
    }

    /// # Safety
    /// `spirv` is the probe's compiled shader; called once, on a probe of null handles.
    unsafe fn build(&mut self, spirv: &[u32]) -> Result<(), vk::Result> {
        let device = &self.engine.device;
        self.buffer = device.create_buffer(
            &vk::BufferCreateInfo::default()
                .size(self.buffer_bytes())
                .usage(vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST),
            None,
        )?;
        self.memory = self.engine.allocate(
            device.get_buffer_memory_requirements(self.buffer),
            vk::MemoryPropertyFlags::HOST_VISIBLE | vk::MemoryPropertyFlags::HOST_COHERENT,
        );
        device.bind_buffer_memory(self.buffer, self.memory, 0)?;
        self.counts = device
            .map_memory(self.memory, 0, vk::WHOLE_SIZE, vk::MemoryMapFlags::empty())?
            .cast();

        // A dynamic offset per dispatch: each free dispatch writes a counter of its own, so
        // they share no memory and need no barrier.
        let binding = vk::DescriptorSetLayoutBinding::default()
            .binding(0)
            .descriptor_type(vk::DescriptorType::STORAGE_BUFFER_DYNAMIC)
            .descriptor_count(1)
            .stage_flags(vk::ShaderStageFlags::COMPUTE);
        self.set_layout = device.create_descriptor_set_layout(
            &vk::DescriptorSetLayoutCreateInfo::default().bindings(std::slice::from_ref(&binding)),
            None,
        )?;
        let size = vk::DescriptorPoolSize {
            ty: vk::DescriptorType::STORAGE_BUFFER_DYNAMIC,
            descriptor_count: 1,
        };
        self.pool = device.create_descriptor_pool(
            &vk::DescriptorPoolCreateInfo::default()
                .max_sets(1)
                .pool_sizes(std::slice::from_ref(&size)),
            None,
        )?;
        let layouts = [self.set_layout];
        self.set = device.allocate_descriptor_sets(
            &vk::DescriptorSetAllocateInfo::default()
                .descriptor_pool(self.pool)
                .set_layouts(&layouts),
        )?[0];
        let range = vk::DescriptorBufferInfo {
            buffer: self.buffer,
            offset: 0,
            range: 4,
        };
        device.update_descriptor_sets(
            &[vk::WriteDescriptorSet::default()
                .dst_set(self.set)
                .dst_binding(0)
                .descriptor_type(vk::DescriptorType::STORAGE_BUFFER_DYNAMIC)
                .buffer_info(std::slice::from_ref(&range))],
            &[],
        );
        self.layout = device.create_pipeline_layout(
            &vk::PipelineLayoutCreateInfo::default().set_layouts(&layouts),
            None,
        )?;

        self.pipeline = create_compute_pipeline(device, self.layout, spirv)?;

        self.queries = device.create_query_pool(
            &vk::QueryPoolCreateInfo::default()
                .query_type(vk::QueryType::TIMESTAMP)
                .query_count(3),
            None,
        )?;
        Ok(())
    }

    /// Zeroes the counters, then the two timed sections.
    fn record(&self, cmd: vk::CommandBuffer) {
        let device = &self.engine.device;
        let compute = (
            vk::PipelineStageFlags::COMPUTE_SHADER,
            vk::AccessFlags::SHADER_READ | vk::AccessFlags::SHADER_WRITE,
        );
        let transfer = (
            vk::PipelineStageFlags::TRANSFER,
            vk::AccessFlags::TRANSFER_WRITE,
        );
        let after_all = vk::PipelineStageFlags::BOTTOM_OF_PIPE;
        let barrier = |from: (vk::PipelineStageFlags, vk::AccessFlags),
                       to: (vk::PipelineStageFlags, vk::AccessFlags)| {
            let memory = vk::MemoryBarrier::default()
                .src_access_mask(from.1)
                .dst_access_mask(to.1);
            // SAFETY: `cmd` is recording.
            unsafe {
                device.cmd_pipeline_barrier(
                    cmd,
                    from.0,
                    to.0,
                    vk::DependencyFlags::empty(),
                    &[memory],
                    &[],
                    &[],
                )
            };
        };
        let dispatch = |counter: u32| {
            // SAFETY: `cmd` is recording with the probe's pipeline bound; the offset stays
            // within the buffer.
            unsafe {
                device.cmd_bind_descriptor_sets(
                    cmd,
                    vk::PipelineBindPoint::COMPUTE,
                    self.layout,
                    0,
                    &[self.set],
                    &[counter * self.stride],
                );
                device.cmd_dispatch(cmd, 1, 1, 1);
            }
        };
        // SAFETY: `cmd` is recording; every object is the probe's and alive.
        unsafe {
            device.cmd_reset_query_pool(cmd, self.queries, 0, 3);
            // Repeated back to back, a copy's zeroing follows the copy before's dispatches.
            barrier(compute, transfer);
            device.cmd_fill_buffer(cmd, self.buffer, 0, vk::WHOLE_SIZE, 0);
            barrier(transfer, compute);
            device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, self.pipeline);
            device.cmd_write_timestamp(cmd, after_all, self.queries, 0);
            for index in 0..CHAIN {
                if index > 0 {
                    barrier(compute, compute);
                }
                dispatch(0);
            }
            device.cmd_write_timestamp(cmd, after_all, self.queries, 1);
            // The free section starts once the chain is done, so the two do not overlap.
            barrier(compute, compute);
            for index in 1..=CHAIN {
                dispatch(index);
            }
            device.cmd_write_timestamp(cmd, after_all, self.queries, 2);
        }
    }

    /// The chain's counter holds `CHAIN` and every free dispatch's counter one.
    fn check_counts(&self) -> Result<(), String> {
        let count = |index: u32| {
            // SAFETY: the memory is mapped, coherent, and the GPU is done with it (the run
            // waited); the offset is within the buffer.
            unsafe {
                self.counts
                    .byte_add((index * self.stride) as usize)
                    .read_volatile()
            }
        };
        let chain = count(0);
        let free_wrong = (1..=CHAIN).filter(|&index| count(index) != 1).count();
        if chain != CHAIN || free_wrong > 0 {
            return Err(format!(
                "{}: the fixed-cost probe counted {chain} of {CHAIN} chained dispatches, and \
                 {free_wrong} free dispatches' counters are not 1",
                self.engine.device_name
            ));
        }
        Ok(())
    }

    /// The three timestamps, in seconds from the first.
    fn read_timestamps(&self) -> Result<[f64; 3], String> {
        let mut ticks = [0u64; 3];
        // SAFETY: the run that wrote the queries has completed.
        unsafe {
            self.engine.device.get_query_pool_results(
                self.queries,
                0,
                &mut ticks,
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
            )
        }
        .map_err(|e| format!("vkGetQueryPoolResults: {e}"))?;
        let since_start = |tick: u64| {
            (tick.wrapping_sub(ticks[0]) & self.valid_mask) as f64 * self.period_seconds
        };
        Ok([0.0, since_start(ticks[1]), since_start(ticks[2])])
    }
}

impl Drop for Probe<'_> {
    fn drop(&mut self) {
        let device = &self.engine.device;
        // SAFETY: every run waited for the GPU; null handles are skipped by Vulkan.
        unsafe {
            device.destroy_query_pool(self.queries, None);
            device.destroy_pipeline(self.pipeline, None);
            device.destroy_pipeline_layout(self.layout, None);
            device.destroy_descriptor_pool(self.pool, None);
            device.destroy_descriptor_set_layout(self.set_layout, None);
            device.destroy_buffer(self.buffer, None);
            if !self.counts.is_null() {
                device.unmap_memory(self.memory);
            }
            device.free_memory(self.memory, None);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use patchex_harness::EngineOptions;

    /// On the test device, under validation with synchronization validation: every dispatch
    /// ran (the counts are checked inside), the times are real, and nothing was reported.
    #[test]
    fn the_probe_counts_every_dispatch_and_times_both_sections() {
        let engine = Engine::new(&EngineOptions::default()).expect("a Vulkan device");
        // A warm-up long enough for one repeated submission, which validation checks too.
        let costs = measure(&engine, Duration::from_millis(1)).expect("the probe runs");
        assert!(costs.dispatch_us > 0.0, "{costs:?}");
        assert!(costs.barrier_us.is_finite(), "{costs:?}");
        engine.assert_validation_clean();
    }
}
