//! Descriptor set layouts, pipeline layouts and the four pipelines.

use super::targets::{
    DEPTH_FORMAT, FORWARD_FORMAT, FORWARD_TARGETS, GBUFFER_FORMAT, GBUFFER_TARGETS,
};
use super::uniforms::MaterialConstants;
use crate::error::{Result, VkContext};
use crate::gpu::{shaders, Gpu};
use crate::scene::Vertex;
use ash::vk;
use std::sync::Arc;

pub(crate) struct Pipelines {
    /// Set 0 of the G-buffer pass: the frame uniforms.
    pub frame_layout: vk::DescriptorSetLayout,
    /// Set 1 of the G-buffer pass: four material textures and a sampler.
    pub material_layout: vk::DescriptorSetLayout,
    /// Set 0 of the resolve pass.
    pub resolve_layout: vk::DescriptorSetLayout,
    /// Set 2 of the forward pass: the two shadow maps.
    pub shadow_maps_layout: vk::DescriptorSetLayout,
    pub gbuffer_layout: vk::PipelineLayout,
    pub shadow_layout: vk::PipelineLayout,
    pub resolve_pipeline_layout: vk::PipelineLayout,
    pub forward_layout: vk::PipelineLayout,
    pub gbuffer: vk::Pipeline,
    pub shadow: vk::Pipeline,
    pub resolve: vk::Pipeline,
    pub forward: vk::Pipeline,
    gpu: Arc<Gpu>,
}

fn binding(
    index: u32,
    ty: vk::DescriptorType,
    stages: vk::ShaderStageFlags,
) -> vk::DescriptorSetLayoutBinding<'static> {
    vk::DescriptorSetLayoutBinding::default()
        .binding(index)
        .descriptor_type(ty)
        .descriptor_count(1)
        .stage_flags(stages)
}

fn set_layout(
    gpu: &Gpu,
    bindings: &[vk::DescriptorSetLayoutBinding],
) -> Result<vk::DescriptorSetLayout> {
    let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(bindings);
    // SAFETY: valid device and create info.
    unsafe { gpu.device.create_descriptor_set_layout(&info, None) }
        .vk("vkCreateDescriptorSetLayout")
}

fn pipeline_layout(
    gpu: &Gpu,
    sets: &[vk::DescriptorSetLayout],
    push_stages: vk::ShaderStageFlags,
    push_size: u32,
) -> Result<vk::PipelineLayout> {
    let ranges = [vk::PushConstantRange {
        stage_flags: push_stages,
        offset: 0,
        size: push_size,
    }];
    let info = vk::PipelineLayoutCreateInfo::default()
        .set_layouts(sets)
        .push_constant_ranges(&ranges);
    // SAFETY: valid device and create info.
    unsafe { gpu.device.create_pipeline_layout(&info, None) }.vk("vkCreatePipelineLayout")
}

impl Pipelines {
    pub fn new(gpu: &Arc<Gpu>) -> Result<Self> {
        use vk::DescriptorType as D;
        use vk::ShaderStageFlags as S;
        let frame_layout = set_layout(
            gpu,
            &[binding(0, D::UNIFORM_BUFFER, S::VERTEX | S::FRAGMENT)],
        )?;
        let material_layout = set_layout(
            gpu,
            &[
                binding(0, D::SAMPLED_IMAGE, S::FRAGMENT),
                binding(1, D::SAMPLED_IMAGE, S::FRAGMENT),
                binding(2, D::SAMPLED_IMAGE, S::FRAGMENT),
                binding(3, D::SAMPLED_IMAGE, S::FRAGMENT),
                binding(4, D::SAMPLER, S::FRAGMENT),
            ],
        )?;
        let mut resolve_bindings = vec![binding(0, D::UNIFORM_BUFFER, S::COMPUTE)];
        resolve_bindings.extend((1..=7).map(|i| binding(i, D::SAMPLED_IMAGE, S::COMPUTE)));
        resolve_bindings.push(binding(8, D::STORAGE_BUFFER, S::COMPUTE));
        let resolve_layout = set_layout(gpu, &resolve_bindings)?;
        let shadow_maps_layout = set_layout(
            gpu,
            &[
                binding(0, D::SAMPLED_IMAGE, S::FRAGMENT),
                binding(1, D::SAMPLED_IMAGE, S::FRAGMENT),
            ],
        )?;

        let gbuffer_layout = pipeline_layout(
            gpu,
            &[frame_layout, material_layout],
            S::FRAGMENT,
            std::mem::size_of::<MaterialConstants>() as u32,
        )?;
        let shadow_layout = pipeline_layout(gpu, &[], S::VERTEX, 64)?;
        let resolve_pipeline_layout = pipeline_layout(gpu, &[resolve_layout], S::COMPUTE, 4)?;
        let forward_layout = pipeline_layout(
            gpu,
            &[frame_layout, material_layout, shadow_maps_layout],
            S::FRAGMENT,
            std::mem::size_of::<MaterialConstants>() as u32,
        )?;

        let gbuffer = graphics_pipeline(gpu, gbuffer_layout, shaders::GBUFFER, Raster::GBuffer)?;
        let shadow = graphics_pipeline(gpu, shadow_layout, shaders::SHADOW, Raster::ShadowDepth)?;
        let forward = graphics_pipeline(gpu, forward_layout, shaders::FORWARD, Raster::Forward)?;
        let resolve = compute_pipeline(gpu, resolve_pipeline_layout, shaders::RESOLVE)?;
        Ok(Self {
            frame_layout,
            material_layout,
            resolve_layout,
            shadow_maps_layout,
            gbuffer_layout,
            shadow_layout,
            resolve_pipeline_layout,
            forward_layout,
            gbuffer,
            shadow,
            resolve,
            forward,
            gpu: gpu.clone(),
        })
    }
}

