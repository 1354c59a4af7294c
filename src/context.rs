//! One plugin context: the engine's device, the plugin's pipelines and images, the frame ring,
//! and the state between `submit` (frame t) and `extrapolate` (its target instants). What a
//! call records lives in `crate::frame`.

use std::mem::ManuallyDrop;
use std::sync::Arc;

use ash::vk;
use gpu_allocator::vulkan::Allocator;

use crate::abi::*;
use crate::camera::Camera;
use crate::error::{bail, Result};
use crate::frame::counters;
use crate::frame::images::FrameImages;
use crate::frame::settings::{Defaults, Preset};
use crate::passes::inpaint::Inpainting;
use crate::passes::{Pipelines, STAGES};
use crate::vk::device::Gpu;
use crate::vk::frame_ring::FrameRing;

pub use crate::frame::settings::{Extensions, NetworkSwitches, NetworkWeightPaths};

pub const MAX_FRAMES_IN_FLIGHT: u32 = 8;

/// Largest extent accepted at creation; 8K with margin.
pub const MAX_EXTENT: u32 = 16384;

/// Frame t, as the last submit left it.
pub(crate) struct SourceFrame {
    pub frame_index: u64,
    /// Which submit of the context it was (1, 2, ...): frame indices may restart after a reset,
    /// so the frame ring and image retirement count submits instead.
    pub serial: u64,
    pub extent: vk::Extent2D,
    pub camera: Camera,
    /// What its shadow sub-task had to work with (PATCHEX_SHADOW_HISTORY_*): none, it came
    /// without a shadow input; tracked, the flow measured how its shadows drift; started or
    /// tracked, the flow ran and left its expansion for the next frame's; separated, its
    /// shadows await a target mask.
    pub shadow_history: PatchexShadowHistory,
    /// Its `PatchexSunLight` (`NO_SUN` with a sky alone): its highlights and sky reflection
    /// were taken out of its shading, and its visibility of the sun is in the highlight images.
    pub sun: Option<crate::passes::highlights::Sun>,
    /// Its `PatchexSkyLight`'s layout: its mips are kept in the sky images.
    pub sky: Option<crate::passes::highlights::SkyMap>,
    /// It came with a `PatchexTranslucencyInput`: its layer is in the translucency images;
    /// `Some(true)` with motion vectors of its own.
    pub translucency: Option<bool>,
}

impl SourceFrame {
    /// It came with a shadow input: its layer (and flow) are in the shadow images.
    pub fn has_shadows(&self) -> bool {
        self.shadow_history != PATCHEX_SHADOW_HISTORY_NONE
    }
}

pub struct Context {
    pub(crate) gpu: Gpu,
    pub(crate) allocator: ManuallyDrop<Allocator>,
    pub(crate) pipelines: Arc<Pipelines>,
    pub(crate) ring: FrameRing,
    pub(crate) images: FrameImages,
    /// PATCHEX_PRESET_NETWORKS and PATCHEX_PRESET_FULL: the two inpainting networks.
    pub(crate) inpainting: Option<Inpainting>,
    /// Which of the alternating expansion images holds the last submitted frame's.
    pub(crate) shadow_current: usize,
    pub(crate) max_extent: vk::Extent2D,
    pub(crate) preset: Preset,
    pub(crate) defaults: Defaults,
    pub(crate) source: Option<SourceFrame>,
    /// A stage left out of every call (`PATCHEX_TEST_FAULT`), to prove that a check catches a
    /// broken pass.
    pub(crate) test_fault: Option<PatchexStage>,
}

/// The environment variable naming a stage (`passes::STAGES`, spaces or underscores) whose
/// commands every call leaves out. For testing checks such as `patchex selftest` only.
pub const TEST_FAULT_VARIABLE: &str = "PATCHEX_TEST_FAULT";

/// The stage `PATCHEX_TEST_FAULT` names, if it is set; an unknown name is refused.
fn test_fault() -> Result<Option<PatchexStage>> {
    let Ok(name) = std::env::var(TEST_FAULT_VARIABLE) else {
        return Ok(None);
    };
    let name = name.replace('_', " ");
    match STAGES.iter().find(|stage| stage.name == name) {
        Some(stage) => Ok(Some(stage.id)),
        None => bail!(
            ErrorInvalidArgument,
            "{TEST_FAULT_VARIABLE}={name:?} names no stage (one of: {})",
            STAGES.map(|stage| stage.name).join(", ")
        ),
    }
}

