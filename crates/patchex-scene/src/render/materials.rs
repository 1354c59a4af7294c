//! Material textures on the GPU and one descriptor set per material.

use super::uniforms::MaterialConstants;
use crate::asset::{Material, TextureData, TextureRole};
use crate::error::{Result, VkContext};
use crate::gpu::{image_barrier, Buffer, Gpu, Image, ImageDesc, ImageTransition};
use crate::scene::Draw;
use ash::vk;
use std::sync::Arc;

pub(crate) struct GpuMaterials {
    pub sets: Vec<vk::DescriptorSet>,
    pool: vk::DescriptorPool,
    sampler: vk::Sampler,
    _textures: Vec<Image>,
    gpu: Arc<Gpu>,
}

const TEXTURE_SLOTS: u32 = 4;

impl GpuMaterials {
    pub fn new(
        gpu: &Arc<Gpu>,
        layout: vk::DescriptorSetLayout,
        materials: &[Material],
        textures: &[TextureData],
    ) -> Result<Self> {
        let white = TextureData::solid([255; 4], TextureRole::Color);
        let flat_normal = TextureData::solid([128, 128, 255, 255], TextureRole::Data);
        let mut images = Vec::with_capacity(textures.len() + 2);
        for texture in textures.iter().chain([&white, &flat_normal]) {
            images.push(upload_texture(gpu, texture)?);
        }
        let white_index = textures.len();
        let flat_normal_index = textures.len() + 1;

        let sampler_info = vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::LINEAR)
            .min_filter(vk::Filter::LINEAR)
            .mipmap_mode(vk::SamplerMipmapMode::LINEAR)
            .address_mode_u(vk::SamplerAddressMode::REPEAT)
            .address_mode_v(vk::SamplerAddressMode::REPEAT)
            .address_mode_w(vk::SamplerAddressMode::REPEAT)
            .max_lod(vk::LOD_CLAMP_NONE);
        let count = materials.len() as u32;
        let pool_sizes = [
            vk::DescriptorPoolSize {
                ty: vk::DescriptorType::SAMPLED_IMAGE,
                descriptor_count: count * TEXTURE_SLOTS,
            },
            vk::DescriptorPoolSize {
                ty: vk::DescriptorType::SAMPLER,
                descriptor_count: count,
            },
        ];
        // SAFETY: valid device; sets are written with live image views and sampler below.
        let (sampler, pool, sets) = unsafe {
            let sampler = gpu
                .device
                .create_sampler(&sampler_info, None)
                .vk("vkCreateSampler")?;
            let pool = gpu
                .device
                .create_descriptor_pool(
                    &vk::DescriptorPoolCreateInfo::default()
                        .max_sets(count)
                        .pool_sizes(&pool_sizes),
                    None,
                )
                .vk("vkCreateDescriptorPool")?;
            let layouts = vec![layout; materials.len()];
            let sets = gpu
                .device
                .allocate_descriptor_sets(
                    &vk::DescriptorSetAllocateInfo::default()
                        .descriptor_pool(pool)
                        .set_layouts(&layouts),
                )
                .vk("vkAllocateDescriptorSets")?;
            (sampler, pool, sets)
        };

        for (material, &set) in materials.iter().zip(&sets) {
            let slots = [
                material.base_color_texture.unwrap_or(white_index),
                material.metallic_roughness_texture.unwrap_or(white_index),
                material.normal_texture.unwrap_or(flat_normal_index),
                material.emissive_texture.unwrap_or(white_index),
            ];
            let image_infos: Vec<[vk::DescriptorImageInfo; 1]> = slots
                .iter()
                .map(|&texture| {
                    [vk::DescriptorImageInfo::default()
                        .image_view(images[texture].view)
                        .image_layout(vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL)]
                })
                .collect();
            let sampler_info = [vk::DescriptorImageInfo::default().sampler(sampler)];
            let mut writes: Vec<vk::WriteDescriptorSet> = image_infos
                .iter()
                .enumerate()
                .map(|(binding, info)| {
                    vk::WriteDescriptorSet::default()
                        .dst_set(set)
                        .dst_binding(binding as u32)
                        .descriptor_type(vk::DescriptorType::SAMPLED_IMAGE)
                        .image_info(info)
                })
                .collect();
            writes.push(
                vk::WriteDescriptorSet::default()
                    .dst_set(set)
                    .dst_binding(TEXTURE_SLOTS)
                    .descriptor_type(vk::DescriptorType::SAMPLER)
                    .image_info(&sampler_info),
            );
            // SAFETY: every referenced view and the sampler are alive.
            unsafe { gpu.device.update_descriptor_sets(&writes, &[]) };
        }