impl Drop for Pipelines {
    fn drop(&mut self) {
        // SAFETY: the renderer waits for the GPU before dropping its parts.
        unsafe {
            let device = &self.gpu.device;
            for pipeline in [self.gbuffer, self.shadow, self.resolve, self.forward] {
                device.destroy_pipeline(pipeline, None);
            }
            for layout in [
                self.gbuffer_layout,
                self.shadow_layout,
                self.resolve_pipeline_layout,
                self.forward_layout,
            ] {
                device.destroy_pipeline_layout(layout, None);
            }
            for layout in [
                self.frame_layout,
                self.material_layout,
                self.resolve_layout,
                self.shadow_maps_layout,
            ] {
                device.destroy_descriptor_set_layout(layout, None);
            }
        }
    }
}

fn vertex_attribute(
    location: u32,
    format: vk::Format,
    offset: usize,
) -> vk::VertexInputAttributeDescription {
    vk::VertexInputAttributeDescription {
        location,
        binding: 0,
        format,
        offset: offset as u32,
    }
}

/// What a graphics pipeline rasterises into, all with dynamic rendering.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Raster {
    /// Depth only, from positions alone: the shadow maps.
    ShadowDepth,
    /// The five G-buffer targets, writing depth.
    GBuffer,
    /// The forward targets, blended back to front ("over", premultiplied), testing the
    /// G-buffer's depth without writing it.
    Forward,
}

