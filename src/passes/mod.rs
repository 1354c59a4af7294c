//! The compute passes. Each file binds its pass's resources and records its dispatches through
//! `vk::recorder`, which orders them by what the shader declares it reads and writes; the math
//! lives in `shaders/` and, as the tests' oracle, in `crate::reference`. `pipeline_table!` below
//! lists every pipeline.

pub mod demodulate;
pub mod diagnostics;
pub mod fill_holes;
pub mod highlights;
pub mod inpaint;
pub mod lbp;
pub mod pack_gbuffer;
pub mod pack_output;
pub mod remodulate;
pub mod segmentation;
pub mod separate_shadows;
pub mod shadow_flow;
pub mod target_shadows;
pub mod translucency;
pub mod warp;

use std::sync::{Arc, Mutex, Weak};

use ash::vk;
use ash::vk::Handle;

use crate::abi::*;
use crate::error::Result;
use crate::shaders;
use crate::vk::device::Gpu;
use crate::vk::frame_ring::FrameRing;
use crate::vk::pipeline::ComputePipeline;
use crate::vk::recorder::Pass;

pub use crate::vk::buffer::CounterRange;
pub use crate::vk::image::Texture;

/// Byte size of `SanitizeCounters` in `shaders/include/gbuffer.wgsl`.
pub const SANITIZE_COUNTER_BYTES: u64 = 4;

/// Where a stage's time goes in the PatchEX paper's runtime table, which the reports follow.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RuntimeGroup {
    Gbuffer,
    Warping,
    Preprocessing,
    Inference,
    Blending,
    /// Copies an engine asks for (diagnostics, an output format the passes cannot store):
    /// outside the method and the runtime table.
    Output,
}

impl RuntimeGroup {
    /// The groups of the runtime table, in its order.
    pub const TABLE: [RuntimeGroup; 5] = [
        Self::Gbuffer,
        Self::Warping,
        Self::Preprocessing,
        Self::Inference,
        Self::Blending,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Self::Gbuffer => "G-buffer",
            Self::Warping => "warping",
            Self::Preprocessing => "preprocessing",
            Self::Inference => "inference",
            Self::Blending => "blending",
            Self::Output => "output",
        }
    }
}

/// One stage of the pipeline: its id in the ABI (`PATCHEX_STAGE_*`, which times and traffic
/// are reported by), the name reports give it, and its group in the runtime table.
#[derive(Clone, Copy, Debug)]
pub struct Stage {
    pub id: PatchexStage,
    pub name: &'static str,
    pub group: RuntimeGroup,
}

const fn stage(id: PatchexStage, name: &'static str, group: RuntimeGroup) -> Stage {
    Stage { id, name, group }
}

/// Every stage a frame can run, in the order they are recorded: the submit's, then each
/// extrapolation's. The recorder holds every call to this order (`Recorder::stage`) and the
/// reference follows it (`reference::extrapolate`).
pub const STAGES: [Stage; 16] = {
    use RuntimeGroup::*;
    [
        stage(PATCHEX_STAGE_PACK_SOURCE_GBUFFER, "pack source", Gbuffer),
        stage(PATCHEX_STAGE_DEMODULATE, "demodulate", Preprocessing),
        stage(PATCHEX_STAGE_SHADOW_FLOW, "shadow flow", Preprocessing),
        stage(PATCHEX_STAGE_SHADOW_WARP, "shadow warp", Warping),
        // Before the warp, which it does not wait for: its dependent passes run beside the
        // warp's, and the networks wait for both chains at one barrier.
        stage(PATCHEX_STAGE_SEGMENT, "segment", Preprocessing),
        stage(PATCHEX_STAGE_WARP, "warp", Warping),
        stage(PATCHEX_STAGE_FILL_HOLES, "fill holes", Warping),
        stage(PATCHEX_STAGE_TARGET_SHADOWS, "target shadows", Warping),
        stage(PATCHEX_STAGE_LBP, "lbp", Preprocessing),
        stage(PATCHEX_STAGE_DIAGNOSTICS, "diagnostics", Output),
        stage(PATCHEX_STAGE_INFERENCE, "inference", Inference),
        stage(PATCHEX_STAGE_BLEND, "blend", Blending),
        stage(PATCHEX_STAGE_REMODULATE, "remodulate", Blending),
        stage(PATCHEX_STAGE_HIGHLIGHTS, "highlights", Warping),
        stage(PATCHEX_STAGE_TRANSLUCENCY, "translucency", Warping),
        stage(PATCHEX_STAGE_PACK_OUTPUT, "pack output", Output),
    ]
};

