//! Inference of one inpainting network on its patch: `network_inputs` gathers the input planes
//! from the frame, then one generated shader per layer (`network::codegen`) runs over the
//! patch, each dispatched indirectly from the `Patch` record so that the work follows the
//! patch's area and a frame without one dispatches no workgroup.

use ash::vk;
use gpu_allocator::vulkan::Allocator;

use crate::error::Result;
use crate::network::codegen::{self, GROUP_EDGE, PATCH_BYTES};
use crate::network::weights::MAX_LEVELS;
use crate::network::{Network, Tensor, INPUT_CHANNELS};
use crate::passes::Texture;
use crate::shaders::network_inputs::{binding, Params, SHADER};
use crate::vk::barriers;
use crate::vk::device::Gpu;
use crate::vk::image::OwnedImage;
use crate::vk::pipeline::{pool_sizes, ComputePipeline, DescriptorWrites};

/// A network's compiled layers, its gather pass and `instances` descriptor sets for each
/// (one per extrapolation that may be recorded before an earlier one completes).
pub struct NetworkPipelines {
    pub network: Network,
    gather: ComputePipeline,
    layers: Vec<ComputePipeline>,
    pool: vk::DescriptorPool,
    /// `[instance][0 = gather, 1 + layer]`.
    sets: Vec<vk::DescriptorSet>,
}

impl NetworkPipelines {
    pub fn new(gpu: &Gpu, network: Network, instances: usize) -> Result<Self> {
        let mut built = Self {
            network,
            gather: ComputePipeline::new(gpu, SHADER)?,
            layers: Vec::new(),
            pool: vk::DescriptorPool::null(),
            sets: Vec::new(),
        };
        let result = built.build(gpu, instances);
        match result {
            Ok(()) => Ok(built),
            Err(error) => {
                built.destroy(&gpu.device);
                Err(error)
            }
        }
    }

    fn build(&mut self, gpu: &Gpu, instances: usize) -> Result<()> {
        for layer in &self.network.layers {
            let what = format!("network layer {}", layer.name);
            let spirv = codegen::compile(&codegen::wgsl(layer), &what)?;
            self.layers.push(
                ComputePipeline::from_spirv(gpu, codegen::shader_info(layer), &spirv)
                    .map_err(|e| e.during(&what))?,
            );
        }
        let per_instance: Vec<&ComputePipeline> =
            std::iter::once(&self.gather).chain(&self.layers).collect();
        let mut sizes = pool_sizes(per_instance.iter().copied());
        for size in &mut sizes {
            size.descriptor_count *= instances as u32;
        }
        let layouts: Vec<_> = (0..instances)
            .flat_map(|_| per_instance.iter().map(|p| p.set_layout))
            .collect();
        // SAFETY: valid device; the pool is destroyed with the pipelines.
        unsafe {
            self.pool = gpu.device.create_descriptor_pool(
                &vk::DescriptorPoolCreateInfo::default()
                    .max_sets(layouts.len() as u32)
                    .pool_sizes(&sizes),
                None,
            )?;
            self.sets = gpu.device.allocate_descriptor_sets(
                &vk::DescriptorSetAllocateInfo::default()
                    .descriptor_pool(self.pool)
                    .set_layouts(&layouts),
            )?;
        }
        Ok(())
    }

    pub fn destroy(&mut self, device: &ash::Device) {
        // SAFETY: no pending work uses them (destroy contract); null handles are no-ops.
        unsafe { device.destroy_descriptor_pool(self.pool, None) };
        self.pool = vk::DescriptorPool::null();
        self.gather.destroy(device);
        for layer in &mut self.layers {
            layer.destroy(device);
        }
    }
}

/// The images of one network run: the gathered input and every layer's output, as RGBA16F
/// arrays of four channels a layer, sized for the largest patch.
pub struct NetworkTensors {
    pub input: OwnedImage,
    pub layers: Vec<OwnedImage>,
}

impl NetworkTensors {
    /// Room for patches up to `max_extent`, which must be a multiple of `network.multiple()`.
    pub fn new(
        gpu: &Gpu,
        allocator: &mut Allocator,
        network: &Network,
        max_extent: vk::Extent2D,
    ) -> Result<Self> {
        // Transfer source: tests and debug tools read tensors back.
        let usage = vk::ImageUsageFlags::STORAGE
            | vk::ImageUsageFlags::SAMPLED
            | vk::ImageUsageFlags::TRANSFER_SRC;
        let format = vk::Format::R16G16B16A16_SFLOAT;
        let mut tensors = Self {
            input: OwnedImage::array(
                gpu,
                allocator,
                "patchex network input",
                format,
                max_extent,
                usage,
                INPUT_CHANNELS.div_ceil(4) as u32,
            )?,
            layers: Vec::new(),
        };
        for layer in &network.layers {
            let extent = vk::Extent2D {
                width: max_extent.width >> layer.level,
                height: max_extent.height >> layer.level,
            };
            let image = OwnedImage::array(
                gpu,
                allocator,
                "patchex network layer",
                format,
                extent,
                usage,
                layer.output_channels().div_ceil(4) as u32,
            );
            match image {
                Ok(image) => tensors.layers.push(image),
                Err(error) => {
                    tensors.destroy(gpu, allocator);
                    return Err(error);
                }
            }
        }
        Ok(tensors)
    }

