//! patchex inside Bevy's render schedule. Every camera frame, after Bevy's main pass and before
//! its post-processing, one system:
//! 1. makes what patchex reads and Bevy does not write as such: base colour and material from
//!    Bevy's deferred G-buffer, and a dynamic-object id from its motion vectors (a wgpu compute
//!    pass that also fixes every image's layout, see `gbuffer.wgsl`);
//! 2. records patchex's passes into a command buffer of their own, through wgpu's Vulkan interop:
//!    on an even displayed instant it submits the rendered frame, on an odd one it extrapolates
//!    the instant from the frame before and its G-buffers;
//! 3. on a generated instant, copies patchex's output over the view's colour, so that Bevy's
//!    post-processing and display show it; in check mode it first copies both out for scoring.
//!
//! Outside check mode Bevy's main pass (lighting and shading) does not run on generated instants:
//! the prepasses (depth, normals, motion vectors, the deferred G-buffer) are all patchex needs.

use std::ffi::CStr;
use std::ptr;

use ash::vk;
use bevy::core_pipeline::prepass::{PreviousViewData, ViewPrepassTextures};
use bevy::core_pipeline::schedule::{Core3d, Core3dSystems};
use bevy::prelude::*;
use bevy::render::RenderApp;
use bevy::render::extract_resource::{ExtractResource, ExtractResourcePlugin};
use bevy::render::render_resource::{Texture, TextureView};
use bevy::render::renderer::{RenderContext, RenderDevice, ViewQuery};
use bevy::render::view::{ExtractedView, ViewTarget};
use patchex::abi::*;
use patchex::error::PatchexResult;
use patchex::ffi::{
    PatchexContext, patchex_create, patchex_destroy, patchex_extrapolate, patchex_get_frame_stats,
    patchex_last_error, patchex_submit_gbuffers,
};
use wgpu::hal::api::Vulkan;
use wgpu::util::DeviceExt;

/// The largest frame the patchex context is created for.
const MAX_EXTENT: u32 = 3840;

/// A pixel whose motion differs from its surface's under the camera alone by more than this, in
/// pixels, shows a moving object. Half-float UV motion vectors hold a few hundredths of a pixel.
const DYNAMIC_THRESHOLD_PIXELS: f32 = 0.25;

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
        let device = render_app.world().resource::<RenderDevice>().clone();
        let generator = FrameGenerator::new(device, self.check);
        render_app.insert_resource(generator);
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
    device: RenderDevice,
    check: bool,
    /// `Err` when patchex could not be created; reported by the main loop.
    context: Result<Context, String>,
    queue_family_index: u32,
    unpack: wgpu::ComputePipeline,
    unpack_layout: wgpu::BindGroupLayout,
    images: Option<WorkingImages>,
    submitted_frames: u64,
    pub readbacks: Vec<ReadbackBuffer>,
    /// The first failure: the main loop stops on it.
    pub failure: Option<String>,
}

/// A patchex context. patchex contexts may move between threads between calls; Bevy's render
/// world calls it from one system at a time.
struct Context(*mut PatchexContext);
// SAFETY: see above: calls never overlap, and the context has no thread affinity.
unsafe impl Send for Context {}
// SAFETY: shared references are never used to call into the context.
unsafe impl Sync for Context {}

impl Drop for Context {
    fn drop(&mut self) {
        // SAFETY: the context is live, and the device outlives it (FrameGenerator holds it and
        // drops it after this field has been dropped).
        unsafe { patchex_destroy(self.0) };
    }
}

/// Images the example owns, at the view's size: the unpacked G-buffer and patchex's output.
struct WorkingImages {
    size: UVec2,
    base_color: Texture,
    material: Texture,
    object_id: Texture,
    generated: Texture,
    base_color_view: TextureView,
    material_view: TextureView,
    object_id_view: TextureView,
    generated_view: TextureView,
}

