//! Inference of the FI and near-BE networks side by side, each on its own patch: one generated
//! shader per step (`network::codegen`) runs each network's layer of that step, the first
//! gathering both networks' input planes from the frame as it goes. Every pass is
//! dispatched indirectly from the step's record, which `plan_patches` writes from both patches,
//! so that the work follows the patches' area and a frame without one dispatches no workgroup.
//! Also here, as they share the patch records: their planning (`record_plan`, in the
//! segmentation's stage) and the blend of the networks' results into the frame
//! (`record_blend`).

use ash::vk;
use gpu_allocator::vulkan::Allocator;

use crate::error::Result;
use crate::network::codegen::{
    self, GatherParams, GROUP_EDGE, PATCH_BYTES, PATCH_DISPATCH_OFFSET, PATCH_DIVISOR_OFFSET,
    PATCH_EXTENT_OFFSET,
};
use crate::network::weights::MAX_LEVELS;
use crate::network::{Network, Tensor, TensorPrecision, INPUT_CHANNELS};
use crate::passes::pack_gbuffer::EngineObjects;
use crate::passes::remodulate::RemodulateInputs;
use crate::passes::segmentation;
use crate::passes::{CounterRange, RegionPasses, Texture};
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

/// The most steps the networks run in: as many as the deeper network has layers
/// (`Network::from_safetensors`: an encoder, bottleneck and decoder layer per level, less
/// one, and the output layer), as many as `PatchSlots` holds dispatches for.
const MAX_STEPS: usize = 16;
const MAX_LAYERS: usize = 2 * MAX_LEVELS + 1;
const _: () = assert!(MAX_LAYERS <= MAX_STEPS);

/// The FI and near-BE networks compiled to run side by side: one generated shader per step,
/// each running both networks' layers of that step in one dispatch. Their descriptor sets are
/// the frame ring's, after the fixed pipelines' (`Inpainting::set_layouts`).
pub struct NetworkPipelines {
    /// FI, then near-BE.
    pub networks: [Network; 2],
    /// The format every layer writes its output in.
    pub precision: TensorPrecision,
    steps: Vec<ComputePipeline>,
}

impl NetworkPipelines {
    pub fn new(gpu: &Gpu, networks: [Network; 2], precision: TensorPrecision) -> Result<Self> {
        let mut built = Self {
            networks,
            precision,
            steps: Vec::new(),
        };
        for step in 0..built.step_count() {
            let layers = built.step_layers(step);
            let what = format!("network step {step}");
            let compiled =
                codegen::compile(&codegen::wgsl(layers, precision), &what).and_then(|spirv| {
                    ComputePipeline::from_spirv(gpu, codegen::shader_info(layers), &spirv)
                        .map_err(|e| e.during(&what))
                });
            match compiled {
                Ok(pipeline) => built.steps.push(pipeline),
                Err(error) => {
                    built.destroy(&gpu.device);
                    return Err(error);
                }
            }
        }
        Ok(built)
    }

    /// A step per layer of the deeper network.
    fn step_count(&self) -> usize {
        self.networks
            .iter()
            .map(|n| n.layers.len())
            .max()
            .unwrap_or(0)
    }

    /// Each network's layer at `step`.
    fn step_layers(&self, step: usize) -> codegen::StepLayers<'_> {
        [0, 1].map(|n| self.networks[n].layers.get(step))
    }

    /// The level network `network`'s pass at `step` runs at, if it has one.
    fn step_level(&self, network: usize, step: usize) -> Option<u32> {
        self.step_layers(step)[network].map(|layer| layer.level)
    }

    /// For `plan_patches`: per network two words, four bits per step, the level of its pass at
    /// that step plus one, 0 where it has none.
    pub fn step_table(&self) -> [u32; 4] {
        let mut table = [0; 4];
        for network in 0..2 {
            for step in 0..self.step_count() {
                if let Some(level) = self.step_level(network, step) {
                    table[2 * network + step / 8] |= (level + 1) << (4 * (step % 8));
                }
            }
        }
        table
    }

    /// Each step's, in the order a run's sets take.
    fn pipelines(&self) -> impl Iterator<Item = &ComputePipeline> {
        self.steps.iter()
    }

    /// The layouts of one run's descriptor sets: one per step.
    pub fn set_layouts(&self) -> Vec<vk::DescriptorSetLayout> {
        self.pipelines().map(|p| p.set_layout).collect()
    }

    /// Descriptor counts of one run's sets together.
    pub fn pool_sizes(&self) -> Vec<vk::DescriptorPoolSize> {
        pool_sizes(self.pipelines())
    }

    pub fn destroy(&mut self, device: &ash::Device) {
        for step in &mut self.steps {
            step.destroy(device);
        }
    }
}

