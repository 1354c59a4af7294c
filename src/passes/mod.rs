//! The compute passes. Each file names what its pass reads and writes and records one dispatch;
//! the math lives in `shaders/` and, as the tests' oracle, in `crate::reference`.

pub mod demodulate;
pub mod diagnostics;
pub mod inpaint;
pub mod lbp;
pub mod pack_gbuffer;
pub mod pack_output;
pub mod remodulate;
pub mod segmentation;
pub mod separate_shadows;
pub mod shadow_flow;
pub mod warp;

use std::sync::{Arc, Mutex, Weak};

use ash::vk;
use ash::vk::Handle;

use crate::abi::*;
use crate::error::Result;
use crate::shaders;
use crate::vk::device::Gpu;
use crate::vk::pipeline::ComputePipeline;

pub use crate::vk::buffer::CounterRange;
pub use crate::vk::image::Texture;

/// Byte size of `SanitizeCounters` in `shaders/include/gbuffer.wgsl`.
pub const SANITIZE_COUNTER_BYTES: u64 = 4;

/// Every stage a frame can run, with the name reports give it.
pub const STAGE_NAMES: [(PatchexStage, &str); 13] = [
    (PATCHEX_STAGE_DEMODULATE, "demodulate"),
    (PATCHEX_STAGE_PACK_SOURCE_GBUFFER, "pack source"),
    (PATCHEX_STAGE_SHADOW_FLOW, "shadow flow"),
    (PATCHEX_STAGE_PACK_TARGET_GBUFFER, "pack target"),
    (PATCHEX_STAGE_WARP, "warp"),
    (PATCHEX_STAGE_SHADOW_WARP, "shadow warp"),
    (PATCHEX_STAGE_SEGMENT, "segment"),
    (PATCHEX_STAGE_LBP, "lbp"),
    (PATCHEX_STAGE_INFERENCE, "inference"),
    (PATCHEX_STAGE_BLEND, "blend"),
    (PATCHEX_STAGE_REMODULATE, "remodulate"),
    (PATCHEX_STAGE_PACK_OUTPUT, "pack output"),
    (PATCHEX_STAGE_DIAGNOSTICS, "diagnostics"),
];

/// Every pass's pipeline, at the index of its constant, which is also its place in the
/// per-frame descriptor sets. Destroyed when dropped.
pub struct Pipelines {
    built: Vec<ComputePipeline>,
    device: ash::Device,
}

/// The pipelines of each device that has a live context. Contexts on one device share them:
/// compiling is most of what `patchex_create` costs, and a CPU driver keeps some memory from
/// every compile (lavapipe 22.3: about 0.4 MB a pipeline, never returned).
static SHARED: Mutex<Vec<(u64, Weak<Pipelines>)>> = Mutex::new(Vec::new());

impl Pipelines {
    pub const DEMODULATE: usize = 0;
    pub const PACK_GBUFFER: usize = 1;
    pub const WARP_GBUFFER: usize = 2;
    pub const WARP_MOTION_VECTOR: usize = 3;
    pub const WARP_OCCLUSION_MOTION: usize = 4;
    pub const OBJECT_BOUNDS: usize = 5;
    pub const GROW_REGIONS: usize = 6;
    pub const REGION_MASKS: usize = 7;
    pub const LBP: usize = 8;
    pub const REMODULATE: usize = 9;
    pub const WRITE_DIAGNOSTICS: usize = 10;
    pub const SEPARATE_SHADOWS: usize = 11;
    pub const SHADOW_PYRAMID: usize = 12;
    pub const SHADOW_POLY: usize = 13;
    pub const SHADOW_FLOW_MATRICES: usize = 14;
    pub const SHADOW_FLOW_ROWS: usize = 15;
    pub const SHADOW_FLOW_SOLVE: usize = 16;
    pub const WRITE_SHADOW_DIAGNOSTICS: usize = 17;
    pub const SHADOW_FLOW_UPSAMPLE: usize = 18;
    pub const PLAN_PATCHES: usize = 19;
    pub const BLEND_PATCHES: usize = 20;
    pub const PACK_OUTPUT: usize = 21;

    /// How many pipelines a device holds.
    pub const COUNT: usize = Self::SHADERS.len();

    /// Descriptor sets are indexed by pipeline, then come the sets of the warps' second
    /// dispatches in one extrapolation, on the shadow layer: the occlusion-motion-vector warp
    /// driven by the shadow's flow, and the frame's own warp (`surface_layer_set`).
    pub const SHADOW_WARP_SET: usize = Self::COUNT;
    const EXTRA_SETS: [usize; 4] = [
        Self::WARP_OCCLUSION_MOTION,
        Self::WARP_GBUFFER,
        Self::WARP_MOTION_VECTOR,
        Self::WARP_OCCLUSION_MOTION,
    ];

    /// The set for running the warp pipeline `warp_index` on the shadow layer.
    pub fn surface_layer_set(warp_index: usize) -> usize {
        Self::COUNT
            + match warp_index {
                Self::WARP_GBUFFER => 1,
                Self::WARP_MOTION_VECTOR => 2,
                _ => 3,
            }
    }

    const SHADERS: [shaders::ShaderInfo; 22] = [
        shaders::demodulate::SHADER,
        shaders::pack_gbuffer::SHADER,
        shaders::warp_gbuffer::SHADER,
        shaders::warp_motion_vector::SHADER,
        shaders::warp_occlusion_motion::SHADER,
        shaders::object_bounds::SHADER,
        shaders::grow_regions::SHADER,
        shaders::region_masks::SHADER,
        shaders::lbp::SHADER,
        shaders::remodulate::SHADER,
        shaders::write_diagnostics::SHADER,
        shaders::separate_shadows::SHADER,
        shaders::shadow_pyramid::SHADER,
        shaders::shadow_poly::SHADER,
        shaders::shadow_flow_matrices::SHADER,
        shaders::shadow_flow_rows::SHADER,
        shaders::shadow_flow_solve::SHADER,
        shaders::write_shadow_diagnostics::SHADER,
        shaders::shadow_flow_upsample::SHADER,
        shaders::plan_patches::SHADER,
        shaders::blend_patches::SHADER,
        shaders::pack_output::SHADER,
    ];

    fn new(gpu: &Gpu) -> Result<Self> {
        let mut pipelines = Self {
            built: Vec::new(),
            device: gpu.device.clone(),
        };
        for shader in Self::SHADERS {
            pipelines.built.push(ComputePipeline::new(gpu, shader)?);
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

    pub fn get(&self, index: usize) -> &ComputePipeline {
        &self.built[index]
    }

    /// In the order of the index constants.
    pub fn all(&self) -> &[ComputePipeline] {
        &self.built
    }

    /// The index of a (validated) warp kind's pipeline.
    pub fn warp(kind: PatchexWarpKind) -> usize {
        match kind {
            PATCHEX_WARP_MOTION_VECTOR => Self::WARP_MOTION_VECTOR,
            PATCHEX_WARP_OCCLUSION_MOTION_VECTOR => Self::WARP_OCCLUSION_MOTION,
            _ => Self::WARP_GBUFFER,
        }
    }

    /// The pipeline of each descriptor set a region uses, in set order.
    fn set_owners(&self) -> impl Iterator<Item = &ComputePipeline> {
        self.built
            .iter()
            .chain(Self::EXTRA_SETS.iter().map(|&index| &self.built[index]))
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
