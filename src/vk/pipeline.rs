//! Compute pipelines built from the shader reflection that build.rs generates, and descriptor
//! writes checked against it.

use ash::vk;

use crate::error::Result;
use crate::shaders::{Binding, DescriptorKind, PushConstants, ShaderInfo};
use crate::vk::access::{Access, Resource, Traffic};
use crate::vk::buffer::CounterRange;
use crate::vk::device::Gpu;
use crate::vk::image::Texture;

pub fn descriptor_type(kind: DescriptorKind) -> vk::DescriptorType {
    match kind {
        DescriptorKind::SampledImage => vk::DescriptorType::SAMPLED_IMAGE,
        DescriptorKind::StorageImage => vk::DescriptorType::STORAGE_IMAGE,
        DescriptorKind::StorageBuffer => vk::DescriptorType::STORAGE_BUFFER,
        DescriptorKind::UniformBuffer => vk::DescriptorType::UNIFORM_BUFFER,
        DescriptorKind::Sampler => vk::DescriptorType::SAMPLER,
    }
}

/// Descriptor counts of one set of each of `pipelines`, together: the size of a pool that holds
/// them.
pub fn pool_sizes<'a>(
    pipelines: impl IntoIterator<Item = &'a ComputePipeline>,
) -> Vec<vk::DescriptorPoolSize> {
    let mut sizes: Vec<vk::DescriptorPoolSize> = Vec::new();
    for pipeline in pipelines {
        for binding in pipeline.shader.bindings {
            let ty = descriptor_type(binding.kind);
            match sizes.iter_mut().find(|s| s.ty == ty) {
                Some(size) => size.descriptor_count += 1,
                None => sizes.push(vk::DescriptorPoolSize {
                    ty,
                    descriptor_count: 1,
                }),
            }
        }
    }
    sizes
}

/// The compute pipeline of `spirv`'s `main` under `layout`; the shader module lives only as
/// long as the creation needs it.
///
/// # Safety
/// `device` is a live device; `spirv` is valid code whose interface `layout` matches.
pub unsafe fn create_compute_pipeline(
    device: &ash::Device,
    layout: vk::PipelineLayout,
    spirv: &[u32],
) -> std::result::Result<vk::Pipeline, vk::Result> {
    let module =
        device.create_shader_module(&vk::ShaderModuleCreateInfo::default().code(spirv), None)?;
    let stage = vk::PipelineShaderStageCreateInfo::default()
        .stage(vk::ShaderStageFlags::COMPUTE)
        .module(module)
        .name(c"main");
    let created = device.create_compute_pipelines(
        vk::PipelineCache::null(),
        &[vk::ComputePipelineCreateInfo::default()
            .stage(stage)
            .layout(layout)],
        None,
    );
    device.destroy_shader_module(module, None);
    Ok(created.map_err(|(_, result)| result)?[0])
}

/// One pass's pipeline, its layout and its descriptor-set layout.
pub struct ComputePipeline {
    pub shader: ShaderInfo,
    pub set_layout: vk::DescriptorSetLayout,
    layout: vk::PipelineLayout,
    pipeline: vk::Pipeline,
    /// `gather_sampler`, fixed in the set layout, where the shader declares a sampler.
    sampler: vk::Sampler,
}

/// The one sampler passes use: it neither filters nor wraps, so a gather returns the four texels
/// that four loads clamped to the image would.
fn gather_sampler() -> vk::SamplerCreateInfo<'static> {
    vk::SamplerCreateInfo::default()
        .mag_filter(vk::Filter::NEAREST)
        .min_filter(vk::Filter::NEAREST)
        .mipmap_mode(vk::SamplerMipmapMode::NEAREST)
        .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_EDGE)
        .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
        .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE)
        .max_lod(0.0)
}

impl ComputePipeline {
    pub fn new(gpu: &Gpu, shader: ShaderInfo) -> Result<Self> {
        Self::from_spirv(gpu, shader, shader.spirv)
    }

