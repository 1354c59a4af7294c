//! Engine-owned images with upload and readback through staging buffers.

use ash::vk;

use crate::texel::{decode, encode, texel_layout};
use crate::Engine;

/// A 2D image owned by the engine (layer 0, mip 0 and any mips below it), with a view of all
/// its mips and dedicated memory.
pub struct EngineImage {
    pub image: vk::Image,
    pub view: vk::ImageView,
    pub format: vk::Format,
    pub width: u32,
    pub height: u32,
    pub usage: vk::ImageUsageFlags,
    pub mip_levels: u32,
    memory: vk::DeviceMemory,
    device: ash::Device,
}

fn aspect(format: vk::Format) -> vk::ImageAspectFlags {
    match format {
        vk::Format::D32_SFLOAT => vk::ImageAspectFlags::DEPTH,
        _ => vk::ImageAspectFlags::COLOR,
    }
}

impl EngineImage {
    pub fn new(
        engine: &Engine,
        format: vk::Format,
        width: u32,
        height: u32,
        usage: vk::ImageUsageFlags,
    ) -> Self {
        Self::with_mips(engine, format, width, height, 1, usage)
    }

    /// An image of `mip_levels` mips, each half the size of the one before.
    pub fn with_mips(
        engine: &Engine,
        format: vk::Format,
        width: u32,
        height: u32,
        mip_levels: u32,
        usage: vk::ImageUsageFlags,
    ) -> Self {
        let device = &engine.device;
        let usage = usage | vk::ImageUsageFlags::TRANSFER_SRC | vk::ImageUsageFlags::TRANSFER_DST;
        // SAFETY: plain object creation on the engine's device; destroyed in Drop.
        unsafe {
            let image = device
                .create_image(
                    &vk::ImageCreateInfo::default()
                        .image_type(vk::ImageType::TYPE_2D)
                        .format(format)
                        .extent(vk::Extent3D {
                            width,
                            height,
                            depth: 1,
                        })
                        .mip_levels(mip_levels)
                        .array_layers(1)
                        .samples(vk::SampleCountFlags::TYPE_1)
                        .tiling(vk::ImageTiling::OPTIMAL)
                        .usage(usage)
                        .initial_layout(vk::ImageLayout::UNDEFINED),
                    None,
                )
                .expect("vkCreateImage");
            let requirements = device.get_image_memory_requirements(image);
            let memory = engine.allocate(requirements, vk::MemoryPropertyFlags::DEVICE_LOCAL);
            device
                .bind_image_memory(image, memory, 0)
                .expect("vkBindImageMemory");
            let view = device
                .create_image_view(
                    &vk::ImageViewCreateInfo::default()
                        .image(image)
                        .view_type(vk::ImageViewType::TYPE_2D)
                        .format(format)
                        .subresource_range(vk::ImageSubresourceRange {
                            level_count: mip_levels,
                            ..range(format)
                        }),
                    None,
                )
                .expect("vkCreateImageView");
            Self {
                image,
                view,
                format,
                width,
                height,
                usage,
                mip_levels,
                memory,
                device: device.clone(),
            }
        }
    }

    /// Fills the image with `values` (row-major, the format's channels interleaved) and leaves
    /// it in `layout`. The image's previous contents are discarded.
    pub fn upload(&self, engine: &Engine, values: &[f32], layout: vk::ImageLayout) {
        self.upload_mips(engine, &[values], layout);
    }

