//! Buffers and images, each with its own dedicated allocation. The renderer creates a few dozen
//! resources at start-up, so a sub-allocator would add code without saving anything.

use super::Gpu;
use crate::error::{Error, Result, VkContext};
use ash::vk;
use std::sync::Arc;

fn find_memory_type(
    gpu: &Gpu,
    requirements: &vk::MemoryRequirements,
    wanted: vk::MemoryPropertyFlags,
    what: &'static str,
) -> Result<u32> {
    let properties = &gpu.memory_properties;
    (0..properties.memory_type_count)
        .find(|&index| {
            requirements.memory_type_bits & (1 << index) != 0
                && properties.memory_types[index as usize]
                    .property_flags
                    .contains(wanted)
        })
        .ok_or(Error::NoMemoryType(what))
}

fn allocate(
    gpu: &Gpu,
    requirements: vk::MemoryRequirements,
    wanted: vk::MemoryPropertyFlags,
    what: &'static str,
) -> Result<vk::DeviceMemory> {
    let info = vk::MemoryAllocateInfo::default()
        .allocation_size(requirements.size)
        .memory_type_index(find_memory_type(gpu, &requirements, wanted, what)?);
    // SAFETY: valid device and allocate info.
    unsafe { gpu.device.allocate_memory(&info, None) }.vk("vkAllocateMemory")
}

/// A host-visible, persistently mapped buffer: vertex data, uniforms and read-back all go
/// through host memory, which every Vulkan device offers.
pub(crate) struct Buffer {
    pub handle: vk::Buffer,
    pub size: u64,
    memory: vk::DeviceMemory,
    mapped: *mut u8,
    gpu: Arc<Gpu>,
}

impl Buffer {
    pub fn new(
        gpu: &Arc<Gpu>,
        size: u64,
        usage: vk::BufferUsageFlags,
        what: &'static str,
    ) -> Result<Self> {
        let size = size.max(4);
        let info = vk::BufferCreateInfo::default()
            .size(size)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        // SAFETY: valid device; the buffer is bound to fresh memory below before any use.
        unsafe {
            let handle = gpu.device.create_buffer(&info, None).vk("vkCreateBuffer")?;
            let requirements = gpu.device.get_buffer_memory_requirements(handle);
            let flags =
                vk::MemoryPropertyFlags::HOST_VISIBLE | vk::MemoryPropertyFlags::HOST_COHERENT;
            let memory = allocate(gpu, requirements, flags, what)?;
            gpu.device
                .bind_buffer_memory(handle, memory, 0)
                .vk("vkBindBufferMemory")?;
            let mapped = gpu
                .device
                .map_memory(memory, 0, vk::WHOLE_SIZE, vk::MemoryMapFlags::empty())
                .vk("vkMapMemory")? as *mut u8;
            Ok(Self {
                handle,
                size,
                memory,
                mapped,
                gpu: gpu.clone(),
            })
        }
    }

    pub fn with_data(
        gpu: &Arc<Gpu>,
        data: &[u8],
        usage: vk::BufferUsageFlags,
        what: &'static str,
    ) -> Result<Self> {
        let buffer = Self::new(gpu, data.len() as u64, usage, what)?;
        buffer.write(0, data);
        Ok(buffer)
    }

    /// Copies `data` in at `offset`. Callers only write while the GPU is idle on this buffer.
    pub fn write(&self, offset: usize, data: &[u8]) {
        assert!(
            offset + data.len() <= self.size as usize,
            "buffer write out of range"
        );
        // SAFETY: the range is inside the mapping (checked above) and the memory is coherent.
        unsafe {
            std::ptr::copy_nonoverlapping(data.as_ptr(), self.mapped.add(offset), data.len())
        };
    }

    /// Reads `count` f32 values from the start. Callers only read after the writing
    /// submission's fence has signalled.
    pub fn read_f32(&self, count: usize) -> Vec<f32> {
        assert!(count * 4 <= self.size as usize, "buffer read out of range");
        let mut values = vec![0f32; count];
        // SAFETY: the range is inside the mapping and f32 has no invalid bit patterns.
        unsafe {
            std::ptr::copy_nonoverlapping(self.mapped as *const f32, values.as_mut_ptr(), count);
        }
        values
    }
}

impl Drop for Buffer {
    fn drop(&mut self) {
        // SAFETY: the owner waits for the GPU to finish before dropping its resources.
        unsafe {
            self.gpu.device.unmap_memory(self.memory);
            self.gpu.device.destroy_buffer(self.handle, None);
            self.gpu.device.free_memory(self.memory, None);
        }
    }
}

#[derive(Clone, Copy)]
pub(crate) struct ImageDesc {
    pub width: u32,
    pub height: u32,
    pub mip_levels: u32,
    pub format: vk::Format,
    pub usage: vk::ImageUsageFlags,
    pub aspect: vk::ImageAspectFlags,
}

/// A device-local 2D image with one view over all its mip levels.
pub(crate) struct Image {
    pub handle: vk::Image,
    pub view: vk::ImageView,
    pub desc: ImageDesc,
    memory: vk::DeviceMemory,
    gpu: Arc<Gpu>,
}

impl Image {
    pub fn new(gpu: &Arc<Gpu>, desc: ImageDesc, what: &'static str) -> Result<Self> {
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(desc.format)
            .extent(vk::Extent3D {
                width: desc.width,
                height: desc.height,
                depth: 1,
            })
            .mip_levels(desc.mip_levels)
            .array_layers(1)
            .samples(vk::SampleCountFlags::TYPE_1)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(desc.usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        // SAFETY: valid device; memory is bound before the view is created.
        unsafe {
            let handle = gpu.device.create_image(&info, None).vk("vkCreateImage")?;
            let requirements = gpu.device.get_image_memory_requirements(handle);
            let memory = allocate(
                gpu,
                requirements,
                vk::MemoryPropertyFlags::DEVICE_LOCAL,
                what,
            )?;
            gpu.device
                .bind_image_memory(handle, memory, 0)
                .vk("vkBindImageMemory")?;
            let view_info = vk::ImageViewCreateInfo::default()
                .image(handle)
                .view_type(vk::ImageViewType::TYPE_2D)
                .format(desc.format)
                .subresource_range(subresource_range(desc.aspect, desc.mip_levels));
            let view = gpu
                .device
                .create_image_view(&view_info, None)
                .vk("vkCreateImageView")?;
            Ok(Self {
                handle,
                view,
                desc,
                memory,
                gpu: gpu.clone(),
            })
        }
    }

    pub fn full_range(&self) -> vk::ImageSubresourceRange {
        subresource_range(self.desc.aspect, self.desc.mip_levels)
    }
}

impl Drop for Image {
    fn drop(&mut self) {
        // SAFETY: the owner waits for the GPU to finish before dropping its resources.
        unsafe {
            self.gpu.device.destroy_image_view(self.view, None);
            self.gpu.device.destroy_image(self.handle, None);
            self.gpu.device.free_memory(self.memory, None);
        }
    }
}

fn subresource_range(aspect: vk::ImageAspectFlags, mip_levels: u32) -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange::default()
        .aspect_mask(aspect)
        .base_mip_level(0)
        .level_count(mip_levels)
        .base_array_layer(0)
        .layer_count(1)
}
