//! Render targets: the five G-buffer colour targets, scene depth, and the two sun shadow maps.

use crate::error::Result;
use crate::gpu::{Gpu, Image, ImageDesc};
use ash::vk;
use std::sync::Arc;

pub(crate) const GBUFFER_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;
pub(crate) const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;
pub(crate) const GBUFFER_TARGETS: usize = 5;

pub(crate) struct GBufferTargets {
    /// base+metallic, normal+roughness, position+depth, motion+stencil+specular, emissive+coverage
    pub color: Vec<Image>,
    pub depth: Image,
}

impl GBufferTargets {
    pub fn new(gpu: &Arc<Gpu>, width: u32, height: u32) -> Result<Self> {
        let color_desc = ImageDesc {
            width,
            height,
            mip_levels: 1,
            format: GBUFFER_FORMAT,
            usage: vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::SAMPLED,
            aspect: vk::ImageAspectFlags::COLOR,
        };
        let color = (0..GBUFFER_TARGETS)
            .map(|_| Image::new(gpu, color_desc, "G-buffer target"))
            .collect::<Result<Vec<_>>>()?;
        let depth = Image::new(
            gpu,
            ImageDesc {
                format: DEPTH_FORMAT,
                usage: vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
                aspect: vk::ImageAspectFlags::DEPTH,
                ..color_desc
            },
            "scene depth",
        )?;
        Ok(Self { color, depth })
    }
}

pub(crate) fn shadow_map(gpu: &Arc<Gpu>, resolution: u32) -> Result<Image> {
    Image::new(
        gpu,
        ImageDesc {
            width: resolution,
            height: resolution,
            mip_levels: 1,
            format: DEPTH_FORMAT,
            usage: vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::SAMPLED,
            aspect: vk::ImageAspectFlags::DEPTH,
        },
        "shadow map",
    )
}
