//! Barriers around the plugin's work: engine images move from the layout they were handed in to
//! the layout a pass needs and back, and the plugin's own images are ordered between passes.
//!
//! The plugin cannot know what the engine did to an image before the call or will do after it,
//! so the engine side of every dependency is ALL_COMMANDS with all memory access.

use ash::vk;

use crate::error::{bail, Result};
use crate::vk::image::{ImportedImage, OwnedImage, Texture, ALL_LAYERS, COLOR_SUBRESOURCE};

/// Layouts in which a pass can read an image as it is.
fn is_readable_layout(layout: vk::ImageLayout) -> bool {
    matches!(
        layout,
        vk::ImageLayout::GENERAL
            | vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL
            | vk::ImageLayout::DEPTH_STENCIL_READ_ONLY_OPTIMAL
            | vk::ImageLayout::DEPTH_READ_ONLY_OPTIMAL
            | vk::ImageLayout::STENCIL_READ_ONLY_OPTIMAL
            | vk::ImageLayout::READ_ONLY_OPTIMAL
    )
}

struct EngineImageUse {
    image: ImportedImage,
    layout_in_pass: vk::ImageLayout,
    /// How the plugin accesses it: SHADER_READ, SHADER_READ | SHADER_WRITE, or TRANSFER_WRITE.
    access: vk::AccessFlags,
}

/// Every stage the plugin touches an engine image in: its passes and its copies.
const PLUGIN_STAGES: vk::PipelineStageFlags = vk::PipelineStageFlags::from_raw(
    vk::PipelineStageFlags::COMPUTE_SHADER.as_raw() | vk::PipelineStageFlags::TRANSFER.as_raw(),
);

/// Every access the plugin's commands make: the passes' reads and writes, the transfers' and
/// the indirect dispatches' arguments.
const PLUGIN_ACCESS: vk::AccessFlags = vk::AccessFlags::from_raw(
    vk::AccessFlags::SHADER_READ.as_raw()
        | vk::AccessFlags::SHADER_WRITE.as_raw()
        | vk::AccessFlags::TRANSFER_READ.as_raw()
        | vk::AccessFlags::TRANSFER_WRITE.as_raw()
        | vk::AccessFlags::INDIRECT_COMMAND_READ.as_raw(),
);

/// The engine images one call touches, each once, with the layout its passes use.
#[derive(Default)]
pub struct EngineImageAccess {
    uses: Vec<EngineImageUse>,
}

impl EngineImageAccess {
    /// Registers a sampled read; returns the view with the layout the descriptor must name.
    pub fn read(&mut self, image: &ImportedImage) -> Result<Texture> {
        let layout = self.read_layout(image)?;
        Ok(Texture {
            image: image.image,
            view: image.view,
            layout,
            bytes: image.bytes,
        })
    }

    /// `read` of an optional input.
    pub fn read_optional(&mut self, image: Option<&ImportedImage>) -> Result<Option<Texture>> {
        image.map(|image| self.read(image)).transpose()
    }

    fn read_layout(&mut self, image: &ImportedImage) -> Result<vk::ImageLayout> {
        if let Some(existing) = self.uses.iter().find(|u| u.image.image == image.image) {
            if existing.access != vk::AccessFlags::SHADER_READ {
                bail!(
                    ErrorInvalidArgument,
                    "the output image is also passed as an input"
                );
            }
            if existing.image.layout != image.layout {
                bail!(
                    ErrorInvalidLayout,
                    "one VkImage is passed twice with different layouts ({:?} and {:?})",
                    existing.image.layout,
                    image.layout
                );
            }
            return Ok(existing.layout_in_pass);
        }
        let layout_in_pass = if is_readable_layout(image.layout) {
            image.layout
        } else if image.barrier_aspects() == vk::ImageAspectFlags::COLOR {
            vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL
        } else {
            vk::ImageLayout::DEPTH_STENCIL_READ_ONLY_OPTIMAL
        };
        self.uses.push(EngineImageUse {
            image: *image,
            layout_in_pass,
            access: vk::AccessFlags::SHADER_READ,
        });
        Ok(layout_in_pass)
    }