impl FrameGenerator {
    fn new(device: RenderDevice, check: bool) -> Self {
        let wgpu_device = device.wgpu_device();
        // SAFETY: only handles are read; wgpu keeps them alive with the device.
        let raw = unsafe {
            wgpu_device.as_hal::<Vulkan>().map(|hal| {
                let instance = hal.shared_instance();
                (
                    instance.raw_instance().handle(),
                    hal.raw_physical_device(),
                    hal.raw_device().handle(),
                    instance.entry().static_fn().get_instance_proc_addr,
                    hal.queue_family_index(),
                )
            })
        };
        let (context, queue_family_index) = match raw {
            None => (Err("Bevy is not rendering through Vulkan".to_owned()), 0),
            Some((instance, physical_device, raw_device, get_instance_proc_addr, family)) => {
                let info = PatchexCreateInfo::new(
                    instance,
                    physical_device,
                    raw_device,
                    get_instance_proc_addr,
                    family,
                    MAX_EXTENT,
                    MAX_EXTENT,
                );
                let mut context = ptr::null_mut();
                // SAFETY: the handles are wgpu's live instance, device and queue family.
                let result = unsafe { patchex_create(&info, &mut context) };
                (
                    checked(result, ptr::null()).map(|()| Context(context)),
                    family,
                )
            }
        };

        let shader = wgpu_device.create_shader_module(wgpu::include_wgsl!("gbuffer.wgsl"));
        let sampled = |binding, sample_type| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Texture {
                sample_type,
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        };
        let storage = |binding, format| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::StorageTexture {
                access: wgpu::StorageTextureAccess::WriteOnly,
                format,
                view_dimension: wgpu::TextureViewDimension::D2,
            },
            count: None,
        };
        let float = wgpu::TextureSampleType::Float { filterable: false };
        let unpack_layout =
            wgpu_device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("patchex G-buffer unpack"),
                entries: &[
                    sampled(0, wgpu::TextureSampleType::Uint),
                    sampled(1, wgpu::TextureSampleType::Depth),
                    sampled(2, float),
                    sampled(3, float),
                    sampled(4, float),
                    storage(5, wgpu::TextureFormat::Rgba8Unorm),
                    storage(6, wgpu::TextureFormat::Rgba8Unorm),
                    storage(7, wgpu::TextureFormat::R8Uint),
                    storage(8, wgpu::TextureFormat::Rgba16Float),
                    wgpu::BindGroupLayoutEntry {
                        binding: 9,
                        visibility: wgpu::ShaderStages::COMPUTE,
                        ty: wgpu::BindingType::Buffer {
                            ty: wgpu::BufferBindingType::Uniform,
                            has_dynamic_offset: false,
                            min_binding_size: None,
                        },
                        count: None,
                    },
                ],
            });
        let pipeline_layout = wgpu_device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("patchex G-buffer unpack"),
            bind_group_layouts: &[Some(&unpack_layout)],
            immediate_size: 0,
        });
        let unpack = wgpu_device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("patchex G-buffer unpack"),
            layout: Some(&pipeline_layout),
            module: &shader,
            entry_point: Some("unpack"),
            compilation_options: Default::default(),
            cache: None,
        });

        Self {
            device,
            check,
            context,
            queue_family_index,
            unpack,
            unpack_layout,
            images: None,
            submitted_frames: 0,
            readbacks: Vec::new(),
            failure: None,
        }
    }

    /// The images at `size`, made anew when the view's size changes.
    fn images(&mut self, size: UVec2) -> &WorkingImages {
        if self
            .images
            .as_ref()
            .is_none_or(|images| images.size != size)
        {
            let make = |label, format, usage| {
                let texture = self.device.create_texture(&wgpu::TextureDescriptor {
                    label: Some(label),
                    size: wgpu::Extent3d {
                        width: size.x,
                        height: size.y,
                        depth_or_array_layers: 1,
                    },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format,
                    usage,
                    view_formats: &[],
                });
                let view = texture.create_view(&Default::default());
                (texture, view)
            };
            let unpacked =
                wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING;
            let (base_color, base_color_view) = make(
                "patchex base colour",
                wgpu::TextureFormat::Rgba8Unorm,
                unpacked,
            );
            let (material, material_view) = make(
                "patchex material",
                wgpu::TextureFormat::Rgba8Unorm,
                unpacked,
            );
            let (object_id, object_id_view) =
                make("patchex object id", wgpu::TextureFormat::R8Uint, unpacked);
            let (generated, generated_view) = make(
                "patchex output",
                wgpu::TextureFormat::Rgba16Float,
                wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::COPY_SRC,
            );
            self.images = Some(WorkingImages {
                size,
                base_color,
                material,
                object_id,
                generated,
                base_color_view,
                material_view,
                object_id_view,
                generated_view,
            });
        }
        self.images.as_ref().expect("made above")
    }

    fn record(
        &mut self,
        instant: DisplayedInstant,
        view: &ExtractedView,
        previous_view: &PreviousViewData,
        target: &ViewTarget,
        prepass: &ViewPrepassTextures,
        render_context: &mut RenderContext,
    ) -> Result<(), String> {
        let (Some(depth), Some(normals), Some(motion), Some(deferred)) = (
            &prepass.depth,
            &prepass.normal,
            &prepass.motion_vectors,
            &prepass.deferred,
        ) else {
            return Err(
                "the camera needs DepthPrepass, NormalPrepass, MotionVectorPrepass and \
                        DeferredPrepass"
                    .to_owned(),
            );
        };
        let context = self.context.as_ref().map_err(Clone::clone)?.0;
        let size = UVec2::new(prepass.size.width, prepass.size.height);
        let generated_instant = instant.is_generated();
        let check = self.check;
        let queue_family_index = self.queue_family_index;
        let frame_index = self.submitted_frames;
        let device = self.device.clone();
        let layout = self.unpack_layout.clone();
        let pipeline = self.unpack.clone();
        let images = self.images(size);

        // 1. Make base colour, material and object ids; every image patchex touches is bound, to
        // fix its layout.
        let world_from_clip = view.world_from_view.to_matrix() * view.clip_from_view.inverse();
        let mut cameras = [0.0f32; 36];
        cameras[..16].copy_from_slice(&world_from_clip.to_cols_array());
        cameras[16..32].copy_from_slice(&previous_view.clip_from_world.to_cols_array());
        cameras[32] = DYNAMIC_THRESHOLD_PIXELS;
        let cameras = device
            .wgpu_device()
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("patchex G-buffer unpack cameras"),
                contents: &cameras
                    .iter()
                    .flat_map(|v| v.to_le_bytes())
                    .collect::<Vec<u8>>(),
                usage: wgpu::BufferUsages::UNIFORM,
            });
        let bind_group = device
            .wgpu_device()
            .create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("patchex G-buffer unpack"),
                layout: &layout,
                entries: &[
                    entry(0, &deferred.texture.default_view),
                    entry(1, &depth.texture.default_view),
                    entry(2, &normals.texture.default_view),
                    entry(3, &motion.texture.default_view),
                    entry(4, target.main_texture_view()),
                    entry(5, &images.base_color_view),
                    entry(6, &images.material_view),
                    entry(7, &images.object_id_view),
                    entry(8, &images.generated_view),
                    wgpu::BindGroupEntry {
                        binding: 9,
                        resource: cameras.as_entire_binding(),
                    },
                ],
            });
        {
            let mut pass = render_context
                .command_encoder()
                .begin_compute_pass(&Default::default());
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.dispatch_workgroups(size.x.div_ceil(8), size.y.div_ceil(8), 1);
        }

        // 2. patchex, in a command buffer of its own: wgpu does not let an encoder mix its own
        // commands with raw ones.
        let sampled = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
        let storage = vk::ImageLayout::GENERAL;
        let geometry = PatchexGeometry {
            depth: describe(
                &depth.texture.texture,
                &depth.texture.default_view,
                vk::ImageLayout::DEPTH_STENCIL_READ_ONLY_OPTIMAL,
            ),
            normal: describe(
                &normals.texture.texture,
                &normals.texture.default_view,
                sampled,
            ),
            normal_encoding: PATCHEX_NORMAL_UNORM,
            stencil: describe(&images.object_id, &images.object_id_view, storage),
            motion_vectors: describe(
                &motion.texture.texture,
                &motion.texture.default_view,
                sampled,
            ),
            // Bevy's motion vectors run forward (current minus previous position) in UV units.
            motion_vector_scale: [-(size.x as f32), -(size.y as f32)],
            camera: camera(view),
        };
        let base_color = describe(&images.base_color, &images.base_color_view, storage);
        let material = describe(&images.material, &images.material_view, storage);
        let mut encoder =
            device
                .wgpu_device()
                .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("patchex"),
                });
        let result = if generated_instant {
            let desc = PatchexExtrapolateDesc {
                header: PatchexStructHeader::of::<PatchexExtrapolateDesc>(
                    PATCHEX_STRUCT_TYPE_EXTRAPOLATE_DESC,
                ),
                queue_family_index,
                alpha: 0.5,
                width: size.x,
                height: size.y,
                base_color,
                material,
                geometry,
                output: describe(&images.generated, &images.generated_view, storage),
            };
            // SAFETY: every image is live until this frame has executed, in the layout given.
            record_raw(&mut encoder, |cmd| unsafe {
                patchex_extrapolate(context, cmd, &desc)
            })
        } else {
            let desc = PatchexFrameDesc {
                header: PatchexStructHeader::of::<PatchexFrameDesc>(PATCHEX_STRUCT_TYPE_FRAME_DESC),
                frame_index,
                reset: (frame_index == 0) as PatchexBool,
                queue_family_index,
                width: size.x,
                height: size.y,
                color: describe(target.main_texture(), target.main_texture_view(), sampled),
                base_color,
                material,
                // A submitted frame's motion points at the generated instant before it, not at
                // the frame before: patchex does not need it.
                geometry: PatchexGeometry {
                    motion_vectors: PatchexImage::default(),
                    ..geometry
                },
            };
            // SAFETY: as above.
            record_raw(&mut encoder, |cmd| unsafe {
                patchex_submit_gbuffers(context, cmd, &desc)
            })
        };
        checked_in(result, context)?;
        render_context.add_command_buffer(encoder.finish());
        if !generated_instant {
            self.submitted_frames += 1;
        }

        // 3. Show the generated frame; in check mode copy out what is scored.
        let images = self.images.as_ref().expect("made above");
        let encoder = render_context.command_encoder();
        let mut readbacks = Vec::new();
        if check {
            let what = if generated_instant {
                Readback::Truth
            } else {
                Readback::Rendered
            };
            readbacks.push(copy_out(&device, encoder, target.main_texture(), what));
        }
        if generated_instant {
            if check {
                readbacks.push(copy_out(
                    &device,
                    encoder,
                    &images.generated,
                    Readback::Generated,
                ));
            }
            encoder.copy_texture_to_texture(
                images.generated.as_image_copy(),
                target.main_texture().as_image_copy(),
                images.generated.size(),
            );
        }
        self.readbacks.extend(readbacks);
        Ok(())
    }
}

