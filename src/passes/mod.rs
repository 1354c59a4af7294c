//! The compute passes. Each file names what its pass reads and writes and records one dispatch;
//! the math lives in `shaders/` and, as the tests' oracle, in `crate::reference`.

pub mod demodulate;
pub mod pack_gbuffer;
pub mod remodulate;
pub mod warp;

use ash::vk;

use crate::abi::*;
use crate::error::Result;
use crate::shaders;
use crate::vk::device::Gpu;
use crate::vk::pipeline::ComputePipeline;

pub use crate::vk::image::Texture;

/// Every stage a frame can run, with the name reports give it.
pub const STAGE_NAMES: [(PatchexStage, &str); 5] = [
    (PATCHEX_STAGE_DEMODULATE, "demodulate"),
    (PATCHEX_STAGE_PACK_SOURCE_GBUFFER, "pack source"),
    (PATCHEX_STAGE_PACK_TARGET_GBUFFER, "pack target"),
    (PATCHEX_STAGE_WARP, "warp"),
    (PATCHEX_STAGE_REMODULATE, "remodulate"),
];

/// Every pass's pipeline. The associated constants give each one's place in per-frame descriptor sets.
pub struct Pipelines {
    pub demodulate: ComputePipeline,
    pub pack_gbuffer: ComputePipeline,
    pub warp_gbuffer: ComputePipeline,
    pub warp_motion_vector: ComputePipeline,
    pub warp_occlusion_motion: ComputePipeline,
    pub remodulate: ComputePipeline,
}

impl Pipelines {
    pub const DEMODULATE: usize = 0;
    pub const PACK_GBUFFER: usize = 1;
    pub const WARP_GBUFFER: usize = 2;
    pub const WARP_MOTION_VECTOR: usize = 3;
    pub const WARP_OCCLUSION_MOTION: usize = 4;
    pub const REMODULATE: usize = 5;

    pub fn new(gpu: &Gpu) -> Result<Self> {
        let mut built: Vec<ComputePipeline> = Vec::new();
        for shader in [
            shaders::demodulate::SHADER,
            shaders::pack_gbuffer::SHADER,
            shaders::warp_gbuffer::SHADER,
            shaders::warp_motion_vector::SHADER,
            shaders::warp_occlusion_motion::SHADER,
            shaders::remodulate::SHADER,
        ] {
            match ComputePipeline::new(gpu, shader) {
                Ok(pipeline) => built.push(pipeline),
                Err(error) => {
                    for mut pipeline in built {
                        pipeline.destroy(gpu);
                    }
                    return Err(error);
                }
            }
        }
        let [demodulate, pack_gbuffer, warp_gbuffer, warp_motion_vector, warp_occlusion_motion, remodulate] =
            <[ComputePipeline; 6]>::try_from(built)
                .ok()
                .expect("six pipelines");
        Ok(Self {
            demodulate,
            pack_gbuffer,
            warp_gbuffer,
            warp_motion_vector,
            warp_occlusion_motion,
            remodulate,
        })
    }

    /// In the order of the index constants.
    pub fn all(&self) -> [&ComputePipeline; 6] {
        [
            &self.demodulate,
            &self.pack_gbuffer,
            &self.warp_gbuffer,
            &self.warp_motion_vector,
            &self.warp_occlusion_motion,
            &self.remodulate,
        ]
    }

    /// The pipeline of a (validated) warp kind, and its index.
    pub fn warp(&self, kind: PatchexWarpKind) -> (&ComputePipeline, usize) {
        match kind {
            PATCHEX_WARP_MOTION_VECTOR => (&self.warp_motion_vector, Self::WARP_MOTION_VECTOR),
            PATCHEX_WARP_OCCLUSION_MOTION_VECTOR => {
                (&self.warp_occlusion_motion, Self::WARP_OCCLUSION_MOTION)
            }
            _ => (&self.warp_gbuffer, Self::WARP_GBUFFER),
        }
    }

    /// Descriptor counts one set of every pipeline needs together, for the descriptor pool.
    pub fn pool_sizes(&self) -> Vec<vk::DescriptorPoolSize> {
        let mut sizes: Vec<vk::DescriptorPoolSize> = Vec::new();
        for pipeline in self.all() {
            for binding in pipeline.shader.bindings {
                let ty = crate::vk::pipeline::descriptor_type(binding.kind);
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

    pub fn destroy(&mut self, gpu: &Gpu) {
        self.demodulate.destroy(gpu);
        self.pack_gbuffer.destroy(gpu);
        self.warp_gbuffer.destroy(gpu);
        self.warp_motion_vector.destroy(gpu);
        self.warp_occlusion_motion.destroy(gpu);
        self.remodulate.destroy(gpu);
    }
}
