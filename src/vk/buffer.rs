//! A host-visible buffer the GPU writes and the host reads once the engine's fence has signalled.

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme, Allocator};
use gpu_allocator::MemoryLocation;

use crate::error::{bail, Error, Result};
use crate::vk::device::Gpu;

pub struct ReadbackBuffer {
    pub buffer: vk::Buffer,
    pub size: u64,
    allocation: Option<Allocation>,
}

impl ReadbackBuffer {
    pub fn new(gpu: &Gpu, allocator: &mut Allocator, name: &str, size: u64) -> Result<Self> {
        let device = &gpu.device;
        let info = vk::BufferCreateInfo::default()
            .size(size)
            // Indirect: the networks' patch records hold their dispatch sizes.
            .usage(
                vk::BufferUsageFlags::STORAGE_BUFFER
                    | vk::BufferUsageFlags::UNIFORM_BUFFER
                    | vk::BufferUsageFlags::TRANSFER_DST
                    | vk::BufferUsageFlags::INDIRECT_BUFFER,
            )
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
                location: MemoryLocation::GpuToCpu,
                linear: true,
                allocation_scheme: AllocationScheme::GpuAllocatorManaged,
            }) {
                Ok(allocation) => allocation,
                Err(error) => {
                    device.destroy_buffer(buffer, None);
                    return Err(during(error.into()));
                }
            };
            let mut readback = Self {
                buffer,
                size,
                allocation: Some(allocation),
            };
            let allocation = readback.allocation.as_ref().unwrap();
            if allocation.mapped_ptr().is_none() {
                readback.destroy(gpu, allocator);
                bail!(
                    ErrorMissingDeviceFeature,
                    "{name}: no host-visible mappable memory"
                );
            }
            if let Err(error) =
                device.bind_buffer_memory(buffer, allocation.memory(), allocation.offset())
            {
                readback.destroy(gpu, allocator);
                return Err(during(error.into()));
            }
            Ok(readback)
        }
    }

    /// Reads a `u32` the GPU wrote at `offset` bytes.
    pub fn read_u32(&self, offset: u64) -> u32 {
        let bytes = self
            .allocation
            .as_ref()
            .and_then(|a| a.mapped_slice())
            .expect("mapped at creation");
        let at = offset as usize;
        u32::from_ne_bytes(bytes[at..at + 4].try_into().unwrap())
    }

    /// Writes `bytes` at `offset`, for the GPU to read once the command buffer is submitted.
    pub fn write(&mut self, offset: u64, bytes: &[u8]) {
        let mapped = self
            .allocation
            .as_mut()
            .and_then(|a| a.mapped_slice_mut())
            .expect("mapped at creation");
        mapped[offset as usize..][..bytes.len()].copy_from_slice(bytes);
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

/// Where a pass's counters live in the frame's host-visible counter buffer.
pub struct CounterRange {
    pub buffer: vk::Buffer,
    pub offset: u64,
    pub range: u64,
}
