//! G-buffer-guided backward warp (ExtraSS): carries frame t's shading to the target instant with
//! a joint bilateral gather, marks holes, and counts them.

use ash::vk;

use crate::abi::{PatchexWarpSettings, PATCHEX_WARP_GBUFFER_GUIDED};
use crate::error::{bail, Result};
use crate::passes::Texture;
use crate::shaders::warp_gbuffer::{binding, Params};
use crate::vk::image::OwnedImage;
use crate::vk::pipeline::{ComputePipeline, DescriptorWrites};

pub const MAX_KERNEL_RADIUS: u32 = 3;

/// The warp's tunable weights, validated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WarpSettings {
    pub kernel_radius: u32,
    pub sigma_spatial: f32,
    pub sigma_depth: f32,
    pub sigma_normal: f32,
    pub sigma_position: f32,
}

impl Default for WarpSettings {
    /// A 3x3 gather; a texel keeps most of its weight within ~5% relative depth, ~0.1 of
    /// (1 - cos) of normal angle (about 25 degrees), and 2% of its distance in world position.
    fn default() -> Self {
        Self {
            kernel_radius: 1,
            sigma_spatial: 0.75,
            sigma_depth: 0.05,
            sigma_normal: 0.1,
            sigma_position: 0.02,
        }
    }
}

impl WarpSettings {
    pub fn from_abi(settings: &PatchexWarpSettings) -> Result<Self> {
        if settings.kind != PATCHEX_WARP_GBUFFER_GUIDED {
            bail!(
                ErrorInvalidArgument,
                "PatchexWarpSettings.kind {} is not available; this build has \
                 PATCHEX_WARP_GBUFFER_GUIDED (0)",
                settings.kind
            );
        }
        if settings.kernel_radius > MAX_KERNEL_RADIUS {
            bail!(
                ErrorInvalidArgument,
                "PatchexWarpSettings.kernel_radius {} exceeds {MAX_KERNEL_RADIUS}",
                settings.kernel_radius
            );
        }
        for (name, sigma) in [
            ("sigma_spatial", settings.sigma_spatial),
            ("sigma_depth", settings.sigma_depth),
            ("sigma_normal", settings.sigma_normal),
            ("sigma_position", settings.sigma_position),
        ] {
            if !(sigma.is_finite() && sigma > 0.0) {
                bail!(
                    ErrorInvalidArgument,
                    "PatchexWarpSettings.{name} {sigma} must be finite and positive"
                );
            }
        }
        Ok(Self {
            kernel_radius: settings.kernel_radius,
            sigma_spatial: settings.sigma_spatial,
            sigma_depth: settings.sigma_depth,
            sigma_normal: settings.sigma_normal,
            sigma_position: settings.sigma_position,
        })
    }

    pub fn params(
        &self,
        extent: vk::Extent2D,
        jitter_delta: [f32; 2],
        motion_scale: [f32; 2],
    ) -> Params {
        Params {
            extent: [extent.width, extent.height],
            jitter_delta,
            motion_scale,
            kernel_radius: self.kernel_radius as i32,
            inv_two_sigma_spatial_sq: 1.0 / (2.0 * self.sigma_spatial * self.sigma_spatial),
            inv_sigma_depth: 1.0 / self.sigma_depth,
            inv_sigma_normal: 1.0 / self.sigma_normal,
            inv_sigma_position: 1.0 / self.sigma_position,
            ..Default::default()
        }
    }
}

pub struct WarpInputs<'a> {
    pub source_shading: &'a OwnedImage,
    pub source_geometry: &'a OwnedImage,
    pub source_normal_id: &'a OwnedImage,
    pub target_geometry: &'a OwnedImage,
    pub target_normal_id: &'a OwnedImage,
    pub motion: Texture,
}

/// Where the hole counters of this warp live.
pub struct CounterRange {
    pub buffer: vk::Buffer,
    pub offset: u64,
    pub range: u64,
}

/// Byte offsets of the counters in `CounterRange`, as `WarpCounters` in the shader declares them.
pub const HOLE_PIXELS_OFFSET: u64 = 0;
pub const OFFSCREEN_PIXELS_OFFSET: u64 = 4;

#[allow(clippy::too_many_arguments)]
pub fn record(
    pipeline: &ComputePipeline,
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    set: vk::DescriptorSet,
    params: &Params,
    inputs: &WarpInputs,
    warped: &OwnedImage,
    counters: &CounterRange,
) {
    let general = vk::ImageLayout::GENERAL;
    DescriptorWrites::new(pipeline)
        .image(binding::SOURCE_SHADING, inputs.source_shading.view, general)
        .image(
            binding::SOURCE_GEOMETRY,
            inputs.source_geometry.view,
            general,
        )
        .image(
            binding::SOURCE_NORMAL_ID,
            inputs.source_normal_id.view,
            general,
        )
        .image(
            binding::TARGET_GEOMETRY,
            inputs.target_geometry.view,
            general,
        )
        .image(
            binding::TARGET_NORMAL_ID,
            inputs.target_normal_id.view,
            general,
        )
        .image(binding::MOTION, inputs.motion.view, inputs.motion.layout)
        .image(binding::WARPED, warped.view, general)
        .buffer(
            binding::COUNTERS,
            counters.buffer,
            counters.offset,
            counters.range,
        )
        .update(device, set);
    let extent = vk::Extent2D {
        width: params.extent[0],
        height: params.extent[1],
    };
    pipeline.dispatch(device, cmd, set, params, extent);
}
