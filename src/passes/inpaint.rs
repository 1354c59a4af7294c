//! Inference of one inpainting network on its patch: `network_inputs` gathers the input planes
//! from the frame, then one generated shader per layer (`network::codegen`) runs over the
//! patch, each dispatched indirectly from the `Patch` record so that the work follows the
//! patch's area and a frame without one dispatches no workgroup.

use ash::vk;
use gpu_allocator::vulkan::Allocator;

use crate::error::Result;
use crate::network::codegen::{
    self, GROUP_EDGE, PATCH_BYTES, PATCH_DISPATCH_OFFSET, PATCH_DIVISOR_OFFSET, PATCH_EXTENT_OFFSET,
};
use crate::network::weights::MAX_LEVELS;
use crate::network::{Network, Tensor, TensorPrecision, INPUT_CHANNELS};
use crate::passes::remodulate::RemodulateInputs;
use crate::passes::{CounterRange, RegionPasses, Texture};
use crate::shaders::network_inputs::{binding, Params, SHADER};
use crate::vk::access::GpuShare;
use crate::vk::device::Gpu;
use crate::vk::image::OwnedImage;
use crate::vk::pipeline::{pool_sizes, ComputePipeline};
use crate::vk::recorder::{Pass, Recorder};

/// Texels of context around a region's rectangle in its patch: past the network's receptive
/// field, a pixel at the edge of a region sees its surroundings as in training.
pub const PATCH_MARGIN: u32 = 8;

/// The network texels a patch may span on each axis, for frames up to `extent`: the tensors'
/// extent. A network's patch is a multiple of `multiple` texels, and so is `max_patch_side`
/// (`PATCHEX_NETWORK_PATCH_SIDE_MULTIPLE`): a frame smaller than it needs only its own extent.
pub fn patch_capacity(extent: [u32; 2], max_patch_side: u32, multiple: u32) -> [u32; 2] {
    const DEEPEST_MULTIPLE: u32 = 1 << (MAX_LEVELS - 1);
    const _: () = assert!(DEEPEST_MULTIPLE == crate::abi::PATCHEX_NETWORK_PATCH_SIDE_MULTIPLE);
    extent.map(|side| side.min(max_patch_side).next_multiple_of(multiple))
}

/// A network's compiled layers and its gather pass. Their descriptor sets are the frame ring's,
/// after the fixed pipelines' (`Inpainting::set_layouts`).
pub struct NetworkPipelines {
    pub network: Network,
    /// The format every layer writes its output in.
    pub precision: TensorPrecision,
    gather: ComputePipeline,
    layers: Vec<ComputePipeline>,
}

impl NetworkPipelines {
    pub fn new(gpu: &Gpu, network: Network, precision: TensorPrecision) -> Result<Self> {
        let mut built = Self {
            network,
            precision,
            gather: ComputePipeline::new(gpu, SHADER)?,
            layers: Vec::new(),
        };
        for layer in &built.network.layers {
            let what = format!("network layer {}", layer.name);
            let compiled = codegen::compile(&codegen::wgsl(layer, built.precision), &what)
                .and_then(|spirv| {
                    ComputePipeline::from_spirv(gpu, codegen::shader_info(layer), &spirv)
                        .map_err(|e| e.during(&what))
                });
            match compiled {
                Ok(pipeline) => built.layers.push(pipeline),
                Err(error) => {
                    built.destroy(&gpu.device);
                    return Err(error);
                }
            }
        }
        Ok(built)
    }

    /// The gather's, then each layer's, in the order a run's sets take.
    fn pipelines(&self) -> impl Iterator<Item = &ComputePipeline> {
        std::iter::once(&self.gather).chain(&self.layers)
    }

    /// The layouts of one run's descriptor sets: the gather's, then one per layer.
    pub fn set_layouts(&self) -> Vec<vk::DescriptorSetLayout> {
        self.pipelines().map(|p| p.set_layout).collect()
    }

