//! patchex inside Bevy's render schedule. Every camera frame, after Bevy's main pass and before
//! its post-processing, one system records, in order:
//! 1. the G-buffer pass (`gbuffer.rs`): base colour, material and object ids for patchex, every
//!    image it touches left in a known layout;
//! 2. patchex's passes, in a command buffer of their own, through wgpu's Vulkan interop: an even
//!    displayed instant submits the rendered frame, an odd one is extrapolated from the frame
//!    before and its own prepasses;
//! 3. on a generated instant, a copy of patchex's output over the view's colour, so that Bevy's
//!    post-processing and display show it; in check mode, first copies of both for scoring.
//!
//! Outside check mode Bevy's main pass (lighting and shading) does not run on generated instants:
//! the prepasses (depth, normals, motion vectors, the deferred G-buffer) are all patchex needs.

use std::ffi::CStr;
use std::ptr;

use bevy::core_pipeline::prepass::{PreviousViewData, ViewPrepassTextures};
use bevy::core_pipeline::schedule::{Core3d, Core3dSystems};
use bevy::prelude::*;
use bevy::render::RenderApp;
use bevy::render::extract_resource::{ExtractResource, ExtractResourcePlugin};
use bevy::render::renderer::{RenderAdapter, RenderContext, RenderDevice, ViewQuery};
use bevy::render::texture::CachedTexture;
use bevy::render::view::{ExtractedView, ViewTarget};
use patchex::abi::*;
use patchex::error::PatchexResult;
use patchex::ffi::{
    PatchexContext, patchex_create, patchex_destroy, patchex_extrapolate, patchex_get_frame_stats,
    patchex_last_error, patchex_submit_gbuffers,
};
use wgpu::hal::api::Vulkan;

use crate::gbuffer::{GBufferImages, GBufferPass, OwnedImage, Prepasses};
use crate::interop::{self, SAMPLED, SAMPLED_DEPTH, STORAGE, describe};

/// The largest frame the patchex context is created for.
const MAX_EXTENT: u32 = 3840;

/// The displayed instant the main world is at: even instants are rendered, odd ones generated.
/// `None` while the scene loads.
#[derive(Resource, Clone, Copy, Default, ExtractResource)]
pub struct DisplayedInstant(pub Option<u64>);

impl DisplayedInstant {
    fn is_generated(self) -> bool {
        self.0.is_some_and(|instant| instant % 2 == 1)
    }
}

pub struct FrameGenerationPlugin {
    /// Render generated instants in full too, and copy both out for scoring.
    pub check: bool,
}

impl Plugin for FrameGenerationPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<DisplayedInstant>()
            .add_plugins(ExtractResourcePlugin::<DisplayedInstant>::default());
        let render_app = app.sub_app_mut(RenderApp);
        render_app.add_systems(
            Core3d,
            generate_frames.in_set(Core3dSystems::EarlyPostProcess),
        );
        if !self.check {
            render_app.configure_sets(
                Core3d,
                Core3dSystems::MainPass
                    .run_if(|instant: Res<DisplayedInstant>| !instant.is_generated()),
            );
        }
    }

    fn finish(&self, app: &mut App) {
        let render_app = app.sub_app_mut(RenderApp);
        let world = render_app.world();
        let device = world.resource::<RenderDevice>().clone();
        let adapter = world.resource::<RenderAdapter>().clone();
        render_app.insert_resource(FrameGenerator::new(device, adapter, self.check));
    }
}

/// Which image a readback buffer holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Readback {
    /// Bevy's rendering of a rendered instant (frame t of the next generated one).
    Rendered,
    /// Bevy's rendering of a generated instant.
    Truth,
    /// patchex's extrapolation of a generated instant.
    Generated,
}

/// An RGBA16F image copied into a buffer the main loop maps after the frame.
pub struct ReadbackBuffer {
    pub what: Readback,
    pub buffer: wgpu::Buffer,
    pub width: u32,
    pub height: u32,
    pub bytes_per_row: u32,
}

/// The patchex context, its images and what the last frame left for the main loop.
#[derive(Resource)]
pub struct FrameGenerator {
    /// `Err` when patchex could not be created; reported at the first frame. Declared first so
    /// that it is dropped (destroyed) before the device below.
    context: Result<Context, String>,
    queue_family_index: u32,
    check: bool,
    gbuffer: GBufferPass,
    images: Option<GBufferImages>,
    submitted_frames: u64,
    /// What this frame copied out, for the main loop to map.
    pub readbacks: Vec<ReadbackBuffer>,
    /// The first failure: the main loop stops on it.
    pub failure: Option<String>,
    device: RenderDevice,
    /// What patchex is told of wgpu's textures' formats is asked of it.
    adapter: RenderAdapter,
}