    /// A pipeline whose code was made at run time; `shader` gives its reflection.
    pub fn from_spirv(gpu: &Gpu, shader: ShaderInfo, spirv: &[u32]) -> Result<Self> {
        let device = &gpu.device;
        let mut pipeline = Self {
            shader,
            set_layout: vk::DescriptorSetLayout::null(),
            layout: vk::PipelineLayout::null(),
            pipeline: vk::Pipeline::null(),
            sampler: vk::Sampler::null(),
        };
        // SAFETY: valid device; on any failure the partly built pipeline is destroyed, and
        // destroying null handles is a no-op.
        let built = unsafe { pipeline.build(device, spirv) };
        match built {
            Ok(()) => Ok(pipeline),
            Err(error) => {
                pipeline.destroy(device);
                Err(error.during(format_args!("creating the {} pipeline", shader.name)))
            }
        }
    }

    /// Creates the sampler, layouts and pipeline into `self`, leaving what failed null.
    ///
    /// # Safety
    /// `device` is a live device; `spirv` is valid code for `self.shader`.
    unsafe fn build(&mut self, device: &ash::Device, spirv: &[u32]) -> Result<()> {
        let shader = self.shader;
        if shader
            .bindings
            .iter()
            .any(|b| b.kind == DescriptorKind::Sampler)
        {
            self.sampler = device.create_sampler(&gather_sampler(), None)?;
        }
        let bindings: Vec<_> = shader
            .bindings
            .iter()
            .map(|b| {
                let binding = vk::DescriptorSetLayoutBinding::default()
                    .binding(b.binding)
                    .descriptor_type(descriptor_type(b.kind))
                    .descriptor_count(1)
                    .stage_flags(vk::ShaderStageFlags::COMPUTE);
                if b.kind == DescriptorKind::Sampler {
                    binding.immutable_samplers(std::slice::from_ref(&self.sampler))
                } else {
                    binding
                }
            })
            .collect();
        let push_constant_ranges = [vk::PushConstantRange {
            stage_flags: vk::ShaderStageFlags::COMPUTE,
            offset: 0,
            size: shader.push_constant_size,
        }];
        let push_constant_ranges = if shader.push_constant_size > 0 {
            &push_constant_ranges[..]
        } else {
            &[]
        };
        self.set_layout = device.create_descriptor_set_layout(
            &vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings),
            None,
        )?;
        self.layout = device.create_pipeline_layout(
            &vk::PipelineLayoutCreateInfo::default()
                .set_layouts(std::slice::from_ref(&self.set_layout))
                .push_constant_ranges(push_constant_ranges),
            None,
        )?;
        self.pipeline = create_compute_pipeline(device, self.layout, spirv)?;
        Ok(())
    }

    /// Binds the pipeline, its descriptor set and push constants, and covers `extent` with
    /// workgroups. Only `vk::recorder` dispatches, so that every dispatch is ordered.
    pub(crate) fn dispatch<P: PushConstants>(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        set: vk::DescriptorSet,
        params: &P,
        extent: vk::Extent2D,
    ) {
        self.bind(device, cmd, set, params);
        let [group_x, group_y, _] = self.shader.workgroup_size;
        // SAFETY: cmd is recording, with this pipeline bound.
        unsafe {
            device.cmd_dispatch(
                cmd,
                extent.width.div_ceil(group_x),
                extent.height.div_ceil(group_y),
                1,
            );
        }
    }

    /// As `dispatch` (`&()` for a pipeline without push constants), with the workgroup counts
    /// the GPU wrote at `offset` in `args`.
    pub(crate) fn dispatch_indirect<P: PushConstants>(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        set: vk::DescriptorSet,
        params: &P,
        args: vk::Buffer,
        offset: u64,
    ) {
        self.bind(device, cmd, set, params);
        // SAFETY: cmd is recording, with this pipeline bound; args holds a
        // VkDispatchIndirectCommand at offset, made visible by the recorder's barrier.
        unsafe { device.cmd_dispatch_indirect(cmd, args, offset) };
    }

    fn bind<P: PushConstants>(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        set: vk::DescriptorSet,
        params: &P,
    ) {
        debug_assert_eq!(
            std::mem::size_of::<P>() as u32,
            self.shader.push_constant_size
        );
        // SAFETY: cmd is recording; set was written for this pipeline's layout.
        unsafe {
            device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, self.pipeline);
            device.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::COMPUTE,
                self.layout,
                0,
                &[set],
                &[],
            );
            if self.shader.push_constant_size > 0 {
                device.cmd_push_constants(
                    cmd,
                    self.layout,
                    vk::ShaderStageFlags::COMPUTE,
                    0,
                    params.as_bytes(),
                );
            }
        }
    }

    pub fn destroy(&mut self, device: &ash::Device) {
        // SAFETY: the pipeline is no longer used by pending work (destroy contract).
        unsafe {
            device.destroy_pipeline(self.pipeline, None);
            device.destroy_pipeline_layout(self.layout, None);
            device.destroy_descriptor_set_layout(self.set_layout, None);
            device.destroy_sampler(self.sampler, None);
        }
        self.sampler = vk::Sampler::null();
        self.pipeline = vk::Pipeline::null();
        self.layout = vk::PipelineLayout::null();
        self.set_layout = vk::DescriptorSetLayout::null();
    }
}