    /// Registers a write: a storage write in GENERAL layout, or for an image written by a copy
    /// (`ImportedImage::written_by_copy`) a transfer write in TRANSFER_DST_OPTIMAL.
    pub fn write(&mut self, image: &ImportedImage) -> Result<Texture> {
        if self.uses.iter().any(|u| u.image.image == image.image) {
            bail!(
                ErrorInvalidArgument,
                "an image the plugin writes is also passed as another input or output"
            );
        }
        let (layout_in_pass, access) = if image.written_by_copy {
            (
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                vk::AccessFlags::TRANSFER_WRITE,
            )
        } else {
            // The passes also read it back: the frame is refined in place.
            (
                vk::ImageLayout::GENERAL,
                vk::AccessFlags::SHADER_READ | vk::AccessFlags::SHADER_WRITE,
            )
        };
        self.uses.push(EngineImageUse {
            image: *image,
            layout_in_pass,
            access,
        });
        Ok(Texture {
            image: image.image,
            view: image.view,
            layout: layout_in_pass,
            bytes: image.bytes,
        })
    }

    /// Waits for the engine's earlier work on every image and moves it to its pass layout.
    /// Also makes everything recorded before visible to the plugin's commands (`later_stages`), so
    /// that no other barrier need wait for it.
    pub fn acquire(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        later_stages: vk::PipelineStageFlags,
    ) {
        let barriers: Vec<_> = self
            .uses
            .iter()
            .map(|u| {
                barrier(&u.image)
                    .src_access_mask(vk::AccessFlags::MEMORY_WRITE)
                    .dst_access_mask(u.access)
                    .old_layout(u.image.layout)
                    .new_layout(u.layout_in_pass)
            })
            .collect();
        let earlier = vk::MemoryBarrier::default()
            .src_access_mask(vk::AccessFlags::MEMORY_WRITE)
            .dst_access_mask(PLUGIN_ACCESS);
        // SAFETY: cmd is in the recording state (API contract); barriers name live images.
        unsafe {
            device.cmd_pipeline_barrier(
                cmd,
                vk::PipelineStageFlags::ALL_COMMANDS,
                PLUGIN_STAGES | later_stages,
                vk::DependencyFlags::empty(),
                &[earlier],
                &[],
                &barriers,
            );
        }
    }

    /// Returns every image to the layout it was handed in, visible to whatever the engine does
    /// next, and makes every write of the call available to later commands: the next call writes
    /// its counters ahead of its own `acquire`.
    pub fn release(&self, device: &ash::Device, cmd: vk::CommandBuffer) {
        let barriers: Vec<_> = self
            .uses
            .iter()
            .map(|u| {
                barrier(&u.image)
                    .src_access_mask(u.access & !vk::AccessFlags::SHADER_READ)
                    .dst_access_mask(vk::AccessFlags::MEMORY_READ | vk::AccessFlags::MEMORY_WRITE)
                    .old_layout(u.layout_in_pass)
                    .new_layout(u.image.layout)
            })
            .collect();
        let written = vk::MemoryBarrier::default()
            .src_access_mask(vk::AccessFlags::SHADER_WRITE | vk::AccessFlags::TRANSFER_WRITE)
            .dst_access_mask(vk::AccessFlags::MEMORY_READ | vk::AccessFlags::MEMORY_WRITE);
        // SAFETY: as in `acquire`.
        unsafe {
            device.cmd_pipeline_barrier(
                cmd,
                PLUGIN_STAGES,
                vk::PipelineStageFlags::ALL_COMMANDS,
                vk::DependencyFlags::empty(),
                &[written],
                &[],
                &barriers,
            );
        }
    }
}

fn barrier(image: &ImportedImage) -> vk::ImageMemoryBarrier<'static> {
    vk::ImageMemoryBarrier::default()
        .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .image(image.image)
        .subresource_range(vk::ImageSubresourceRange {
            aspect_mask: image.barrier_aspects(),
            level_count: image.mip_levels,
            ..COLOR_SUBRESOURCE
        })
}

