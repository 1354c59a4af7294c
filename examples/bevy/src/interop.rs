//! wgpu's objects as patchex takes them: raw Vulkan handles, formats, usages, layouts, the camera
//! in Vulkan's clip space, and a command buffer to record into.

use ash::vk;
use bevy::math::{Mat4, Vec3};
use bevy::render::view::ExtractedView;
use patchex::abi::{PATCHEX_DEPTH_HARDWARE_REVERSED, PatchexCamera, PatchexImage};
use patchex::error::PatchexResult;
use wgpu::hal::api::Vulkan;

/// Layouts wgpu leaves a texture in after a compute pass has bound it: sampled colour, sampled
/// depth and storage.
pub const SAMPLED: vk::ImageLayout = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
pub const SAMPLED_DEPTH: vk::ImageLayout = vk::ImageLayout::DEPTH_STENCIL_READ_ONLY_OPTIMAL;
pub const STORAGE: vk::ImageLayout = vk::ImageLayout::GENERAL;

/// A wgpu texture as patchex imports it, in `layout` when patchex's commands run.
pub fn describe(
    adapter: &wgpu::Adapter,
    texture: &wgpu::Texture,
    view: &wgpu::TextureView,
    layout: vk::ImageLayout,
) -> PatchexImage {
    // SAFETY: only the handles are read; the texture and view outlive the frame's commands.
    let (image, view) = unsafe {
        (
            texture
                .as_hal::<Vulkan>()
                .map_or(vk::Image::null(), |t| t.raw_handle()),
            view.as_hal::<Vulkan>()
                .map_or(vk::ImageView::null(), |v| v.raw_handle()),
        )
    };
    PatchexImage {
        image,
        view,
        format: vk_format(adapter, texture.format()),
        width: texture.width(),
        height: texture.height(),
        layout,
        usage: vk_usage(texture),
    }
}

/// The Vulkan format wgpu created a texture with, by wgpu-hal's own mapping (which also resolves
/// the formats wgpu chooses per device, such as `Depth24Plus`). patchex answers a format it does
/// not take with a clear error.
fn vk_format(adapter: &wgpu::Adapter, format: wgpu::TextureFormat) -> vk::Format {
    // SAFETY: the adapter is only asked for a mapping.
    unsafe { adapter.as_hal::<Vulkan>() }.map_or(vk::Format::UNDEFINED, |adapter| {
        adapter.texture_format_as_raw(format)
    })
}

/// The Vulkan usage wgpu creates a texture with: what it was asked for, and an attachment usage
/// wgpu adds so that it can clear the texture (depth formats always; colour ones without
/// COPY_DST, which are all renderable here). `Texture::usage` reports only the first, and patchex
/// checks each layout against the whole.
fn vk_usage(texture: &wgpu::Texture) -> vk::ImageUsageFlags {
    let usage = texture.usage();
    let mut flags = vk::ImageUsageFlags::empty();
    for (wgpu_usage, vk_usage) in [
        (
            wgpu::TextureUsages::TEXTURE_BINDING,
            vk::ImageUsageFlags::SAMPLED,
        ),
        (
            wgpu::TextureUsages::STORAGE_BINDING,
            vk::ImageUsageFlags::STORAGE,
        ),
        (
            wgpu::TextureUsages::COPY_SRC,
            vk::ImageUsageFlags::TRANSFER_SRC,
        ),
        (
            wgpu::TextureUsages::COPY_DST,
            vk::ImageUsageFlags::TRANSFER_DST,
        ),
    ] {
        if usage.contains(wgpu_usage) {
            flags |= vk_usage;
        }
    }
    if texture.format().is_depth_stencil_format() {
        flags |= vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT;
    } else if usage.contains(wgpu::TextureUsages::RENDER_ATTACHMENT)
        || !usage.contains(wgpu::TextureUsages::COPY_DST)
    {
        flags |= vk::ImageUsageFlags::COLOR_ATTACHMENT;
    }
    flags
}

/// The view's camera in patchex's conventions. Bevy projects with an infinite reversed-Z
/// perspective into wgpu's clip space, whose y points up: patchex's (Vulkan's) points down.
pub fn camera(view: &ExtractedView) -> PatchexCamera {
    let y_down = Mat4::from_scale(Vec3::new(1.0, -1.0, 1.0));
    PatchexCamera {
        view: view.world_from_view.to_matrix().inverse().to_cols_array(),
        projection: (y_down * view.clip_from_view).to_cols_array(),
        jitter: [0.0, 0.0],
        // Where Bevy's projection puts depth 1 (glam column-major: column 3, row 2).
        near_plane: view.clip_from_view.w_axis.z,
        far_plane: f32::INFINITY,
        depth_convention: PATCHEX_DEPTH_HARDWARE_REVERSED,
    }
}

/// Records into a new command buffer of its own: wgpu does not let one encoder mix its commands
/// with raw ones. wgpu tracks nothing in it.
pub fn record_raw(
    device: &wgpu::Device,
    record: impl FnOnce(vk::CommandBuffer) -> PatchexResult,
) -> Result<(wgpu::CommandBuffer, PatchexResult), String> {
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("patchex"),
    });
    // SAFETY: the command buffer is only recorded into, and the encoder is not used meanwhile.
    let result = unsafe {
        encoder.as_hal_mut::<Vulkan, _, _>(|hal| {
            hal.map(|hal| record(hal.raw_handle()))
                .ok_or_else(|| "wgpu's encoder is not a Vulkan one".to_owned())
        })
    }?;
    Ok((encoder.finish(), result))
}