impl FrameGenerator {
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
    let (view, previous_view, target, prepass) = view.into_inner();
    if let Err(failure) = generator.record(
        *instant,
        view,
        previous_view,
        target,
        prepass,
        &mut render_context,
    ) {
        generator.failure = Some(failure);
    }
}

/// Records into `encoder`'s Vulkan command buffer.
fn record_raw(
    encoder: &mut wgpu::CommandEncoder,
    record: impl FnOnce(vk::CommandBuffer) -> PatchexResult,
) -> Result<PatchexResult, String> {
    // SAFETY: the command buffer is only recorded into, and the encoder is not used meanwhile.
    unsafe {
        encoder.as_hal_mut::<Vulkan, _, _>(|hal| {
            hal.map(|hal| record(hal.raw_handle()))
                .ok_or_else(|| "wgpu's encoder is not a Vulkan one".to_owned())
        })
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

fn checked_in(
    result: Result<PatchexResult, String>,
    context: *mut PatchexContext,
) -> Result<(), String> {
    checked(result?, context)
}

fn entry<'a>(binding: u32, view: &'a wgpu::TextureView) -> wgpu::BindGroupEntry<'a> {
    wgpu::BindGroupEntry {
        binding,
        resource: wgpu::BindingResource::TextureView(view),
    }
}