/// Makes what commands in `src_stages` wrote (`written`) visible to commands in `dst_stages`,
/// and orders their reads before later writes. The recorder places it (`vk::recorder`).
pub fn memory(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    src_stages: vk::PipelineStageFlags,
    written: vk::AccessFlags,
    dst_stages: vk::PipelineStageFlags,
) {
    let memory = vk::MemoryBarrier::default()
        .src_access_mask(written)
        .dst_access_mask(PLUGIN_ACCESS);
    // SAFETY: cmd is recording.
    unsafe {
        device.cmd_pipeline_barrier(
            cmd,
            src_stages,
            dst_stages,
            vk::DependencyFlags::empty(),
            &[memory],
            &[],
            &[],
        );
    }
}

/// Moves a plugin image a pass just wrote (GENERAL) to TRANSFER_SRC_OPTIMAL for a copy, or
/// (`back`) returns it to GENERAL once the copy has read it, before a later pass writes it.
pub fn owned_for_copy(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    image: &OwnedImage,
    back: bool,
) {
    let (general, source) = (
        vk::ImageLayout::GENERAL,
        vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
    );
    let barrier = vk::ImageMemoryBarrier::default()
        .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .image(image.image)
        .subresource_range(ALL_LAYERS);
    let (barrier, from, to) = if back {
        (
            barrier
                .old_layout(source)
                .new_layout(general)
                .dst_access_mask(vk::AccessFlags::SHADER_WRITE),
            vk::PipelineStageFlags::TRANSFER,
            vk::PipelineStageFlags::COMPUTE_SHADER,
        )
    } else {
        (
            barrier
                .old_layout(general)
                .new_layout(source)
                .src_access_mask(vk::AccessFlags::SHADER_WRITE)
                .dst_access_mask(vk::AccessFlags::TRANSFER_READ),
            vk::PipelineStageFlags::COMPUTE_SHADER,
            vk::PipelineStageFlags::TRANSFER,
        )
    };
    // SAFETY: cmd is recording; the image is live.
    unsafe {
        device.cmd_pipeline_barrier(
            cmd,
            from,
            to,
            vk::DependencyFlags::empty(),
            &[],
            &[],
            &[barrier],
        );
    }
}

/// Makes the copy of the counters into the readback buffer readable by the host after the
/// engine's fence.
pub fn transfer_to_host(device: &ash::Device, cmd: vk::CommandBuffer) {
    let memory = vk::MemoryBarrier::default()
        .src_access_mask(vk::AccessFlags::TRANSFER_WRITE)
        .dst_access_mask(vk::AccessFlags::HOST_READ);
    // SAFETY: cmd is recording.
    unsafe {
        device.cmd_pipeline_barrier(
            cmd,
            vk::PipelineStageFlags::TRANSFER,
            vk::PipelineStageFlags::HOST,
            vk::DependencyFlags::empty(),
            &[memory],
            &[],
            &[],
        );
    }
}

/// Moves plugin images that no command buffer has touched yet from UNDEFINED to GENERAL.
pub fn initialize_owned(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    images: &mut [&mut OwnedImage],
) {
    let barriers: Vec<_> = images
        .iter_mut()
        .filter(|image| !image.initialized)
        .map(|image| {
            image.initialized = true;
            vk::ImageMemoryBarrier::default()
                .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
                .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
                .image(image.image)
                .subresource_range(ALL_LAYERS)
                .old_layout(vk::ImageLayout::UNDEFINED)
                .new_layout(vk::ImageLayout::GENERAL)
                .dst_access_mask(vk::AccessFlags::SHADER_READ | vk::AccessFlags::SHADER_WRITE)
        })
        .collect();
    if barriers.is_empty() {
        return;
    }
    // SAFETY: cmd is recording; the images are live.
    unsafe {
        device.cmd_pipeline_barrier(
            cmd,
            vk::PipelineStageFlags::TOP_OF_PIPE,
            vk::PipelineStageFlags::COMPUTE_SHADER,
            vk::DependencyFlags::empty(),
            &[],
            &[],
            &barriers,
        );
    }
}