    /// The repaired colour of the patch (RGB, alpha 1), at the patch's own origin.
    pub fn output(&self) -> &OwnedImage {
        self.layers.last().expect("a network has layers")
    }

    pub fn size_bytes(&self) -> u64 {
        self.input.size_bytes() + self.layers.iter().map(|l| l.size_bytes()).sum::<u64>()
    }

    pub fn destroy(&mut self, gpu: &Gpu, allocator: &mut Allocator) {
        self.input.destroy(gpu, allocator);
        for layer in &mut self.layers {
            layer.destroy(gpu, allocator);
        }
    }
}

/// What the network reads from the frame.
pub struct FrameInputs {
    /// Warped demodulated shading, alpha 1 where valid and 0 in holes.
    pub warped: Texture,
    pub material: Option<Texture>,
    pub lbp: Texture,
    /// Bound in place of an absent material image.
    pub placeholder: Texture,
    pub frame_extent: vk::Extent2D,
}

/// Where the `Patch` record lives: a buffer with STORAGE and INDIRECT usage.
#[derive(Clone, Copy)]
pub struct PatchRecord {
    pub buffer: vk::Buffer,
    pub offset: u64,
}

/// The bytes of a `Patch` record for a patch the host chose (the pipeline's patches are planned
/// on the GPU): `origin` and `extent` in frame texels, the extent a multiple of the network's.
pub fn patch_bytes(network: &Network, origin: [u32; 2], extent: [u32; 2]) -> Vec<u8> {
    let mut words = vec![origin[0], origin[1], extent[0], extent[1]];
    for level in 0..MAX_LEVELS {
        let groups = |size: u32| (size >> level).div_ceil(GROUP_EDGE);
        let used = level < network.widths.len();
        words.extend([
            if used { groups(extent[0]) } else { 0 },
            if used { groups(extent[1]) } else { 0 },
            1,
            0,
        ]);
    }
    let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_ne_bytes()).collect();
    debug_assert_eq!(bytes.len() as u64, PATCH_BYTES);
    bytes
}

/// Records the gather and every layer for extrapolation slot `instance`. The patch record must
/// be written and visible to compute shaders and indirect reads.
pub fn record(
    gpu: &Gpu,
    cmd: vk::CommandBuffer,
    pipelines: &NetworkPipelines,
    instance: usize,
    tensors: &NetworkTensors,
    inputs: &FrameInputs,
    patch: PatchRecord,
) {
    let device = &gpu.device;
    let general = vk::ImageLayout::GENERAL;
    let sets_per_instance = 1 + pipelines.layers.len();
    let sets = &pipelines.sets[instance * sets_per_instance..][..sets_per_instance];
    let material = inputs.material.unwrap_or(inputs.placeholder);
    DescriptorWrites::new(&pipelines.gather)
        .image(binding::WARPED, inputs.warped.view, inputs.warped.layout)
        .image(binding::MATERIAL, material.view, material.layout)
        .image(binding::LBP, inputs.lbp.view, inputs.lbp.layout)
        .image(binding::NETWORK_INPUT, tensors.input.view, general)
        .buffer(
            binding::NETWORK_PATCH,
            patch.buffer,
            patch.offset,
            PATCH_BYTES,
        )
        .update(device, sets[0]);
    pipelines.gather.dispatch_indirect(
        device,
        cmd,
        sets[0],
        &Params {
            frame_extent: [inputs.frame_extent.width, inputs.frame_extent.height],
            has_material: inputs.material.is_some() as u32,
            _pad_end: [0; 4],
        },
        patch.buffer,
        dispatch_offset(patch, 0),
    );
    let view = |tensor: Tensor| match tensor {
        Tensor::Input => tensors.input.view,
        Tensor::Layer(n) => tensors.layers[n].view,
    };
    for (n, (layer, pipeline)) in pipelines
        .network
        .layers
        .iter()
        .zip(&pipelines.layers)
        .enumerate()
    {
        barriers::compute_to_compute(device, cmd, false);
        let main = view(layer.main);
        DescriptorWrites::new(pipeline)
            .image(0, main, general)
            .image(1, layer.skip.map_or(main, view), general)
            .image(2, tensors.input.view, general)
            .image(3, tensors.layers[n].view, general)
            .buffer(4, patch.buffer, patch.offset, PATCH_BYTES)
            .update(device, sets[1 + n]);
        pipeline.dispatch_indirect(
            device,
            cmd,
            sets[1 + n],
            &(),
            patch.buffer,
            dispatch_offset(patch, layer.level),
        );
    }
}

fn dispatch_offset(patch: PatchRecord, level: u32) -> u64 {
    patch.offset + 16 + 16 * level as u64
}
