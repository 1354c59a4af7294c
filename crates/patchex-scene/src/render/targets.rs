//! Render targets: the five G-buffer colour targets, scene depth, the two sun shadow maps, and
//! the forward pass's two targets.

use crate::error::Result;
use crate::gpu::{Buffer, Gpu, Image, ImageDesc};
use ash::vk;
use std::sync::Arc;

pub(crate) const GBUFFER_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;
pub(crate) const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;
pub(crate) const GBUFFER_TARGETS: usize = 5;
/// Read back as f32 by the host, like the resolve pass's planes.
pub(crate) const FORWARD_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;
pub(crate) const FORWARD_TARGETS: usize = 2;

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

/// The forward pass's targets (premultiplied colour and coverage; weighted motion and
/// coverage) and the host buffer they are copied into, made only for worlds with blended
/// surfaces.
pub(crate) struct ForwardTargets {
    pub color: Vec<Image>,
    /// RGBA f32 texels of each target in turn.
    pub readback: Buffer,
}

impl ForwardTargets {
    pub fn new(gpu: &Arc<Gpu>, width: u32, height: u32) -> Result<Self> {
        let desc = ImageDesc {
            width,
            height,
            mip_levels: 1,
            format: FORWARD_FORMAT,
            usage: vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC,
            aspect: vk::ImageAspectFlags::COLOR,
        };
        let color = (0..FORWARD_TARGETS)
            .map(|_| Image::new(gpu, desc, "forward target"))
            .collect::<Result<Vec<_>>>()?;
        let readback = Buffer::new(
            gpu,
            (FORWARD_TARGETS * 16 * width as usize * height as usize) as u64,
            vk::BufferUsageFlags::TRANSFER_DST,
            "forward read-back",
        )?;
        Ok(Self { color, readback })
    }
}

/// Colour attachments of `images`, cleared to zero and stored.
pub(crate) fn cleared_attachments(images: &[Image]) -> Vec<vk::RenderingAttachmentInfo<'static>> {
    images
        .iter()
        .map(|image| {
            vk::RenderingAttachmentInfo::default()
                .image_view(image.view)
                .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                .load_op(vk::AttachmentLoadOp::CLEAR)
                .store_op(vk::AttachmentStoreOp::STORE)
                .clear_value(vk::ClearValue {
                    color: vk::ClearColorValue { float32: [0.0; 4] },
                })
        })
        .collect()
}
