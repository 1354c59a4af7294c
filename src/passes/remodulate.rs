//! Remodulation: multiplies the extrapolated shading by the target instant's own material in
//! place in the frame image (the engine's output, or the staging frame), counting the pixels whose inputs or result it had to
//! sanitise. With a shadow input, the shading first loses the share of light the dynamic
//! shadows take away at the target (see `shaders/remodulate.wgsl`).

use ash::vk;

use crate::passes::{CounterRange, Texture};
use crate::shaders::remodulate::{binding, Params};
use crate::vk::recorder::{Pass, Recorder};

pub struct RemodulateInputs {
    pub base_color: Texture,
    pub material: Option<Texture>,
    /// The share of light the shadows take away at the target (`warp::CarriedLayer::share`);
    /// `None` without a shadow input.
    pub shadow_share: Option<Texture>,
    pub placeholder: Texture,
}

pub fn record(
    rec: &mut Recorder,
    pass: Pass,
    extent: vk::Extent2D,
    inputs: &RemodulateInputs,
    frame: Texture,
    counters: &CounterRange,
) {
    let material = inputs.material.unwrap_or(inputs.placeholder);
    let shadow_share = inputs.shadow_share.unwrap_or(inputs.placeholder);
    let bound = rec.bind(pass, |writes| {
        writes
            .image(binding::FRAME, frame)
            .image(binding::BASE_COLOR, inputs.base_color)
            .image(binding::MATERIAL, material)
            .image(binding::SHADOW_SHARE, shadow_share)
            .buffer(binding::COUNTERS, counters)
    });
    let params = Params {
        extent: [extent.width, extent.height],
        has_material: inputs.material.is_some() as u32,
        has_shadow_share: inputs.shadow_share.is_some() as u32,
    };
    rec.dispatch(&bound, &params, extent);
}
