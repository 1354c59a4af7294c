//! Owns the GPU side of one world at one resolution and renders frames from it.

use super::forward_pass::{record_forward_pass, ForwardInputs};
use super::gbuffer_pass::{record_gbuffer_pass, GBufferInputs};
use super::gpu_batch::GpuBatch;
use super::materials::GpuMaterials;
use super::particle_pass::draw_particles;
use super::pipelines::Pipelines;
use super::resolve_pass::record_resolve_pass;
use super::shadow_pass::{record_shadow_pass, SHADOW_READERS};
use super::targets::{
    shadow_map, ForwardTargets, GBufferTargets, FORWARD_TARGETS, GBUFFER_TARGETS,
};
use super::timings::{Mark, PassTimer, PassTimings};
use super::translucent_layer::TranslucentLayer;
use super::uniforms::FrameUniforms;
use crate::dataset::{FrameLayers, PLANE_COUNT, SCENE_DEPTH};
use crate::error::{Result, VkContext};
use crate::gpu::{Buffer, Gpu, Image};
use crate::scene::{CameraState, World};
use ash::vk;
use std::sync::Arc;

/// What to render: the instant, the previous instant (for motion vectors), and whether to
/// light the frame or only fill the G-buffers (as an engine does for extrapolated instants).
#[derive(Clone, Copy, Debug)]
pub struct FrameRequest {
    pub time: f32,
    pub previous_time: f32,
    pub camera: CameraState,
    pub previous_camera: CameraState,
    pub lighting: bool,
}

impl FrameRequest {
    pub fn at(world: &World, time: f32, previous_time: f32, aspect: f32, lighting: bool) -> Self {
        Self {
            time,
            previous_time,
            camera: world.camera(time, aspect),
            previous_camera: world.camera(previous_time, aspect),
            lighting,
        }
    }
}

pub struct Renderer {
    width: u32,
    height: u32,
    descriptor_pool: vk::DescriptorPool,
    frame_set: vk::DescriptorSet,
    resolve_set: vk::DescriptorSet,
    shadow_maps_set: vk::DescriptorSet,
    frame_uniforms: Buffer,
    planes: Buffer,
    static_batch: GpuBatch,
    dynamic_batch: GpuBatch,
    materials: GpuMaterials,
    targets: GBufferTargets,
    /// Made only for worlds with blended surfaces.
    forward_targets: Option<ForwardTargets>,
    static_shadow: Image,
    dynamic_shadow: Image,
    pipelines: Pipelines,
    timer: Option<PassTimer>,
    last_timings: Option<PassTimings>,
    gpu: Arc<Gpu>,
}