/// The images of one network's run: the gathered input (RGBA16F) and every layer's output (in
/// `precision`), as arrays of four channels a layer, sized for the largest patch.
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
        network: &Network,
        precision: TensorPrecision,
        max_extent: vk::Extent2D,
    ) -> Result<Self> {
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
                precision.format(),
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

/// Where a `Patch` record lives: a buffer with STORAGE and INDIRECT usage.
#[derive(Clone, Copy)]
pub struct PatchRecord {
    pub buffer: vk::Buffer,
    pub offset: u64,
}

/// The bytes of the patch records (`PatchSlots`) for the networks' patches the host chose (the
/// pipeline's are planned on the GPU): each network's `origin` and `extent` in frame texels, the
/// extent a multiple of its network's, then the steps' dispatches as `plan_patches` writes them.
/// The blend's patch is empty.
pub fn patch_slots_bytes(
    pipelines: &NetworkPipelines,
    patches: [([u32; 2], [u32; 2]); 2],
) -> Vec<u8> {
    let slot_words = (PATCH_SLOT_BYTES / 4) as usize;
    let mut words = vec![0u32; (PATCH_SLOTS_BYTES / 4) as usize];
    let dispatch = |network: usize, level: u32| {
        let extent = patches[network].1;
        extent.map(|side| (side >> level).div_ceil(GROUP_EDGE))
    };
    for (network, (origin, extent)) in patches.into_iter().enumerate() {
        let record = &mut words[network * slot_words..];
        record[..5].copy_from_slice(&[origin[0], origin[1], extent[0], extent[1], 1]);
        let levels = pipelines.networks[network].widths.len() as u32;
        for level in 0..levels {
            let at = (PATCH_DISPATCH_OFFSET / 4) as usize + 4 * level as usize;
            let [x, y] = dispatch(network, level);
            record[at..at + 3].copy_from_slice(&[x, y, 1]);
        }
    }
    let steps = &mut words[PATCH_SLOT_STEPS as usize * slot_words..];
    for step in 0..pipelines.step_count() {
        let mut groups = [0, 0];
        for network in 0..2 {
            if let Some(level) = pipelines.step_level(network, step) {
                let [x, y] = dispatch(network, level);
                groups = [groups[0].max(x), groups[1] + y];
            }
        }
        steps[4 * step..4 * step + 3].copy_from_slice(&[groups[0], groups[1], 1]);
    }
    words.iter().flat_map(|w| w.to_ne_bytes()).collect()
}

/// The networks' run in an extrapolation.
pub struct NetworkRun<'a> {
    pub pipelines: &'a NetworkPipelines,
    /// Of the layouts `NetworkPipelines::set_layouts`, in this extrapolation's region.
    pub sets: Vec<vk::DescriptorSet>,
    /// FI's, then near-BE's.
    pub tensors: [&'a NetworkTensors; 2],
    /// The patch records (`PatchSlots`, `PATCH_SLOTS_BYTES`).
    pub patches: CounterRange,
}

/// Records each step of the two networks side by side: one dispatch and one barrier a step.
/// Each network's part counts the bytes of the share of the frame and of its tensors that its
/// patch spans.
pub fn record(rec: &mut Recorder, inputs: &FrameInputs, run: &NetworkRun) {
    let patch = [PATCH_SLOT_FI, PATCH_SLOT_NEAR_BE].map(|slot| patch_record(&run.patches, slot));
    for step in 0..run.pipelines.step_count() {
        record_step(rec, inputs, run, &patch, step);
    }
}

/// Records `step` of the networks side by side: each network's layer of that step over its
/// patch `patch`, where it has one; the first step gathers from the frame in `inputs`.
fn record_step(
    rec: &mut Recorder,
    inputs: &FrameInputs,
    run: &NetworkRun,
    patch: &[PatchRecord; 2],
    step: usize,
) {
    use codegen::binding::{MAIN, MATERIAL, NETWORK_INPUT, OUTPUT, PATCH, SKIP, WARPED};
    let layers = run.pipelines.step_layers(step);
    let gathers = codegen::step_gathers(layers);
    let pass = Pass {
        pipeline: &run.pipelines.steps[step],
        set: run.sets[step],
    };
    let tensor_bindings = [0, 1].map(|network| {
        let base = network as u32 * codegen::NETWORK_BINDINGS;
        [MAIN, SKIP, NETWORK_INPUT, OUTPUT, PATCH].map(|binding| base + binding)
    });
    let material = inputs.material.unwrap_or(inputs.placeholder);
    let bound = rec.bind(pass, |mut writes| {
        if gathers {
            writes = writes
                .image(WARPED, inputs.warped)
                .image(MATERIAL, material);
        }
        for (network, layer) in layers.iter().enumerate() {
            let Some(layer) = layer else { continue };
            let tensors = run.tensors[network];
            let tensor = |tensor: Tensor| match tensor {
                Tensor::Input => &tensors.input,
                Tensor::Layer(n) => &tensors.layers[n],
            };
            let [main, skip, input, output, patch_binding] = tensor_bindings[network];
            if !gathers {
                let main_tensor = tensor(layer.main);
                writes = writes
                    .image(main, main_tensor)
                    .image(skip, layer.skip.map_or(main_tensor, tensor));
            }
            writes = writes
                .image(input, &tensors.input)
                .image(output, &tensors.layers[step])
                .buffer(patch_binding, &patch[network].range());
        }
        writes
    });
    // Each network's tensors are read and written over its patch, and the frame it gathers
    // from over the pixels the patch covers; its record is read whole.
    let frame = [WARPED, MATERIAL];
    let frame_pixels = inputs.frame_extent.width as u64 * inputs.frame_extent.height as u64;
    let mut shares: Vec<(&[u32], GpuShare)> = Vec::new();
    for network in (0..2).filter(|&network| layers[network].is_some()) {
        let texels = patch[network].texels(run.tensors[network]);
        shares.push((&tensor_bindings[network][..4], texels));
        if gathers {
            shares.push((&frame, patch[network].pixels(frame_pixels)));
        }
    }
    let step_dispatch = step_dispatch(&run.patches, step);
    if gathers {
        let params = GatherParams {
            frame_extent: [inputs.frame_extent.width, inputs.frame_extent.height],
            has_material: inputs.material.is_some() as u32,
            ..Default::default()
        };
        rec.dispatch_over_patch(&bound, &params, &step_dispatch, &shares);
    } else {
        rec.dispatch_over_patch(&bound, &(), &step_dispatch, &shares);
    }
}

/// The indirect dispatch of `step` in the patch records `patches`.
fn step_dispatch(patches: &CounterRange, step: usize) -> CounterRange {
    CounterRange {
        buffer: patches.buffer,
        offset: patches.offset + PATCH_SLOT_STEPS * PATCH_SLOT_BYTES + 16 * step as u64,
        range: 12,
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
}

/// The patch records of an extrapolation (`PatchSlots` in shaders/include/patch.wgsl): three
/// patches, each 256 bytes from the last, then the steps' dispatches.
pub const PATCH_SLOT_BYTES: u64 = 256;
pub const PATCH_SLOT_FI: u64 = 0;
pub const PATCH_SLOT_NEAR_BE: u64 = 1;
pub const PATCH_SLOT_BLEND: u64 = 2;
const PATCH_SLOT_STEPS: u64 = 3;
pub const PATCH_SLOTS_BYTES: u64 = PATCH_SLOT_STEPS * PATCH_SLOT_BYTES + 16 * MAX_STEPS as u64;

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
    /// The level of each network's pass at each step (`NetworkPipelines::step_table`).
    pub step_levels: [u32; 4],
}

/// Records `plan_patches`: the FI, near-BE and blend patches from the objects' totals in the
/// object `table`, whose list of grown rectangles it fills as well.
pub fn record_plan(
    rec: &mut Recorder,
    pass: Pass,
    extent: vk::Extent2D,
    plan: &PatchPlan,
    table: &CounterRange,
    patches: &CounterRange,
) {
    use crate::shaders::plan_patches::{binding, Params};
    let bound = rec.bind(pass, |writes| {
        writes
            .buffer(binding::TOTALS, &segmentation::object_totals(table))
            .buffer(binding::SLOTS, patches)
            .buffer(binding::LIST, &segmentation::rect_list(table))
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
        step_levels: plan.step_levels,
        ..Default::default()
    };
    let one = vk::Extent2D {
        width: 1,
        height: 1,
    };
    rec.dispatch(&bound, &params, one);
}

/// What `blend_patches` reads: the target's stencil and the grown rectangles, which give each
/// pixel's region, and the FI and near-BE networks' tensors (a network that is off this frame
/// has an empty patch, and its tensors are not read).
pub struct BlendInputs<'a> {
    /// The patch records `plan_patches` wrote.
    pub patches: CounterRange,
    pub target_objects: EngineObjects,
    /// The segmentation's object table (`segmentation::TABLE_BYTES`).
    pub table: CounterRange,
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
            .image(blend::TARGET_STENCIL, inputs.target_objects.stencil)
            .buffer(blend::RECTS, &segmentation::rect_list(&inputs.table))
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
        has_stencil: inputs.target_objects.has_stencil,
        ..Default::default()
    };
    // The stencil is read over the blend patch, each network's tensors over its own.
    let blend_patch = patch_record(patches, PATCH_SLOT_BLEND);
    rec.dispatch_sharing(
        &bound,
        &params,
        extent,
        &[
            (
                &[blend::TARGET_STENCIL],
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
    pub pipelines: NetworkPipelines,
    /// FI's, then near-BE's.
    pub tensors: [NetworkTensors; 2],
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
        let mut pipelines = NetworkPipelines::new(gpu, networks, precision)?;
        let mut tensors: Vec<NetworkTensors> = Vec::new();
        for network in &pipelines.networks {
            let [width, height] = patch_capacity(
                [max_extent.width, max_extent.height],
                max_patch_side,
                network.multiple(),
            );
            let extent = vk::Extent2D { width, height };
            match NetworkTensors::new(gpu, allocator, network, precision, extent) {
                Ok(made) => tensors.push(made),
                Err(error) => {
                    for mut made in tensors {
                        made.destroy(gpu, allocator);
                    }
                    pipelines.destroy(&gpu.device);
                    return Err(error);
                }
            }
        }
        let tensors = <[_; 2]>::try_from(tensors).unwrap_or_else(|_| unreachable!("two networks"));
        Ok(Self {
            pipelines,
            tensors,
            max_patch_side,
        })
    }

    /// Level counts for `plan_patches`: 0 for a network that is switched off.
    pub fn levels(&self, run: [bool; 2]) -> [u32; 2] {
        [0, 1].map(|i| {
            if run[i] {
                self.pipelines.networks[i].widths.len() as u32
            } else {
                0
            }
        })
    }

    /// The layouts of the networks' descriptor sets, which every region of the frame ring holds.
    pub fn set_layouts(&self) -> Vec<vk::DescriptorSetLayout> {
        self.pipelines.set_layouts()
    }

    /// Descriptor counts of the sets of `set_layouts` together.
    pub fn pool_sizes(&self) -> Vec<vk::DescriptorPoolSize> {
        self.pipelines.pool_sizes()
    }

    /// The networks' run with the sets of `passes`' region, on the region's patch records
    /// `patches`.
    pub fn run(&self, passes: &RegionPasses, patches: &CounterRange) -> NetworkRun<'_> {
        NetworkRun {
            pipelines: &self.pipelines,
            sets: (0..self.pipelines.step_count())
                .map(|n| passes.network_set(n))
                .collect(),
            tensors: self.tensors(),
            patches: *patches,
        }
    }

    pub fn tensors(&self) -> [&NetworkTensors; 2] {
        [&self.tensors[0], &self.tensors[1]]
    }

    pub fn size_bytes(&self) -> u64 {
        self.tensors.iter().map(NetworkTensors::size_bytes).sum()
    }

    /// Every tensor image, for their first layout transition.
    pub fn images(&mut self) -> impl Iterator<Item = &mut OwnedImage> {
        self.tensors
            .iter_mut()
            .flat_map(|t| std::iter::once(&mut t.input).chain(t.layers.iter_mut()))
    }

    pub fn destroy(&mut self, gpu: &Gpu, allocator: &mut Allocator) {
        self.pipelines.destroy(&gpu.device);
        for tensors in &mut self.tensors {
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