impl Context {
    /// # Safety
    /// The handles in `info` must be live objects of one Vulkan instance.
    pub unsafe fn new(info: &PatchexCreateInfo, defaults: Extensions) -> Result<Self> {
        let preset = Preset::new(info.preset, &defaults)?;
        let test_fault = test_fault()?;
        let networks = if preset.networks {
            Some(
                defaults
                    .network_weights
                    .clone()
                    .unwrap_or_default()
                    .load()?,
            )
        } else {
            None
        };
        if !(1..=MAX_FRAMES_IN_FLIGHT).contains(&info.frames_in_flight) {
            bail!(
                ErrorInvalidArgument,
                "PatchexCreateInfo.frames_in_flight {} must be 1 to {MAX_FRAMES_IN_FLIGHT}",
                info.frames_in_flight
            );
        }
        if info.max_width == 0
            || info.max_height == 0
            || info.max_width > MAX_EXTENT
            || info.max_height > MAX_EXTENT
        {
            bail!(
                ErrorInvalidArgument,
                "PatchexCreateInfo max extent {}x{} must be 1 to {MAX_EXTENT} on each side",
                info.max_width,
                info.max_height
            );
        }
        let gpu = Gpu::load(info)?;
        FrameImages::check_formats(&gpu)?;
        let mut allocator = gpu.allocator()?;
        let pipelines = Pipelines::shared(&gpu)?;
        // The networks' descriptor sets are the ring's, so the networks come first.
        let mut inpainting = match networks {
            Some(networks) => Some(Inpainting::new(
                &gpu,
                &mut allocator,
                networks,
                defaults.network_precision.unwrap_or_default(),
                vk::Extent2D {
                    width: info.max_width,
                    height: info.max_height,
                },
                defaults
                    .network_max_patch_side
                    .unwrap_or(PATCHEX_DEFAULT_NETWORK_MAX_PATCH_SIDE),
            )?),
            None => None,
        };
        let mut set_layouts = pipelines.set_layouts();
        let mut pool_sizes = pipelines.pool_sizes();
        if let Some(inpainting) = &inpainting {
            set_layouts.extend(inpainting.set_layouts());
            pool_sizes.extend(inpainting.pool_sizes());
        }
        let ring = FrameRing::new(
            &gpu,
            &mut allocator,
            info.frames_in_flight as usize,
            &set_layouts,
            &pool_sizes,
            counters::REGION_BYTES,
        )
        .and_then(|mut ring| match FrameImages::new(&gpu, &mut allocator) {
            Ok(images) => Ok((ring, images)),
            Err(error) => {
                ring.destroy(&gpu, &mut allocator);
                Err(error)
            }
        });
        let (ring, images) = match ring {
            Ok(made) => made,
            Err(error) => {
                if let Some(inpainting) = &mut inpainting {
                    inpainting.destroy(&gpu, &mut allocator);
                }
                return Err(error);
            }
        };
        Ok(Self {
            gpu,
            allocator: ManuallyDrop::new(allocator),
            pipelines,
            ring,
            images,
            inpainting,
            shadow_current: 0,
            max_extent: vk::Extent2D {
                width: info.max_width,
                height: info.max_height,
            },
            preset,
            defaults: Defaults::new(&defaults),
            source: None,
            test_fault,
        })
    }

    /// Refuses a call recorded for another queue family than the context's.
    pub(crate) fn check_queue_family(&self, family: u32, what: &str) -> Result<()> {
        if family != self.gpu.queue_family_index {
            bail!(
                ErrorWrongQueueFamily,
                "{what}.queue_family_index is {family}, but the context records for family {}",
                self.gpu.queue_family_index
            );
        }
        Ok(())
    }
}

impl Drop for Context {
    fn drop(&mut self) {
        let gpu = &self.gpu;
        self.images.destroy(gpu, &mut self.allocator);
        if let Some(mut inpainting) = self.inpainting.take() {
            inpainting.destroy(gpu, &mut self.allocator);
        }
        self.ring.destroy(gpu, &mut self.allocator);
        // SAFETY: every allocation was freed above; the allocator is not used again.
        unsafe { ManuallyDrop::drop(&mut self.allocator) };
    }
}