impl Renderer {
    pub fn new(gpu: &Arc<Gpu>, world: &World, width: u32, height: u32) -> Result<Self> {
        let pipelines = Pipelines::new(gpu)?;
        let materials = GpuMaterials::new(
            gpu,
            pipelines.material_layout,
            &world.materials,
            &world.textures,
        )?;
        let static_batch = GpuBatch::new(gpu, &world.static_batch, &world.materials)?;
        let dynamic_batch = GpuBatch::new(gpu, &world.dynamic_batch, &world.materials)?;
        let targets = GBufferTargets::new(gpu, width, height)?;
        let forward_targets = if static_batch.blended.is_empty() && dynamic_batch.blended.is_empty()
        {
            None
        } else {
            Some(ForwardTargets::new(gpu, width, height)?)
        };
        let static_shadow = shadow_map(gpu, world.sun.shadow_resolution)?;
        let dynamic_shadow = shadow_map(gpu, world.sun.shadow_resolution)?;
        let frame_uniforms = Buffer::new(
            gpu,
            std::mem::size_of::<FrameUniforms>() as u64,
            vk::BufferUsageFlags::UNIFORM_BUFFER,
            "frame uniforms",
        )?;
        let planes = Buffer::new(
            gpu,
            (PLANE_COUNT * width as usize * height as usize * 4) as u64,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            "layer planes",
        )?;

        let pool_sizes = [
            vk::DescriptorPoolSize {
                ty: vk::DescriptorType::UNIFORM_BUFFER,
                descriptor_count: 2,
            },
            vk::DescriptorPoolSize {
                ty: vk::DescriptorType::SAMPLED_IMAGE,
                descriptor_count: 9,
            },
            vk::DescriptorPoolSize {
                ty: vk::DescriptorType::STORAGE_BUFFER,
                descriptor_count: 1,
            },
        ];
        // SAFETY: valid device; the sets are written below with live resources.
        let (descriptor_pool, sets) = unsafe {
            let pool = gpu
                .device
                .create_descriptor_pool(
                    &vk::DescriptorPoolCreateInfo::default()
                        .max_sets(3)
                        .pool_sizes(&pool_sizes),
                    None,
                )
                .vk("vkCreateDescriptorPool")?;
            let layouts = [
                pipelines.frame_layout,
                pipelines.resolve_layout,
                pipelines.shadow_maps_layout,
            ];
            let sets = gpu
                .device
                .allocate_descriptor_sets(
                    &vk::DescriptorSetAllocateInfo::default()
                        .descriptor_pool(pool)
                        .set_layouts(&layouts),
                )
                .vk("vkAllocateDescriptorSets")?;
            (pool, sets)
        };

        let renderer = Self {
            width,
            height,
            descriptor_pool,
            frame_set: sets[0],
            resolve_set: sets[1],
            shadow_maps_set: sets[2],
            frame_uniforms,
            planes,
            static_batch,
            dynamic_batch,
            materials,
            targets,
            forward_targets,
            static_shadow,
            dynamic_shadow,
            pipelines,
            timer: PassTimer::new(gpu)?,
            last_timings: None,
            gpu: gpu.clone(),
        };
        renderer.write_descriptor_sets();
        // Static casters never move, so their shadow map is rendered once.
        gpu.submit_and_wait(|command_buffer| {
            record_shadow_pass(
                gpu,
                command_buffer,
                &renderer.pipelines,
                &renderer.static_shadow,
                &[&renderer.static_batch],
                world.sun.light_view_proj,
                vk::PipelineStageFlags::TOP_OF_PIPE,
            )
        })?;
        Ok(renderer)
    }

    fn write_descriptor_sets(&self) {
        let uniform_info = [vk::DescriptorBufferInfo {
            buffer: self.frame_uniforms.handle,
            offset: 0,
            range: vk::WHOLE_SIZE,
        }];
        let planes_info = [vk::DescriptorBufferInfo {
            buffer: self.planes.handle,
            offset: 0,
            range: vk::WHOLE_SIZE,
        }];
        let views: Vec<vk::ImageView> = self
            .targets
            .color
            .iter()
            .map(|image| image.view)
            .chain([self.static_shadow.view, self.dynamic_shadow.view])
            .collect();
        debug_assert_eq!(views.len(), GBUFFER_TARGETS + 2);
        let image_infos: Vec<[vk::DescriptorImageInfo; 1]> = views
            .iter()
            .map(|&view| {
                [vk::DescriptorImageInfo::default()
                    .image_view(view)
                    .image_layout(vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL)]
            })
            .collect();
        let mut writes = vec![
            vk::WriteDescriptorSet::default()
                .dst_set(self.frame_set)
                .dst_binding(0)
                .descriptor_type(vk::DescriptorType::UNIFORM_BUFFER)
                .buffer_info(&uniform_info),
            vk::WriteDescriptorSet::default()
                .dst_set(self.resolve_set)
                .dst_binding(0)
                .descriptor_type(vk::DescriptorType::UNIFORM_BUFFER)
                .buffer_info(&uniform_info),
            vk::WriteDescriptorSet::default()
                .dst_set(self.resolve_set)
                .dst_binding(8)
                .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                .buffer_info(&planes_info),
        ];
        for (index, info) in image_infos.iter().enumerate() {
            writes.push(
                vk::WriteDescriptorSet::default()
                    .dst_set(self.resolve_set)
                    .dst_binding(index as u32 + 1)
                    .descriptor_type(vk::DescriptorType::SAMPLED_IMAGE)
                    .image_info(info),
            );
        }
        for (binding, info) in image_infos[GBUFFER_TARGETS..].iter().enumerate() {
            writes.push(
                vk::WriteDescriptorSet::default()
                    .dst_set(self.shadow_maps_set)
                    .dst_binding(binding as u32)
                    .descriptor_type(vk::DescriptorType::SAMPLED_IMAGE)
                    .image_info(info),
            );
        }
        // SAFETY: every referenced buffer and view is owned by `self`.
        unsafe { self.gpu.device.update_descriptor_sets(&writes, &[]) };
    }

