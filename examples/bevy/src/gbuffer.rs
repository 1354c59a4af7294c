//! The pass that makes what patchex reads and Bevy does not write as such (`gbuffer.wgsl`): base
//! colour and material from Bevy's deferred G-buffer, and a dynamic-object id from its motion
//! vectors. It binds every other image patchex touches afterwards, so that wgpu leaves each in a
//! layout the example knows (`interop::SAMPLED`, `SAMPLED_DEPTH`, `STORAGE`).

use bevy::core_pipeline::prepass::{PreviousViewData, ViewPrepassTextures};
use bevy::math::UVec2;
use bevy::render::texture::CachedTexture;
use bevy::render::view::{ExtractedView, ViewTarget};
use wgpu::util::DeviceExt;

/// A pixel whose motion differs from its surface's under the camera alone by more than this, in
/// pixels, shows a moving object. Half-float UV motion vectors hold a few hundredths of a pixel.
const DYNAMIC_THRESHOLD_PIXELS: f32 = 0.25;

/// The prepasses patchex and this pass read.
pub struct Prepasses<'a> {
    pub depth: &'a CachedTexture,
    pub normals: &'a CachedTexture,
    pub motion_vectors: &'a CachedTexture,
    pub deferred: &'a CachedTexture,
}

impl<'a> Prepasses<'a> {
    pub fn of(prepass: &'a ViewPrepassTextures) -> Result<Self, String> {
        match (
            &prepass.depth,
            &prepass.normal,
            &prepass.motion_vectors,
            &prepass.deferred,
        ) {
            (Some(depth), Some(normals), Some(motion_vectors), Some(deferred)) => Ok(Self {
                depth: &depth.texture,
                normals: &normals.texture,
                motion_vectors: &motion_vectors.texture,
                deferred: &deferred.texture,
            }),
            _ => Err(
                "the camera needs DepthPrepass, NormalPrepass, MotionVectorPrepass and \
                      DeferredPrepass"
                    .to_owned(),
            ),
        }
    }
}

/// A texture the example owns, and its view.
pub struct OwnedImage {
    pub texture: wgpu::Texture,
    pub view: wgpu::TextureView,
}

/// The pass's outputs at the view's size, and patchex's output.
pub struct GBufferImages {
    pub size: UVec2,
    pub base_color: OwnedImage,
    pub material: OwnedImage,
    pub object_id: OwnedImage,
    pub generated: OwnedImage,
}

impl GBufferImages {
    pub fn new(device: &wgpu::Device, size: UVec2) -> Self {
        let image = |label, format, usage| {
            let texture = device.create_texture(&wgpu::TextureDescriptor {
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
            OwnedImage { texture, view }
        };
        let unpacked = wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING;
        Self {
            size,
            base_color: image(
                "patchex base colour",
                wgpu::TextureFormat::Rgba8Unorm,
                unpacked,
            ),
            material: image(
                "patchex material",
                wgpu::TextureFormat::Rgba8Unorm,
                unpacked,
            ),
            object_id: image("patchex object id", wgpu::TextureFormat::R8Uint, unpacked),
            generated: image(
                "patchex output",
                wgpu::TextureFormat::Rgba16Float,
                wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::COPY_SRC,
            ),
        }
    }
}

pub struct GBufferPass {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
}

impl GBufferPass {
    pub fn new(device: &wgpu::Device) -> Self {
        let entry = |binding, ty| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty,
            count: None,
        };
        let sampled = |binding, sample_type| {
            entry(
                binding,
                wgpu::BindingType::Texture {
                    sample_type,
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
            )
        };
        let storage = |binding, format| {
            entry(
                binding,
                wgpu::BindingType::StorageTexture {
                    access: wgpu::StorageTextureAccess::WriteOnly,
                    format,
                    view_dimension: wgpu::TextureViewDimension::D2,
                },
            )
        };
        let float = wgpu::TextureSampleType::Float { filterable: false };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("patchex G-buffer"),
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
                entry(
                    9,
                    wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                ),
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("patchex G-buffer"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("patchex G-buffer"),
            layout: Some(&pipeline_layout),
            module: &device.create_shader_module(wgpu::include_wgsl!("gbuffer.wgsl")),
            entry_point: Some("unpack"),
            compilation_options: Default::default(),
            cache: None,
        });
        Self { pipeline, layout }
    }

    #[allow(clippy::too_many_arguments)]
    pub fn record(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        view: &ExtractedView,
        previous_view: &PreviousViewData,
        target: &ViewTarget,
        prepasses: &Prepasses,
        images: &GBufferImages,
    ) {
        // The shader's `Cameras`: this instant's clip to world, the previous instant's world to
        // clip, the threshold (and padding).
        let world_from_clip = view.world_from_view.to_matrix() * view.clip_from_view.inverse();
        let cameras: Vec<u8> = world_from_clip
            .to_cols_array()
            .into_iter()
            .chain(previous_view.clip_from_world.to_cols_array())
            .chain([DYNAMIC_THRESHOLD_PIXELS, 0.0, 0.0, 0.0])
            .flat_map(f32::to_le_bytes)
            .collect();
        let cameras = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("patchex G-buffer cameras"),
            contents: &cameras,
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let texture = |binding, view| wgpu::BindGroupEntry {
            binding,
            resource: wgpu::BindingResource::TextureView(view),
        };
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("patchex G-buffer"),
            layout: &self.layout,
            entries: &[
                texture(0, &prepasses.deferred.default_view),
                texture(1, &prepasses.depth.default_view),
                texture(2, &prepasses.normals.default_view),
                texture(3, &prepasses.motion_vectors.default_view),
                texture(4, target.main_texture_view()),
                texture(5, &images.base_color.view),
                texture(6, &images.material.view),
                texture(7, &images.object_id.view),
                texture(8, &images.generated.view),
                wgpu::BindGroupEntry {
                    binding: 9,
                    resource: cameras.as_entire_binding(),
                },
            ],
        });
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.dispatch_workgroups(images.size.x.div_ceil(8), images.size.y.div_ceil(8), 1);
    }
}