enum Descriptor {
    Image(vk::DescriptorImageInfo),
    Buffer(vk::DescriptorBufferInfo),
}

/// The resources of one dispatch, keyed by the binding numbers the shader declares.
pub struct DescriptorWrites<'a> {
    shader: &'a ShaderInfo,
    /// Binding, descriptor, what it names, and that resource's bytes.
    resources: Vec<(u32, Descriptor, Resource, u64)>,
}

impl<'a> DescriptorWrites<'a> {
    pub fn new(pipeline: &'a ComputePipeline) -> Self {
        Self {
            shader: &pipeline.shader,
            resources: Vec::new(),
        }
    }

    /// An image, the plugin's (in GENERAL) or the engine's (in its pass layout).
    pub fn image(mut self, binding: u32, image: impl Into<Texture>) -> Self {
        let texture = image.into();
        let info = vk::DescriptorImageInfo {
            sampler: vk::Sampler::null(),
            image_view: texture.view,
            image_layout: texture.layout,
        };
        self.resources.push((
            binding,
            Descriptor::Image(info),
            Resource::Image(texture.image),
            texture.bytes,
        ));
        self
    }

    pub fn buffer(mut self, binding: u32, range: &CounterRange) -> Self {
        let info = vk::DescriptorBufferInfo {
            buffer: range.buffer,
            offset: range.offset,
            range: range.range,
        };
        self.resources.push((
            binding,
            Descriptor::Buffer(info),
            Resource::range(range),
            range.range,
        ));
        self
    }

    /// What a dispatch with these descriptors reads and writes, as the shader declares it.
    pub fn accesses(&self) -> Vec<Access> {
        self.resources
            .iter()
            .map(|(binding, _, resource, _)| Access {
                resource: *resource,
                write: self.declared(*binding).writes,
                stage: vk::PipelineStageFlags::COMPUTE_SHADER,
            })
            .collect()
    }

    /// The bytes one dispatch with these descriptors moves through each binding (`Traffic`),
    /// before its arithmetic.
    pub fn traffic(&self) -> Vec<(u32, Traffic)> {
        self.resources
            .iter()
            .map(|(binding, _, _, bytes)| {
                let declared = self.declared(*binding);
                let moved = |moves: bool| if moves { *bytes } else { 0 };
                let traffic = Traffic {
                    bytes_read: moved(declared.reads),
                    bytes_written: moved(declared.writes),
                    operations: 0,
                };
                (*binding, traffic)
            })
            .collect()
    }