    /// GPU time of each pass of the last frame; `None` before the first frame or on devices
    /// without timestamps.
    pub fn last_timings(&self) -> Option<PassTimings> {
        self.last_timings
    }

    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// Renders one frame and reads its layers back.
    pub fn render(&mut self, world: &World, request: &FrameRequest) -> Result<FrameLayers> {
        let uniforms = FrameUniforms::new(
            &request.camera,
            &request.previous_camera,
            &world.sun,
            &world.description.sun,
            self.width,
            self.height,
        );
        self.frame_uniforms.write(0, bytemuck::bytes_of(&uniforms));
        if !self.dynamic_batch.is_empty() {
            self.dynamic_batch
                .write_vertices(&world.dynamic_vertices(request.time, request.previous_time));
        }
        let gpu = self.gpu.clone();
        gpu.submit_and_wait(|command_buffer| {
            let mark = |mark: Mark| {
                if let Some(timer) = &self.timer {
                    timer.mark(command_buffer, mark);
                }
            };
            if let Some(timer) = &self.timer {
                timer.reset(command_buffer);
            }
            mark(Mark::Start);
            record_shadow_pass(
                &gpu,
                command_buffer,
                &self.pipelines,
                &self.dynamic_shadow,
                &[&self.dynamic_batch],
                world.sun.light_view_proj,
                SHADOW_READERS,
            );
            mark(Mark::ShadowDone);
            record_gbuffer_pass(
                &gpu,
                command_buffer,
                &GBufferInputs {
                    pipelines: &self.pipelines,
                    targets: &self.targets,
                    frame_set: self.frame_set,
                    gpu_materials: &self.materials,
                    materials: &world.materials,
                    batches: [&self.static_batch, &self.dynamic_batch],
                },
            );
            let forward = self.forward_targets.as_ref().filter(|_| request.lighting);
            if let Some(forward) = forward {
                record_forward_pass(
                    &gpu,
                    command_buffer,
                    &ForwardInputs {
                        pipelines: &self.pipelines,
                        gbuffer: &self.targets,
                        targets: forward,
                        frame_set: self.frame_set,
                        shadow_maps_set: self.shadow_maps_set,
                        gpu_materials: &self.materials,
                        materials: &world.materials,
                        batches: [&self.static_batch, &self.dynamic_batch],
                        camera_position: request.camera.position,
                    },
                );
            }
            mark(Mark::GBufferDone);
            record_resolve_pass(
                &gpu,
                command_buffer,
                &self.pipelines,
                self.resolve_set,
                &self.planes,
                (self.width, self.height),
                request.lighting,
            );
            mark(Mark::ResolveDone);
        })?;
        self.last_timings = self.timer.as_ref().map(PassTimer::read).transpose()?;
        let pixels = self.width as usize * self.height as usize;
        let planes = self.planes.read_f32(PLANE_COUNT * pixels);
        let mut layers = FrameLayers::from_planes(
            &planes,
            self.width as usize,
            self.height as usize,
            request.lighting,
        );
        if request.lighting {
            if let Some(layer) = self.translucent_layer(world, request, &layers) {
                layer.composite(&mut layers);
            }
        }
        Ok(layers)
    }

    /// What the frame draws after lighting: the forward pass's blended surfaces, then the
    /// particles among them; `None` for a world with neither.
    fn translucent_layer(
        &self,
        world: &World,
        request: &FrameRequest,
        layers: &FrameLayers,
    ) -> Option<TranslucentLayer> {
        let (width, height) = (self.width as usize, self.height as usize);
        let mut layer = match &self.forward_targets {
            Some(targets) => TranslucentLayer::from_forward_targets(
                &targets
                    .readback
                    .read_f32(FORWARD_TARGETS * 4 * width * height),
                width,
                height,
            ),
            None if world.description.particles.is_empty() => return None,
            None => TranslucentLayer::new(width, height),
        };
        if !world.description.particles.is_empty() {
            draw_particles(
                &mut layer,
                &layers.layer(SCENE_DEPTH).plane(0),
                &world.particles(request.time, request.previous_time),
                &request.camera,
                &request.previous_camera,
            );
        }
        Some(layer)
    }
}

impl Drop for Renderer {
    fn drop(&mut self) {
        // SAFETY: every submission is waited on, so the pool's sets are no longer in use.
        unsafe {
            let _ = self.gpu.device.device_wait_idle();
            self.gpu
                .device
                .destroy_descriptor_pool(self.descriptor_pool, None);
        }
    }
}