fn graphics_pipeline(
    gpu: &Gpu,
    layout: vk::PipelineLayout,
    spirv: &[u8],
    raster: Raster,
) -> Result<vk::Pipeline> {
    let shaded = raster != Raster::ShadowDepth;
    use std::mem::offset_of;
    use vk::Format as F;
    let module = gpu.create_shader_module(spirv)?;
    let mut stages = vec![vk::PipelineShaderStageCreateInfo::default()
        .stage(vk::ShaderStageFlags::VERTEX)
        .module(module)
        .name(c"vs_main")];
    if shaded {
        stages.push(
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::FRAGMENT)
                .module(module)
                .name(c"fs_main"),
        );
    }
    let bindings = [vk::VertexInputBindingDescription {
        binding: 0,
        stride: std::mem::size_of::<Vertex>() as u32,
        input_rate: vk::VertexInputRate::VERTEX,
    }];
    let mut attributes = vec![vertex_attribute(
        0,
        F::R32G32B32_SFLOAT,
        offset_of!(Vertex, position),
    )];
    if shaded {
        attributes.extend([
            vertex_attribute(1, F::R32G32B32_SFLOAT, offset_of!(Vertex, prev_position)),
            vertex_attribute(2, F::R32G32B32_SFLOAT, offset_of!(Vertex, normal)),
            vertex_attribute(3, F::R32G32B32A32_SFLOAT, offset_of!(Vertex, tangent)),
            vertex_attribute(4, F::R32G32_SFLOAT, offset_of!(Vertex, uv)),
            vertex_attribute(5, F::R32G32B32A32_SFLOAT, offset_of!(Vertex, color)),
        ]);
    }
    let vertex_input = vk::PipelineVertexInputStateCreateInfo::default()
        .vertex_binding_descriptions(&bindings)
        .vertex_attribute_descriptions(&attributes);
    let input_assembly = vk::PipelineInputAssemblyStateCreateInfo::default()
        .topology(vk::PrimitiveTopology::TRIANGLE_LIST);
    let viewport = vk::PipelineViewportStateCreateInfo::default()
        .viewport_count(1)
        .scissor_count(1);
    // No culling: many glTF materials are double-sided, and the shader faces normals to the
    // viewer. With the y-down projection, glTF's counter-clockwise front faces stay CCW.
    let rasterization = vk::PipelineRasterizationStateCreateInfo::default()
        .polygon_mode(vk::PolygonMode::FILL)
        .cull_mode(vk::CullModeFlags::NONE)
        .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
        .line_width(1.0);
    let multisample = vk::PipelineMultisampleStateCreateInfo::default()
        .rasterization_samples(vk::SampleCountFlags::TYPE_1);
    let depth_stencil = vk::PipelineDepthStencilStateCreateInfo::default()
        .depth_test_enable(true)
        .depth_write_enable(raster != Raster::Forward)
        .depth_compare_op(vk::CompareOp::LESS);
    let (color_format, color_count) = match raster {
        Raster::ShadowDepth => (GBUFFER_FORMAT, 0),
        Raster::GBuffer => (GBUFFER_FORMAT, GBUFFER_TARGETS),
        Raster::Forward => (FORWARD_FORMAT, FORWARD_TARGETS),
    };
    let write_all = vk::PipelineColorBlendAttachmentState::default()
        .color_write_mask(vk::ColorComponentFlags::RGBA);
    let over = write_all
        .blend_enable(true)
        .src_color_blend_factor(vk::BlendFactor::ONE)
        .dst_color_blend_factor(vk::BlendFactor::ONE_MINUS_SRC_ALPHA)
        .color_blend_op(vk::BlendOp::ADD)
        .src_alpha_blend_factor(vk::BlendFactor::ONE)
        .dst_alpha_blend_factor(vk::BlendFactor::ONE_MINUS_SRC_ALPHA)
        .alpha_blend_op(vk::BlendOp::ADD);
    let blend = if raster == Raster::Forward {
        over
    } else {
        write_all
    };
    let blend_attachments = vec![blend; color_count];
    let color_blend =
        vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend_attachments);
    let dynamic_states = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
    let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states);
    let color_formats = vec![color_format; color_count];
    let mut rendering = vk::PipelineRenderingCreateInfo::default()
        .color_attachment_formats(&color_formats)
        .depth_attachment_format(DEPTH_FORMAT);
    let info = vk::GraphicsPipelineCreateInfo::default()
        .stages(&stages)
        .vertex_input_state(&vertex_input)
        .input_assembly_state(&input_assembly)
        .viewport_state(&viewport)
        .rasterization_state(&rasterization)
        .multisample_state(&multisample)
        .depth_stencil_state(&depth_stencil)
        .color_blend_state(&color_blend)
        .dynamic_state(&dynamic)
        .layout(layout)
        .push_next(&mut rendering);
    // SAFETY: all referenced state lives until the call returns; the module is destroyed after.
    let result = unsafe {
        gpu.device
            .create_graphics_pipelines(vk::PipelineCache::null(), &[info], None)
            .map_err(|(_, e)| e)
    };
    // SAFETY: pipelines do not reference their shader modules after creation.
    unsafe { gpu.device.destroy_shader_module(module, None) };
    Ok(result.vk("vkCreateGraphicsPipelines")?[0])
}

fn compute_pipeline(gpu: &Gpu, layout: vk::PipelineLayout, spirv: &[u8]) -> Result<vk::Pipeline> {
    let module = gpu.create_shader_module(spirv)?;
    let stage = vk::PipelineShaderStageCreateInfo::default()
        .stage(vk::ShaderStageFlags::COMPUTE)
        .module(module)
        .name(c"cs_main");
    let info = vk::ComputePipelineCreateInfo::default()
        .stage(stage)
        .layout(layout);
    // SAFETY: valid module and layout.
    let result = unsafe {
        gpu.device
            .create_compute_pipelines(vk::PipelineCache::null(), &[info], None)
            .map_err(|(_, e)| e)
    };
    // SAFETY: as above.
    unsafe { gpu.device.destroy_shader_module(module, None) };
    Ok(result.vk("vkCreateComputePipelines")?[0])
}