/// A wgpu texture as patchex imports it, in `layout` when patchex's commands run.
fn describe(
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
        format: vk_format(texture.format()),
        width: texture.width(),
        height: texture.height(),
        layout,
        usage: vk_usage(texture),
    }
}

/// The Vulkan formats wgpu gives the textures the example hands to patchex.
fn vk_format(format: wgpu::TextureFormat) -> vk::Format {
    match format {
        wgpu::TextureFormat::Rgba16Float => vk::Format::R16G16B16A16_SFLOAT,
        wgpu::TextureFormat::Rgba8Unorm => vk::Format::R8G8B8A8_UNORM,
        wgpu::TextureFormat::R8Uint => vk::Format::R8_UINT,
        wgpu::TextureFormat::Rgb10a2Unorm => vk::Format::A2B10G10R10_UNORM_PACK32,
        wgpu::TextureFormat::Rg16Float => vk::Format::R16G16_SFLOAT,
        wgpu::TextureFormat::Depth32Float => vk::Format::D32_SFLOAT,
        // patchex answers an unsupported format with a clear error.
        _ => vk::Format::UNDEFINED,
    }
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
        (
            wgpu::TextureUsages::RENDER_ATTACHMENT,
            vk::ImageUsageFlags::COLOR_ATTACHMENT,
        ),
    ] {
        if usage.contains(wgpu_usage) {
            flags |= vk_usage;
        }
    }
    if texture.format().is_depth_stencil_format() {
        flags &= !vk::ImageUsageFlags::COLOR_ATTACHMENT;
        flags |= vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT;
    } else if !usage.contains(wgpu::TextureUsages::COPY_DST) {
        flags |= vk::ImageUsageFlags::COLOR_ATTACHMENT;
    }
    flags
}

/// The view's camera in patchex's conventions. Bevy projects with an infinite reversed-Z
/// perspective into wgpu's clip space, whose y points up: patchex's (Vulkan's) points down.
fn camera(view: &ExtractedView) -> PatchexCamera {
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

/// Copies an RGBA16F texture into a new mappable buffer.
fn copy_out(
    device: &RenderDevice,
    encoder: &mut wgpu::CommandEncoder,
    texture: &wgpu::Texture,
    what: Readback,
) -> ReadbackBuffer {
    let (width, height) = (texture.width(), texture.height());
    let bytes_per_row = (width * 8).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
    let buffer = device.wgpu_device().create_buffer(&wgpu::BufferDescriptor {
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
