//! The frame ring's two buffers: the counters the passes write in device-local memory, and the
//! host-visible copy the host reads once the engine's fence has signalled.
//!
//! The passes' atomics, uniform blocks, hole lists and indirect arguments stay in device memory:
//! on a discrete GPU, host-visible memory sits across the bus, where every atomic of every
//! workgroup would pay a round trip. Each call ends with one copy of its counters to the host.

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme, Allocator};
use gpu_allocator::MemoryLocation;

use crate::error::{bail, Error, Result};
use crate::vk::device::Gpu;

/// What a [`Buffer`] is for, which decides its memory and usage.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum BufferRole {
    /// Written and read by the passes: storage, uniform blocks, indirect arguments, fills.
    Counters,
    /// A copy of the counters the host reads.
    Readback,
}

pub struct Buffer {
    pub buffer: vk::Buffer,
    allocation: Option<Allocation>,
}

impl Buffer {
    pub fn new(
        gpu: &Gpu,
        allocator: &mut Allocator,
        name: &str,
        size: u64,
        role: BufferRole,
    ) -> Result<Self> {
        let device = &gpu.device;
        let (usage, location) = match role {
            BufferRole::Counters => (
                vk::BufferUsageFlags::STORAGE_BUFFER
                    | vk::BufferUsageFlags::UNIFORM_BUFFER
                    | vk::BufferUsageFlags::TRANSFER_SRC
                    | vk::BufferUsageFlags::TRANSFER_DST
                    | vk::BufferUsageFlags::INDIRECT_BUFFER,
                MemoryLocation::GpuOnly,
            ),
            BufferRole::Readback => (vk::BufferUsageFlags::TRANSFER_DST, MemoryLocation::GpuToCpu),
        };
        let info = vk::BufferCreateInfo::default()
            .size(size)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        let during = |error: Error| error.during(format_args!("creating the {name} buffer"));
        // SAFETY: valid device; handles made here are destroyed on every error path.
        unsafe {
            let buffer = device
                .create_buffer(&info, None)
                .map_err(|e| during(e.into()))?;
            let allocation = match allocator.allocate(&AllocationCreateDesc {
                name,
                requirements: device.get_buffer_memory_requirements(buffer),
                location,
                linear: true,
                allocation_scheme: AllocationScheme::GpuAllocatorManaged,
            }) {
                Ok(allocation) => allocation,
                Err(error) => {
                    device.destroy_buffer(buffer, None);
                    return Err(during(error.into()));
                }
            };
            let mut made = Self {
                buffer,
                allocation: Some(allocation),
            };
            let allocation = made.allocation.as_ref().unwrap();
            if role == BufferRole::Readback && allocation.mapped_ptr().is_none() {
                made.destroy(gpu, allocator);
                bail!(
                    ErrorMissingDeviceFeature,
                    "{name}: no host-visible mappable memory"
                );
            }
            if let Err(error) =
                device.bind_buffer_memory(buffer, allocation.memory(), allocation.offset())
            {
                made.destroy(gpu, allocator);
                return Err(during(error.into()));
            }
            Ok(made)
        }
    }

    /// Reads a `u32` the GPU copied to `offset` bytes of a readback buffer.
    pub fn read_u32(&self, offset: u64) -> u32 {
        let bytes = self
            .allocation
            .as_ref()
            .and_then(|a| a.mapped_slice())
            .expect("readback buffers are mapped at creation");
        let at = offset as usize;
        u32::from_ne_bytes(bytes[at..at + 4].try_into().unwrap())
    }

    pub fn size_bytes(&self) -> u64 {
        self.allocation.as_ref().map_or(0, |a| a.size())
    }

    pub fn destroy(&mut self, gpu: &Gpu, allocator: &mut Allocator) {
        // SAFETY: no pending GPU work uses the buffer (destroy contract).
        unsafe { gpu.device.destroy_buffer(self.buffer, None) };
        if let Some(allocation) = self.allocation.take() {
            let _ = allocator.free(allocation);
        }
    }
}

/// Where a pass's counters live in the frame ring's counter buffer.
#[derive(Clone, Copy)]
pub struct CounterRange {
    pub buffer: vk::Buffer,
    pub offset: u64,
    pub range: u64,
}