    fn declared(&self, binding: u32) -> &Binding {
        self.shader
            .bindings
            .iter()
            .find(|b| b.binding == binding)
            .unwrap_or_else(|| panic!("pass {} has no binding {binding}", self.shader.name))
    }

    /// Writes every binding of `set` but the samplers, which the set layout fixes. Panics (a
    /// plugin bug, caught at the ABI) if a binding the shader declares was left out or one it
    /// does not declare was given.
    pub fn update(self, device: &ash::Device, set: vk::DescriptorSet) {
        let samplers = self
            .shader
            .bindings
            .iter()
            .filter(|b| b.kind == DescriptorKind::Sampler);
        assert_eq!(
            self.resources.len(),
            self.shader.bindings.len() - samplers.count(),
            "pass {}: every binding must be written once",
            self.shader.name
        );
        let writes: Vec<_> = self
            .resources
            .iter()
            .map(|(binding, descriptor, _, _)| {
                let write = vk::WriteDescriptorSet::default()
                    .dst_set(set)
                    .dst_binding(*binding)
                    .descriptor_type(descriptor_type(self.declared(*binding).kind));
                match descriptor {
                    Descriptor::Image(info) => write.image_info(std::slice::from_ref(info)),
                    Descriptor::Buffer(info) => write.buffer_info(std::slice::from_ref(info)),
                }
            })
            .collect();
        // SAFETY: the set is not in use by pending GPU work (frame ring contract).
        unsafe { device.update_descriptor_sets(&writes, &[]) };
    }
}

/// A pool holding `copies` sets of each of a list of layouts, allocated once and never freed
/// one by one: the frame ring's per-region sets, or a test's.
pub struct DescriptorPool {
    pool: vk::DescriptorPool,
    /// `copies` runs of the layouts, in order.
    pub sets: Vec<vk::DescriptorSet>,
}

impl DescriptorPool {
    /// `pool_sizes` counts the descriptors of one set of each layout together.
    pub fn new(
        gpu: &Gpu,
        layouts: &[vk::DescriptorSetLayout],
        pool_sizes: &[vk::DescriptorPoolSize],
        copies: usize,
    ) -> Result<Self> {
        let sizes: Vec<_> = pool_sizes
            .iter()
            .map(|s| vk::DescriptorPoolSize {
                ty: s.ty,
                descriptor_count: s.descriptor_count * copies as u32,
            })
            .collect();
        let all: Vec<_> = (0..copies).flat_map(|_| layouts.iter().copied()).collect();
        let mut made = Self {
            pool: vk::DescriptorPool::null(),
            sets: Vec::new(),
        };
        // SAFETY: valid device; on failure the pool is destroyed (a null pool is a no-op).
        let built = unsafe {
            (|| -> Result<()> {
                made.pool = gpu.device.create_descriptor_pool(
                    &vk::DescriptorPoolCreateInfo::default()
                        .max_sets(all.len() as u32)
                        .pool_sizes(&sizes),
                    None,
                )?;
                if !all.is_empty() {
                    made.sets = gpu.device.allocate_descriptor_sets(
                        &vk::DescriptorSetAllocateInfo::default()
                            .descriptor_pool(made.pool)
                            .set_layouts(&all),
                    )?;
                }
                Ok(())
            })()
        };
        match built {
            Ok(()) => Ok(made),
            Err(error) => {
                made.destroy(&gpu.device);
                Err(error)
            }
        }
    }

    pub fn destroy(&mut self, device: &ash::Device) {
        // SAFETY: no pending work uses the pool's sets (destroy contract).
        unsafe { device.destroy_descriptor_pool(self.pool, None) };
        self.pool = vk::DescriptorPool::null();
        self.sets.clear();
    }
}