/// A patchex context. Calls into it are made by the render world's system and by the main loop
/// between updates, never at the same time, and a context may move between threads between calls.
struct Context(*mut PatchexContext);
// SAFETY: see above.
unsafe impl Send for Context {}
// SAFETY: see above: no two calls overlap.
unsafe impl Sync for Context {}

impl Drop for Context {
    fn drop(&mut self) {
        // SAFETY: the context is live, and the device outlives it (see FrameGenerator).
        unsafe { patchex_destroy(self.0) };
    }
}

impl Context {
    /// A context on wgpu's Vulkan device, and the queue family of its queue.
    fn new(device: &wgpu::Device) -> Result<(Self, u32), String> {
        // SAFETY: only handles are read; wgpu keeps them alive with the device.
        let info = unsafe {
            let hal = device
                .as_hal::<Vulkan>()
                .ok_or("Bevy is not rendering through Vulkan")?;
            let instance = hal.shared_instance();
            PatchexCreateInfo::new(
                instance.raw_instance().handle(),
                hal.raw_physical_device(),
                hal.raw_device().handle(),
                instance.entry().static_fn().get_instance_proc_addr,
                hal.queue_family_index(),
                MAX_EXTENT,
                MAX_EXTENT,
            )
        };
        let mut context = ptr::null_mut();
        // SAFETY: the handles are wgpu's live instance, device and queue family.
        checked(unsafe { patchex_create(&info, &mut context) }, ptr::null())?;
        Ok((Self(context), info.queue_family_index))
    }
}

impl FrameGenerator {
    fn new(device: RenderDevice, adapter: RenderAdapter, check: bool) -> Self {
        let (context, queue_family_index) = match Context::new(device.wgpu_device()) {
            Ok((context, family)) => (Ok(context), family),
            Err(message) => (Err(message), 0),
        };
        Self {
            context,
            queue_family_index,
            check,
            gbuffer: GBufferPass::new(device.wgpu_device()),
            images: None,
            submitted_frames: 0,
            readbacks: Vec::new(),
            failure: None,
            device,
            adapter,
        }
    }

    fn record(
        &mut self,
        instant: DisplayedInstant,
        (view, previous_view, target, prepass): (
            &ExtractedView,
            &PreviousViewData,
            &ViewTarget,
            &ViewPrepassTextures,
        ),
        render_context: &mut RenderContext,
    ) -> Result<(), String> {
        let context = self.context.as_ref().map_err(Clone::clone)?.0;
        let prepasses = Prepasses::of(prepass)?;
        let device = self.device.wgpu_device().clone();
        let size = UVec2::new(prepass.size.width, prepass.size.height);
        if self
            .images
            .as_ref()
            .is_none_or(|images| images.size != size)
        {
            self.images = Some(GBufferImages::new(&device, size));
        }
        let images = self.images.as_ref().expect("made above");

        // 1. The G-buffer pass.
        self.gbuffer.record(
            &device,
            render_context.command_encoder(),
            view,
            previous_view,
            target,
            &prepasses,
            images,
        );

        // 2. patchex.
        let adapter = &self.adapter;
        let owned =
            |image: &OwnedImage, layout| describe(adapter, &image.texture, &image.view, layout);
        let cached = |image: &CachedTexture, layout| {
            describe(adapter, &image.texture, &image.default_view, layout)
        };
        let geometry = PatchexGeometry {
            depth: cached(prepasses.depth, SAMPLED_DEPTH),
            normal: cached(prepasses.normals, SAMPLED),
            normal_encoding: PATCHEX_NORMAL_UNORM,
            stencil: owned(&images.object_id, STORAGE),
            motion_vectors: cached(prepasses.motion_vectors, SAMPLED),
            // Bevy's motion vectors run forward (current minus previous position) in UV units.
            motion_vector_scale: [-(size.x as f32), -(size.y as f32)],
            camera: interop::camera(view),
        };
        let generated_instant = instant.is_generated();
        let (commands, result) = if generated_instant {
            let desc = PatchexExtrapolateDesc {
                header: PatchexStructHeader::of::<PatchexExtrapolateDesc>(
                    PATCHEX_STRUCT_TYPE_EXTRAPOLATE_DESC,
                ),
                queue_family_index: self.queue_family_index,
                alpha: 0.5,
                width: size.x,
                height: size.y,
                base_color: owned(&images.base_color, STORAGE),
                material: owned(&images.material, STORAGE),
                geometry,
                output: owned(&images.generated, STORAGE),
            };
            // SAFETY: every image is live until this frame has executed, in the layout given.
            interop::record_raw(&device, |cmd| unsafe {
                patchex_extrapolate(context, cmd, &desc)
            })?
        } else {
            let desc = PatchexFrameDesc {
                header: PatchexStructHeader::of::<PatchexFrameDesc>(PATCHEX_STRUCT_TYPE_FRAME_DESC),
                frame_index: self.submitted_frames,
                reset: (self.submitted_frames == 0) as PatchexBool,
                queue_family_index: self.queue_family_index,
                width: size.x,
                height: size.y,
                color: describe(
                    adapter,
                    target.main_texture(),
                    target.main_texture_view(),
                    SAMPLED,
                ),
                base_color: owned(&images.base_color, STORAGE),
                material: owned(&images.material, STORAGE),
                // A rendered frame's motion points at the generated instant before it, not at
                // the frame before: patchex does not need it.
                geometry: PatchexGeometry {
                    motion_vectors: PatchexImage::default(),
                    ..geometry
                },
            };
            // SAFETY: as above.
            interop::record_raw(&device, |cmd| unsafe {
                patchex_submit_gbuffers(context, cmd, &desc)
            })?
        };
        checked(result, context)?;
        if result == PatchexResult::RenderInstead {
            // A game would render this instant instead; the example's camera never cuts.
            return Err("patchex asks for a generated instant to be rendered: a camera cut".into());
        }
        render_context.add_command_buffer(commands);
        if !generated_instant {
            self.submitted_frames += 1;
        }

        // 3. Show the generated frame; in check mode copy out what is scored first.
        let encoder = render_context.command_encoder();
        let colour = target.main_texture();
        if self.check {
            let what = if generated_instant {
                Readback::Truth
            } else {
                Readback::Rendered
            };
            self.readbacks
                .push(copy_out(&device, encoder, colour, what));
        }
        if generated_instant {
            let generated = &images.generated.texture;
            if self.check {
                self.readbacks
                    .push(copy_out(&device, encoder, generated, Readback::Generated));
            }
            encoder.copy_texture_to_texture(
                generated.as_image_copy(),
                colour.as_image_copy(),
                generated.size(),
            );
        }
        Ok(())
    }