    /// Fills each mip of the image with its values, mip 0 first, and leaves it in `layout`.
    pub fn upload_mips(&self, engine: &Engine, mips: &[&[f32]], layout: vk::ImageLayout) {
        assert_eq!(
            mips.len(),
            self.mip_levels as usize,
            "one set of values a mip"
        );
        let (channels, _) = texel_layout(self.format);
        let mut bytes = Vec::new();
        let mut regions = Vec::new();
        for (level, values) in mips.iter().enumerate() {
            let (width, height) = ((self.width >> level).max(1), (self.height >> level).max(1));
            assert_eq!(
                values.len(),
                (width * height) as usize * channels,
                "upload size of mip {level}"
            );
            let mut region = self.as_image_ref().copy_region();
            region.buffer_offset = bytes.len() as u64;
            region.image_subresource.mip_level = level as u32;
            region.image_extent = vk::Extent3D {
                width,
                height,
                depth: 1,
            };
            regions.push(region);
            bytes.extend(encode(self.format, values));
        }
        let staging = StagingBuffer::new(engine, bytes.len() as u64);
        staging.write(&bytes);
        let barrier = |old, new| {
            let mut barrier = self.as_image_ref().barrier(old, new);
            barrier.subresource_range.level_count = self.mip_levels;
            barrier
        };
        engine.run(|cmd| {
            // SAFETY: cmd is recording; the buffer holds exactly the mips' texels.
            unsafe {
                let device = &engine.device;
                let stages = vk::PipelineStageFlags::ALL_COMMANDS;
                let flags = vk::DependencyFlags::empty();
                let to_copy = barrier(
                    vk::ImageLayout::UNDEFINED,
                    vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                );
                device.cmd_pipeline_barrier(cmd, stages, stages, flags, &[], &[], &[to_copy]);
                device.cmd_copy_buffer_to_image(
                    cmd,
                    staging.buffer,
                    self.image,
                    vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                    &regions,
                );
                let after = barrier(vk::ImageLayout::TRANSFER_DST_OPTIMAL, layout);
                device.cmd_pipeline_barrier(cmd, stages, stages, flags, &[], &[], &[after]);
            }
        });
    }

    /// See [`ImageRef::read`].
    pub fn read(&self, engine: &Engine, layout: vk::ImageLayout) -> Vec<f32> {
        self.as_image_ref().read(engine, layout)
    }

    fn as_image_ref(&self) -> ImageRef {
        ImageRef {
            image: self.image,
            format: self.format,
            width: self.width,
            height: self.height,
        }
    }
}

/// Layer 0 of any 2D colour or depth image on the engine's device, such as one the plugin owns,
/// for reading back.
#[derive(Clone, Copy)]
pub struct ImageRef {
    pub image: vk::Image,
    pub format: vk::Format,
    pub width: u32,
    pub height: u32,
}

impl ImageRef {
    fn barrier(
        &self,
        old: vk::ImageLayout,
        new: vk::ImageLayout,
    ) -> vk::ImageMemoryBarrier<'static> {
        vk::ImageMemoryBarrier::default()
            .image(self.image)
            .subresource_range(range(self.format))
            .old_layout(old)
            .new_layout(new)
            .src_access_mask(vk::AccessFlags::MEMORY_WRITE)
            .dst_access_mask(vk::AccessFlags::MEMORY_READ | vk::AccessFlags::MEMORY_WRITE)
            .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
            .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
    }

    fn record_barrier(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        old: vk::ImageLayout,
        new: vk::ImageLayout,
    ) {
        // SAFETY: cmd is recording.
        unsafe {
            device.cmd_pipeline_barrier(
                cmd,
                vk::PipelineStageFlags::ALL_COMMANDS,
                vk::PipelineStageFlags::ALL_COMMANDS,
                vk::DependencyFlags::empty(),
                &[],
                &[],
                &[self.barrier(old, new)],
            );
        }
    }

    /// Reads the image, which must be in `layout`, and leaves it there. Validation's layout
    /// tracking reports it when the image is in fact in another layout.
    pub fn read(&self, engine: &Engine, layout: vk::ImageLayout) -> Vec<f32> {
        let (_, bytes_per_texel) = texel_layout(self.format);
        let size = (self.width * self.height) as u64 * bytes_per_texel as u64;
        let staging = StagingBuffer::new(engine, size);
        engine.run(|cmd| {
            self.record_barrier(
                &engine.device,
                cmd,
                layout,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
            );
            // SAFETY: cmd is recording; the buffer is large enough for the image.
            unsafe {
                engine.device.cmd_copy_image_to_buffer(
                    cmd,
                    self.image,
                    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                    staging.buffer,
                    &[self.copy_region()],
                );
            }
            self.record_barrier(
                &engine.device,
                cmd,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                layout,
            );
            let to_host = vk::MemoryBarrier::default()
                .src_access_mask(vk::AccessFlags::TRANSFER_WRITE)
                .dst_access_mask(vk::AccessFlags::HOST_READ);
            // SAFETY: cmd is recording.
            unsafe {
                engine.device.cmd_pipeline_barrier(
                    cmd,
                    vk::PipelineStageFlags::TRANSFER,
                    vk::PipelineStageFlags::HOST,
                    vk::DependencyFlags::empty(),
                    &[to_host],
                    &[],
                    &[],
                );
            }
        });
        decode(self.format, &staging.read())
    }

    fn copy_region(&self) -> vk::BufferImageCopy {
        vk::BufferImageCopy {
            buffer_offset: 0,
            buffer_row_length: 0,
            buffer_image_height: 0,
            image_subresource: vk::ImageSubresourceLayers {
                aspect_mask: aspect(self.format),
                mip_level: 0,
                base_array_layer: 0,
                layer_count: 1,
            },
            image_offset: vk::Offset3D::default(),
            image_extent: vk::Extent3D {
                width: self.width,
                height: self.height,
                depth: 1,
            },
        }
    }
}