    /// Descriptor counts of one run's sets together.
    pub fn pool_sizes(&self) -> Vec<vk::DescriptorPoolSize> {
        pool_sizes(self.pipelines())
    }

    pub fn destroy(&mut self, device: &ash::Device) {
        self.gather.destroy(device);
        for layer in &mut self.layers {
            layer.destroy(device);
        }
    }
}

/// The images of one network run: the gathered input (RGBA16F) and every layer's output (in the
/// pipelines' precision), as arrays of four channels a layer, sized for the largest patch.
pub struct NetworkTensors {
    pub input: OwnedImage,
    pub layers: Vec<OwnedImage>,
}

impl NetworkTensors {
    /// Room for patches up to `max_extent`, which must be a multiple of the network's
    /// `multiple()`.
    pub fn new(
        gpu: &Gpu,
        allocator: &mut Allocator,
        pipelines: &NetworkPipelines,
        max_extent: vk::Extent2D,
    ) -> Result<Self> {
        let network = &pipelines.network;
        // Transfer source: tests and debug tools read tensors back.
        let usage = vk::ImageUsageFlags::STORAGE
            | vk::ImageUsageFlags::SAMPLED
            | vk::ImageUsageFlags::TRANSFER_SRC;
        let mut tensors = Self {
            input: OwnedImage::array(
                gpu,
                allocator,
                "patchex network input",
                vk::Format::R16G16B16A16_SFLOAT,
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
                pipelines.precision.format(),
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

    /// The network texels the tensors hold room for, at the network's first level.
    fn capacity(&self) -> u64 {
        self.input.extent.width as u64 * self.input.extent.height as u64
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
    let divisor = 1;
    let mut words = vec![origin[0], origin[1], extent[0], extent[1], divisor, 0, 0, 0];
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

/// One network's run in an extrapolation.
pub struct NetworkRun<'a> {
    pub pipelines: &'a NetworkPipelines,
    /// Of the layouts `NetworkPipelines::set_layouts`, in this extrapolation's region.
    pub sets: Vec<vk::DescriptorSet>,
    pub tensors: &'a NetworkTensors,
    pub patch: PatchRecord,
}

/// Records the gather and every layer of each network in `runs`, level by level across the
/// networks: one barrier orders a step of all of them, so no network waits for another's work.
/// Each pass counts the bytes of the share of the frame and of the tensors its patch spans.
pub fn record(rec: &mut Recorder, inputs: &FrameInputs, runs: &[NetworkRun]) {
    let material = inputs.material.unwrap_or(inputs.placeholder);
    let frame_pixels = inputs.frame_extent.width as u64 * inputs.frame_extent.height as u64;
    for run in runs {
        let gather = Pass {
            pipeline: &run.pipelines.gather,
            set: run.sets[0],
        };
        let gather = rec.bind(gather, |writes| {
            writes
                .image(binding::WARPED, inputs.warped)
                .image(binding::MATERIAL, material)
                .image(binding::NETWORK_INPUT, &run.tensors.input)
                .buffer(binding::NETWORK_PATCH, &run.patch.range())
        });
        let params = Params {
            frame_extent: [inputs.frame_extent.width, inputs.frame_extent.height],
            has_material: inputs.material.is_some() as u32,
            _pad_end: [0; 4],
        };
        rec.dispatch_over_patch(
            &gather,
            &params,
            &run.patch.dispatch(0),
            &[
                (
                    &[binding::WARPED, binding::MATERIAL],
                    run.patch.pixels(frame_pixels),
                ),
                (&[binding::NETWORK_INPUT], run.patch.texels(run.tensors)),
            ],
        );
    }
    let steps = runs
        .iter()
        .map(|run| run.pipelines.layers.len())
        .max()
        .unwrap_or(0);
    for n in 0..steps {
        for run in runs.iter().filter(|run| n < run.pipelines.layers.len()) {
            let layer = &run.pipelines.network.layers[n];
            let tensors = run.tensors;
            let tensor = |tensor: Tensor| match tensor {
                Tensor::Input => &tensors.input,
                Tensor::Layer(n) => &tensors.layers[n],
            };
            let pass = Pass {
                pipeline: &run.pipelines.layers[n],
                set: run.sets[1 + n],
            };
            let main = tensor(layer.main);
            let bound = rec.bind(pass, |writes| {
                writes
                    .image(0, main)
                    .image(1, layer.skip.map_or(main, tensor))
                    .image(2, &tensors.input)
                    .image(3, &tensors.layers[n])
                    .buffer(4, &run.patch.range())
            });
            rec.dispatch_over_patch(
                &bound,
                &(),
                &run.patch.dispatch(layer.level),
                &[(&[0, 1, 2, 3], run.patch.texels(tensors))],
            );
        }
    }
}

impl PatchRecord {
    /// The whole record, as the shaders bind it.
    fn range(&self) -> CounterRange {
        CounterRange {
            buffer: self.buffer,
            offset: self.offset,
            range: PATCH_BYTES,
        }
    }

    /// The frame pixels the patch covers, of a frame of `frame_pixels`.
    fn pixels(&self, frame_pixels: u64) -> GpuShare {
        GpuShare::PatchPixels {
            extent: self.offset + PATCH_EXTENT_OFFSET,
            divisor: self.offset + PATCH_DIVISOR_OFFSET,
            capacity: frame_pixels,
        }
    }

    /// The texels the patch spans of `tensors`.
    fn texels(&self, tensors: &NetworkTensors) -> GpuShare {
        GpuShare::PatchTexels {
            extent: self.offset + PATCH_EXTENT_OFFSET,
            capacity: tensors.capacity(),
        }
    }

    /// The indirect dispatch of network level `level`.
    fn dispatch(&self, level: u32) -> CounterRange {
        CounterRange {
            buffer: self.buffer,
            offset: self.offset + PATCH_DISPATCH_OFFSET + 16 * level as u64,
            range: 12,
        }
    }
}

/// The three patch records of an extrapolation (`PatchSlot` in shaders/include/patch.wgsl),
/// each 256 bytes from the last.
pub const PATCH_SLOT_BYTES: u64 = 256;
pub const PATCH_SLOT_FI: u64 = 0;
pub const PATCH_SLOT_NEAR_BE: u64 = 1;
pub const PATCH_SLOT_BLEND: u64 = 2;
pub const PATCH_SLOTS_BYTES: u64 = 3 * PATCH_SLOT_BYTES;

/// The record of slot `slot` in `patches`.
pub fn patch_record(patches: &CounterRange, slot: u64) -> PatchRecord {
    PatchRecord {
        buffer: patches.buffer,
        offset: patches.offset + slot * PATCH_SLOT_BYTES,
    }
}

/// What the networks run on this extrapolation.
pub struct PatchPlan {
    /// Of the FI and near-BE networks; 0 for one that does not run.
    pub levels: [u32; 2],
    /// FI's patch is the whole frame.
    pub whole_frame: bool,
    /// Frame pixels per network texel on each axis, as asked for; a patch larger than
    /// `max_patch_side` texels runs at a multiple of it.
    pub divisor: u32,
    pub max_patch_side: u32,
    /// The segmentation's k_x and k_y, which grow the near-BE rectangles.
    pub growth: [f32; 2],
}

/// Records `plan_patches`: the FI, near-BE and blend patches from the objects' totals in the
/// object table (`segmentation::object_totals`).
pub fn record_plan(
    rec: &mut Recorder,
    pass: Pass,
    extent: vk::Extent2D,
    plan: &PatchPlan,
    totals: &CounterRange,
    patches: &CounterRange,
) {
    use crate::shaders::plan_patches::{binding, Params};
    let bound = rec.bind(pass, |writes| {
        writes
            .buffer(binding::TOTALS, totals)
            .buffer(binding::PATCHES, patches)
    });
    let params = Params {
        extent: [extent.width, extent.height],
        margin: PATCH_MARGIN,
        group_edge: GROUP_EDGE,
        levels: plan.levels,
        whole_frame: plan.whole_frame as u32,
        divisor: plan.divisor,
        max_patch_side: plan.max_patch_side,
        growth: plan.growth,
        ..Default::default()
    };
    let one = vk::Extent2D {
        width: 1,
        height: 1,
    };
    rec.dispatch(&bound, &params, one);
}

/// What `blend_patches` reads: the region mask and the FI and near-BE networks' tensors (a
/// network that is off this frame has an empty patch, and its tensors are not read).
pub struct BlendInputs<'a> {
    /// The patch records `plan_patches` wrote.
    pub patches: CounterRange,
    pub regions: &'a OwnedImage,
    pub networks: [&'a NetworkTensors; 2],
    /// Every pixel of the FI patch takes the FI network's result.
    pub whole_frame: bool,
    /// Pixels the warp did not mark as holes take the correction too (the paper's blend).
    pub correct_valid_pixels: bool,
}

/// Records `blend_patches`: the networks' results scattered into the frame under the region
/// masks, the frame remodulated as it is written (`remodulate`), over every pixel.
pub fn record_blend(
    rec: &mut Recorder,
    pass: Pass,
    extent: vk::Extent2D,
    inputs: &BlendInputs,
    remodulation: &RemodulateInputs,
    frame: Texture,
    sanitized: &CounterRange,
) {
    let patches = &inputs.patches;
    use crate::shaders::blend_patches::binding as blend;
    let [fi, near_be] = inputs.networks;
    let bound = rec.bind(pass, |writes| {
        remodulation
            .bind(writes, frame, sanitized)
            .image(blend::REGIONS, inputs.regions)
            .image(blend::FI_INPUT, &fi.input)
            .image(blend::FI_OUTPUT, fi.output())
            .image(blend::NEAR_BE_INPUT, &near_be.input)
            .image(blend::NEAR_BE_OUTPUT, near_be.output())
            .buffer(blend::PATCHES, patches)
    });
    let (has_material, has_shadow_share) = remodulation.present();
    let params = crate::shaders::blend_patches::Params {
        extent: [extent.width, extent.height],
        has_material,
        has_shadow_share,
        whole_frame: inputs.whole_frame as u32,
        correct_valid_pixels: inputs.correct_valid_pixels as u32,
    };
    // The regions are read over the blend patch, each network's tensors over its own.
    let blend_patch = patch_record(patches, PATCH_SLOT_BLEND);
    rec.dispatch_sharing(
        &bound,
        &params,
        extent,
        &[
            (
                &[blend::REGIONS],
                blend_patch.pixels(extent.width as u64 * extent.height as u64),
            ),
            (
                &[blend::FI_INPUT, blend::FI_OUTPUT],
                patch_record(patches, PATCH_SLOT_FI).texels(fi),
            ),
            (
                &[blend::NEAR_BE_INPUT, blend::NEAR_BE_OUTPUT],
                patch_record(patches, PATCH_SLOT_NEAR_BE).texels(near_be),
            ),
        ],
    );
}

/// The two networks of the networks presets (NETWORKS, FULL), compiled, with their tensors.
pub struct Inpainting {
    /// FI, then near-BE.
    pub networks: [(NetworkPipelines, NetworkTensors); 2],
    /// The network texels a patch may span per axis (`PatchexNetworkMemory`).
    pub max_patch_side: u32,
}

impl Inpainting {
    /// Compiles `networks` (FI, near-BE) and makes their tensors for the patches of frames up to
    /// `max_extent`, at most `max_patch_side` texels a side.
    pub fn new(
        gpu: &Gpu,
        allocator: &mut Allocator,
        networks: [Network; 2],
        precision: TensorPrecision,
        max_extent: vk::Extent2D,
        max_patch_side: u32,
    ) -> Result<Self> {
        let mut built: Vec<(NetworkPipelines, NetworkTensors)> = Vec::new();
        for network in networks {
            let [width, height] = patch_capacity(
                [max_extent.width, max_extent.height],
                max_patch_side,
                network.multiple(),
            );
            let extent = vk::Extent2D { width, height };
            let made = NetworkPipelines::new(gpu, network, precision).and_then(|mut pipelines| {
                match NetworkTensors::new(gpu, allocator, &pipelines, extent) {
                    Ok(tensors) => Ok((pipelines, tensors)),
                    Err(error) => {
                        pipelines.destroy(&gpu.device);
                        Err(error)
                    }
                }
            });
            match made {
                Ok(pair) => built.push(pair),
                Err(error) => {
                    for (mut pipelines, mut tensors) in built {
                        pipelines.destroy(&gpu.device);
                        tensors.destroy(gpu, allocator);
                    }
                    return Err(error);
                }
            }
        }
        let networks = <[_; 2]>::try_from(built).unwrap_or_else(|_| unreachable!("two networks"));
        Ok(Self {
            networks,
            max_patch_side,
        })
    }

    /// Level counts for `plan_patches`: 0 for a network that is switched off.
    pub fn levels(&self, run: [bool; 2]) -> [u32; 2] {
        [0, 1].map(|i| {
            if run[i] {
                self.networks[i].0.network.widths.len() as u32
            } else {
                0
            }
        })
    }

    /// The layouts of the two networks' descriptor sets, FI's then near-BE's, which every
    /// region of the frame ring holds.
    pub fn set_layouts(&self) -> Vec<vk::DescriptorSetLayout> {
        self.networks
            .iter()
            .flat_map(|(pipelines, _)| pipelines.set_layouts())
            .collect()
    }

    /// Descriptor counts of the sets of `set_layouts` together.
    pub fn pool_sizes(&self) -> Vec<vk::DescriptorPoolSize> {
        pool_sizes(self.networks.iter().flat_map(|(p, _)| p.pipelines()))
    }

    /// The two networks' runs with the sets of `passes`' region, on the patches of the region's
    /// counters `patches`.
    pub fn runs(&self, passes: &RegionPasses, patches: &CounterRange) -> Vec<NetworkRun<'_>> {
        let mut sets = (0..).map(|n| passes.network_set(n));
        [PATCH_SLOT_FI, PATCH_SLOT_NEAR_BE]
            .into_iter()
            .zip(&self.networks)
            .map(|(patch_slot, (pipelines, tensors))| NetworkRun {
                pipelines,
                sets: sets.by_ref().take(1 + pipelines.layers.len()).collect(),
                tensors,
                patch: patch_record(patches, patch_slot),
            })
            .collect()
    }

    pub fn tensors(&self) -> [&NetworkTensors; 2] {
        [&self.networks[0].1, &self.networks[1].1]
    }

    pub fn size_bytes(&self) -> u64 {
        self.networks.iter().map(|(_, t)| t.size_bytes()).sum()
    }

    /// Every tensor image, for their first layout transition.
    pub fn images(&mut self) -> impl Iterator<Item = &mut OwnedImage> {
        self.networks
            .iter_mut()
            .flat_map(|(_, t)| std::iter::once(&mut t.input).chain(t.layers.iter_mut()))
    }

    pub fn destroy(&mut self, gpu: &Gpu, allocator: &mut Allocator) {
        for (pipelines, tensors) in &mut self.networks {
            pipelines.destroy(&gpu.device);
            tensors.destroy(gpu, allocator);
        }
    }
}

/// The extent and divisor `plan_patches` wrote into the patch record at `offset` of the
/// counters.
pub fn read_patch(counters: &crate::vk::buffer::Buffer, offset: u64) -> ([u32; 2], u32) {
    let extent = offset + PATCH_EXTENT_OFFSET;
    (
        [counters.read_u32(extent), counters.read_u32(extent + 4)],
        counters.read_u32(offset + PATCH_DIVISOR_OFFSET),
    )
}