        Ok(Self {
            sets,
            pool,
            sampler,
            _textures: images,
            gpu: gpu.clone(),
        })
    }
}

impl GpuMaterials {
    /// Binds `draw`'s material (set 1 and the push constants of `layout`, whose fragment stage
    /// reads `Material` in shaders/include/material.wgsl).
    pub fn bind(
        &self,
        gpu: &Gpu,
        command_buffer: vk::CommandBuffer,
        layout: vk::PipelineLayout,
        materials: &[Material],
        draw: &Draw,
    ) {
        let material = draw.material as usize;
        let constants = MaterialConstants::new(&materials[material], draw.stencil);
        // SAFETY: recording, with a pipeline of `layout` bound; the set is alive.
        unsafe {
            gpu.device.cmd_bind_descriptor_sets(
                command_buffer,
                vk::PipelineBindPoint::GRAPHICS,
                layout,
                1,
                &[self.sets[material]],
                &[],
            );
            gpu.device.cmd_push_constants(
                command_buffer,
                layout,
                vk::ShaderStageFlags::FRAGMENT,
                0,
                bytemuck::bytes_of(&constants),
            );
        }
    }
}

impl Drop for GpuMaterials {
    fn drop(&mut self) {
        // SAFETY: the renderer waits for the GPU before dropping its parts.
        unsafe {
            self.gpu.device.destroy_descriptor_pool(self.pool, None);
            self.gpu.device.destroy_sampler(self.sampler, None);
        }
    }
}

/// Copies every mip level through a staging buffer and leaves the image shader-readable.
fn upload_texture(gpu: &Arc<Gpu>, texture: &TextureData) -> Result<Image> {
    let format = match texture.role {
        TextureRole::Color => vk::Format::R8G8B8A8_SRGB,
        TextureRole::Data => vk::Format::R8G8B8A8_UNORM,
    };
    let image = Image::new(
        gpu,
        ImageDesc {
            width: texture.width,
            height: texture.height,
            mip_levels: texture.mips.len() as u32,
            format,
            usage: vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST,
            aspect: vk::ImageAspectFlags::COLOR,
        },
        "material texture",
    )?;
    let bytes: Vec<u8> = texture.mips.concat();
    let staging = Buffer::with_data(
        gpu,
        &bytes,
        vk::BufferUsageFlags::TRANSFER_SRC,
        "texture staging",
    )?;
    let mut offset = 0u64;
    let regions: Vec<vk::BufferImageCopy> = texture
        .mips
        .iter()
        .enumerate()
        .map(|(level, mip)| {
            let (width, height) = texture.mip_size(level);
            let region = vk::BufferImageCopy::default()
                .buffer_offset(offset)
                .image_subresource(
                    vk::ImageSubresourceLayers::default()
                        .aspect_mask(vk::ImageAspectFlags::COLOR)
                        .mip_level(level as u32)
                        .layer_count(1),
                )
                .image_extent(vk::Extent3D {
                    width,
                    height,
                    depth: 1,
                });
            offset += mip.len() as u64;
            region
        })
        .collect();
    gpu.submit_and_wait(|command_buffer| {
        image_barrier(
            gpu,
            command_buffer,
            &[&image],
            ImageTransition {
                from: (
                    vk::ImageLayout::UNDEFINED,
                    vk::PipelineStageFlags::TOP_OF_PIPE,
                    vk::AccessFlags::empty(),
                ),
                to: (
                    vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                    vk::PipelineStageFlags::TRANSFER,
                    vk::AccessFlags::TRANSFER_WRITE,
                ),
            },
        );
        // SAFETY: recording; the staging buffer outlives the wait in `submit_and_wait`.
        unsafe {
            gpu.device.cmd_copy_buffer_to_image(
                command_buffer,
                staging.handle,
                image.handle,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &regions,
            );
        }
        image_barrier(
            gpu,
            command_buffer,
            &[&image],
            ImageTransition {
                from: (
                    vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                    vk::PipelineStageFlags::TRANSFER,
                    vk::AccessFlags::TRANSFER_WRITE,
                ),
                to: (
                    vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                    vk::PipelineStageFlags::FRAGMENT_SHADER,
                    vk::AccessFlags::SHADER_READ,
                ),
            },
        );
    })?;
    Ok(image)
}