impl Drop for EngineImage {
    fn drop(&mut self) {
        // SAFETY: the harness waits for every submission before images go out of scope.
        unsafe {
            self.device.destroy_image_view(self.view, None);
            self.device.destroy_image(self.image, None);
            self.device.free_memory(self.memory, None);
        }
    }
}

fn range(format: vk::Format) -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange {
        aspect_mask: aspect(format),
        base_mip_level: 0,
        level_count: 1,
        base_array_layer: 0,
        layer_count: 1,
    }
}

/// A host-visible transfer buffer.
struct StagingBuffer {
    buffer: vk::Buffer,
    memory: vk::DeviceMemory,
    size: u64,
    device: ash::Device,
}

impl StagingBuffer {
    fn new(engine: &Engine, size: u64) -> Self {
        let device = &engine.device;
        // SAFETY: plain object creation; destroyed in Drop.
        unsafe {
            let buffer = device
                .create_buffer(
                    &vk::BufferCreateInfo::default().size(size).usage(
                        vk::BufferUsageFlags::TRANSFER_SRC | vk::BufferUsageFlags::TRANSFER_DST,
                    ),
                    None,
                )
                .expect("vkCreateBuffer");
            let requirements = device.get_buffer_memory_requirements(buffer);
            let memory = engine.allocate(
                requirements,
                vk::MemoryPropertyFlags::HOST_VISIBLE | vk::MemoryPropertyFlags::HOST_COHERENT,
            );
            device
                .bind_buffer_memory(buffer, memory, 0)
                .expect("vkBindBufferMemory");
            Self {
                buffer,
                memory,
                size,
                device: device.clone(),
            }
        }
    }

    fn write(&self, bytes: &[u8]) {
        // SAFETY: coherent host-visible memory of at least `size` bytes, not in use by the GPU.
        unsafe {
            let pointer = self
                .device
                .map_memory(self.memory, 0, self.size, vk::MemoryMapFlags::empty())
                .expect("vkMapMemory");
            std::ptr::copy_nonoverlapping(bytes.as_ptr(), pointer.cast::<u8>(), bytes.len());
            self.device.unmap_memory(self.memory);
        }
    }

    fn read(&self) -> Vec<u8> {
        // SAFETY: as in `write`; the GPU finished writing before `run` returned.
        unsafe {
            let pointer = self
                .device
                .map_memory(self.memory, 0, self.size, vk::MemoryMapFlags::empty())
                .expect("vkMapMemory");
            let bytes =
                std::slice::from_raw_parts(pointer.cast::<u8>(), self.size as usize).to_vec();
            self.device.unmap_memory(self.memory);
            bytes
        }
    }
}

impl Drop for StagingBuffer {
    fn drop(&mut self) {
        // SAFETY: the submission using the buffer has completed.
        unsafe {
            self.device.destroy_buffer(self.buffer, None);
            self.device.free_memory(self.memory, None);
        }
    }
}