/// `stage`'s position in [`STAGES`].
pub fn stage_position(stage: PatchexStage) -> usize {
    STAGES
        .iter()
        .position(|s| s.id == stage)
        .expect("every recorded stage is in STAGES")
}

/// Every pipeline the passes record with, each on one line: its shader, and how many
/// descriptor sets one region (a submit or an extrapolation) can use it with. A pipeline
/// dispatched more than once in a region with other resources needs a set for each.
macro_rules! pipeline_table {
    ($($(#[$doc:meta])* $id:ident: $shader:ident, $sets:literal;)*) => {
        /// A pipeline of `Pipelines`.
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        pub enum PipelineId {
            $($(#[$doc])* $id,)*
        }

        const TABLE: &[(shaders::ShaderInfo, usize)] = &[$((shaders::$shader::SHADER, $sets),)*];
    };
}

pipeline_table! {
    Demodulate: demodulate, 1;
    /// With a sun: frame t's highlights out of its shading, in the submit; the target's in.
    RemoveHighlights: remove_highlights, 1;
    PlaceHighlights: place_highlights, 1;
    /// With a translucency input: frame t's taken apart from its surfaces, in the submit; moved
    /// and blended over the target.
    SeparateTranslucency: separate_translucency, 1;
    PlaceTranslucency: place_translucency, 1;
    /// Frame t's G-buffer, in the submit.
    PackGbuffer: pack_gbuffer, 1;
    SeparateShadows: separate_shadows, 1;
    ShadowMaskFinest: shadow_mask_finest, 1;
    ShadowMaskPyramid: shadow_mask_pyramid, 1;
    ShadowPoly: shadow_poly, 1;
    /// Reading the estimate from either flow atlas, and the start (`shadow_flow::FlowPasses`).
    ShadowFlowIterate: shadow_flow_iterate, 3;
    /// The frame's warp (when chosen), which carries the shadow layer beside it.
    WarpGbuffer: warp_gbuffer, 1;
    WarpMotionVector: warp_motion_vector, 1;
    /// The same, and always the shadow layer moved by its flow.
    WarpOcclusionMotion: warp_occlusion_motion, 2;
    /// The G-buffer warp's hole fill.
    FillHoles: fill_holes, 1;
    /// With a target shadow input: the sun's share over frame t's shadows, then the target's.
    EstimateSunShare: estimate_sun_share, 1;
    PlaceTargetShadows: place_target_shadows, 1;
    ObjectBounds: object_bounds, 1;
    GrowRegions: grow_regions, 1;
    RegionMasks: region_masks, 1;
    Lbp: lbp, 1;
    PlanPatches: plan_patches, 1;
    BlendPatches: blend_patches, 1;
    Remodulate: remodulate, 1;
    PackOutput: pack_output, 1;
    WriteDiagnostics: write_diagnostics, 1;
    WriteShadowDiagnostics: write_shadow_diagnostics, 1;
}

/// Every pipeline of `PipelineId`, compiled. Destroyed when dropped.
pub struct Pipelines {
    built: Vec<ComputePipeline>,
    device: ash::Device,
}

/// The pipelines of each device that has a live context. Contexts on one device share them:
/// compiling is most of what `patchex_create` costs, and a CPU driver keeps some memory from
/// every compile (lavapipe 22.3: about 0.4 MB a pipeline, never returned).
static SHARED: Mutex<Vec<(u64, Weak<Pipelines>)>> = Mutex::new(Vec::new());

impl Pipelines {
    /// How many pipelines a device holds.
    pub const COUNT: usize = TABLE.len();

    fn new(gpu: &Gpu) -> Result<Self> {
        let mut pipelines = Self {
            built: Vec::new(),
            device: gpu.device.clone(),
        };
        for (shader, _) in TABLE {
            pipelines.built.push(ComputePipeline::new(gpu, *shader)?);
        }
        Ok(pipelines)
    }

    /// The pipelines of `gpu`'s device, compiled by the first context that asks for them and
    /// destroyed with the last one holding them.
    pub fn shared(gpu: &Gpu) -> Result<Arc<Self>> {
        let mut shared = SHARED
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner());
        shared.retain(|(_, pipelines)| pipelines.strong_count() > 0);
        let device = gpu.device.handle().as_raw();
        let existing = shared
            .iter()
            .find(|(owner, _)| *owner == device)
            .and_then(|(_, pipelines)| pipelines.upgrade());
        if let Some(pipelines) = existing {
            return Ok(pipelines);
        }
        let pipelines = Arc::new(Self::new(gpu)?);
        shared.push((device, Arc::downgrade(&pipelines)));
        Ok(pipelines)
    }

    pub fn get(&self, id: PipelineId) -> &ComputePipeline {
        &self.built[id as usize]
    }

    /// The pipeline of a (validated) warp kind.
    pub fn warp(kind: PatchexWarpKind) -> PipelineId {
        match kind {
            PATCHEX_WARP_MOTION_VECTOR => PipelineId::WarpMotionVector,
            PATCHEX_WARP_OCCLUSION_MOTION_VECTOR => PipelineId::WarpOcclusionMotion,
            _ => PipelineId::WarpGbuffer,
        }
    }

    /// Where the `n`th set of `id` sits among one region's sets.
    fn set_index(id: PipelineId, n: usize) -> usize {
        let (_, sets) = TABLE[id as usize];
        assert!(
            n < sets,
            "{id:?} has {sets} descriptor sets a region, not {}",
            n + 1
        );
        TABLE[..id as usize]
            .iter()
            .map(|(_, sets)| sets)
            .sum::<usize>()
            + n
    }

    /// How many descriptor sets a region holds for the pipelines; the networks' follow.
    pub fn set_count() -> usize {
        TABLE.iter().map(|(_, sets)| sets).sum()
    }

    /// The pipeline of each descriptor set a region uses, in set order.
    fn set_owners(&self) -> impl Iterator<Item = &ComputePipeline> {
        self.built
            .iter()
            .zip(TABLE)
            .flat_map(|(pipeline, (_, sets))| std::iter::repeat_n(pipeline, *sets))
    }

    /// The layout of each descriptor set a region uses, in set order.
    pub fn set_layouts(&self) -> Vec<vk::DescriptorSetLayout> {
        self.set_owners().map(|p| p.set_layout).collect()
    }

    /// Descriptor counts of one region's sets together, for the descriptor pool.
    pub fn pool_sizes(&self) -> Vec<vk::DescriptorPoolSize> {
        crate::vk::pipeline::pool_sizes(self.set_owners())
    }
}

impl Drop for Pipelines {
    fn drop(&mut self) {
        for pipeline in &mut self.built {
            pipeline.destroy(&self.device);
        }
    }
}

/// The pipelines with one region's descriptor sets in the frame ring: what a call's passes
/// record with.
pub struct RegionPasses<'a> {
    pub pipelines: &'a Pipelines,
    pub ring: &'a FrameRing,
    pub slot: usize,
    pub region: usize,
}

impl<'a> RegionPasses<'a> {
    /// `id` with its first set.
    pub fn get(&self, id: PipelineId) -> Pass<'a> {
        self.nth(id, 0)
    }

    /// The region's `n`th set after the pipelines': the networks' (`Inpainting::set_layouts`).
    pub fn network_set(&self, n: usize) -> vk::DescriptorSet {
        let set = Pipelines::set_count() + n;
        self.ring.descriptor_set(self.slot, self.region, set)
    }

    /// `bytes` of the region's counters at `offset` (`frame::counters`).
    pub fn counters(&self, offset: u64, bytes: u64) -> CounterRange {
        self.ring
            .counter_range(self.slot, self.region, offset, bytes)
    }

    /// All of the region's counters, zeroed at the start of its call.
    pub fn all_counters(&self) -> CounterRange {
        self.ring.region_counters(self.slot, self.region)
    }

    /// `id` with its `n`th set, for its `n`th dispatch with other resources in the region.
    pub fn nth(&self, id: PipelineId, n: usize) -> Pass<'a> {
        Pass {
            pipeline: self.pipelines.get(id),
            set: self
                .ring
                .descriptor_set(self.slot, self.region, Pipelines::set_index(id, n)),
        }
    }
}