    /// patchex's statistics of the last submitted frame and its extrapolation: call once the
    /// GPU has finished them.
    pub fn last_frame_stats(&self) -> Result<PatchexFrameStats, String> {
        let context = self.context.as_ref().map_err(Clone::clone)?.0;
        let frame_index = self
            .submitted_frames
            .checked_sub(1)
            .ok_or("no frame submitted yet")?;
        // SAFETY: every field is a number or a null pointer, for which zero is valid.
        let mut stats: PatchexFrameStats = unsafe { std::mem::zeroed() };
        stats.header =
            PatchexStructHeader::of::<PatchexFrameStats>(PATCHEX_STRUCT_TYPE_FRAME_STATS);
        // SAFETY: the context is live and `stats` writable.
        checked(
            unsafe { patchex_get_frame_stats(context, frame_index, &mut stats) },
            context,
        )?;
        Ok(stats)
    }
}

fn generate_frames(
    view: ViewQuery<(
        &ExtractedView,
        &PreviousViewData,
        &ViewTarget,
        &ViewPrepassTextures,
    )>,
    instant: Res<DisplayedInstant>,
    mut generator: ResMut<FrameGenerator>,
    mut render_context: RenderContext,
) {
    if instant.0.is_none() || generator.failure.is_some() {
        return;
    }
    if let Err(failure) = generator.record(*instant, view.into_inner(), &mut render_context) {
        generator.failure = Some(failure);
    }
}

fn checked(result: PatchexResult, context: *const PatchexContext) -> Result<(), String> {
    if result as i32 >= 0 {
        return Ok(());
    }
    // SAFETY: context is null or live; the message is valid until the next call.
    let message = unsafe { CStr::from_ptr(patchex_last_error(context)) };
    Err(format!("patchex: {}", message.to_string_lossy()))
}

/// Copies an RGBA16F texture into a new mappable buffer.
fn copy_out(
    device: &wgpu::Device,
    encoder: &mut wgpu::CommandEncoder,
    texture: &wgpu::Texture,
    what: Readback,
) -> ReadbackBuffer {
    let (width, height) = (texture.width(), texture.height());
    let bytes_per_row = (width * 8).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("patchex check readback"),
        size: u64::from(bytes_per_row * height),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(bytes_per_row),
                rows_per_image: None,
            },
        },
        texture.size(),
    );
    ReadbackBuffer {
        what,
        buffer,
        width,
        height,
        bytes_per_row,
    }
}
