//! Remodulation: multiplies the extrapolated shading by the target instant's own material in
//! place in the frame image (the engine's output, or the staging frame), counting the pixels whose inputs or result it had to
//! sanitise. With a shadow input, the shadow is first moved in the shading (see
//! `shaders/remodulate.wgsl`).

use ash::vk;

use crate::passes::{CounterRange, Texture};
use crate::shaders::remodulate::{binding, Params};
use crate::vk::recorder::{Pass, Recorder};

pub struct RemodulateInputs {
    pub base_color: Texture,
    pub material: Option<Texture>,
    /// The shadow's change at the target (`warp::Store::ShadowChange`); `None` without a
    /// shadow input.
    pub shadow_change: Option<Texture>,
    /// The target's object ids, the engine's stencil (read for the shadow layers only); `None`:
    /// all static.
    pub target_stencil: Option<Texture>,
    pub placeholder: Texture,
    pub placeholder_uint: Texture,
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
    let (shadow_change, stencil) = match inputs.shadow_change {
        Some(change) => (
            change,
            inputs.target_stencil.unwrap_or(inputs.placeholder_uint),
        ),
        None => (inputs.placeholder, inputs.placeholder_uint),
    };
    let bound = rec.bind(pass, |writes| {
        writes
            .image(binding::FRAME, frame)
            .image(binding::BASE_COLOR, inputs.base_color)
            .image(binding::MATERIAL, material)
            .image(binding::SHADOW_CHANGE, shadow_change)
            .image(binding::TARGET_STENCIL, stencil)
            .buffer(binding::COUNTERS, counters)
    });
    let params = Params {
        extent: [extent.width, extent.height],
        has_material: inputs.material.is_some() as u32,
        has_shadow_change: inputs.shadow_change.is_some() as u32,
        has_stencil: inputs.target_stencil.is_some() as u32,
        ..Default::default()
    };
    rec.dispatch(&bound, &params, extent);
}
