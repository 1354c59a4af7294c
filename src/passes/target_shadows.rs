//! The shadows at the target from the engine's target shadow input (`PatchexTargetShadowInput`):
//! the sun's share of frame t's light over its shadows (`shaders/estimate_sun_share.wgsl`), then
//! the share of light the target's shadows take away (`shaders/place_target_shadows.wgsl`), in
//! place of the layer the frame's warp carried.

use ash::vk;

use crate::passes::{CounterRange, Texture};
use crate::shaders::{estimate_sun_share, place_target_shadows};
use crate::vk::image::OwnedImage;
use crate::vk::recorder::{Pass, Recorder};

/// Bytes of the sun's share sums in the counters: three channels and the darkness, u32 each.
pub const SUN_SHARE_BYTES: u64 = 16;

pub struct TargetShadowInputs<'a> {
    /// Frame t's shadow layer, with its darkness in alpha.
    pub shadow_layer: &'a OwnedImage,
    /// The engine's mask at the target.
    pub mask: Texture,
    /// The target's stencil (object ids); `None`: every pixel is static, `placeholder` is bound.
    pub stencil: Option<Texture>,
    pub placeholder_uint: Texture,
    pub sun_share: CounterRange,
    /// Where the mask's sanitised pixels are counted (the target's).
    pub sanitized: CounterRange,
}

/// `share` holds frame t's shadow layer as the frame's warp carried it, and receives the share
/// of light the target's shadows take away.
pub fn record(
    rec: &mut Recorder,
    passes: [Pass; 2],
    extent: vk::Extent2D,
    inputs: &TargetShadowInputs,
    share: &OwnedImage,
) {
    let [estimate, place] = passes;
    let bound = rec.bind(estimate, |writes| {
        writes
            .image(
                estimate_sun_share::binding::SHADOW_LAYER,
                inputs.shadow_layer,
            )
            .buffer(estimate_sun_share::binding::SUN_SHARE, &inputs.sun_share)
    });
    let params = estimate_sun_share::Params {
        extent: [extent.width, extent.height],
    };
    rec.dispatch(&bound, &params, extent);

    let stencil = inputs.stencil.unwrap_or(inputs.placeholder_uint);
    let bound = rec.bind(place, |writes| {
        use place_target_shadows::binding;
        writes
            .image(binding::SHARE, share)
            .image(binding::TARGET_MASK, inputs.mask)
            .image(binding::TARGET_STENCIL, stencil)
            .buffer(binding::SUN_SHARE, &inputs.sun_share)
            .buffer(binding::COUNTERS, &inputs.sanitized)
    });
    let params = place_target_shadows::Params {
        extent: [extent.width, extent.height],
        has_stencil: inputs.stencil.is_some() as u32,
        ..Default::default()
    };
    rec.dispatch(&bound, &params, extent);
}
