//! Demodulation of frame t: reads its colour and material G-buffer, writes the shading the
//! rest of the pipeline warps, and counts the pixels whose inputs it had to sanitise.

use ash::vk;

use crate::passes::{CounterRange, Texture};
use crate::shaders::demodulate::{binding, Params};
use crate::vk::image::OwnedImage;
use crate::vk::recorder::{Pass, Recorder};

pub struct DemodulateInputs {
    pub color: Texture,
    pub base_color: Texture,
    /// `None`: Unreal's default material (metallic 0, specular 0.5); `placeholder` is bound.
    pub material: Option<Texture>,
    pub placeholder: Texture,
}

pub fn record(
    rec: &mut Recorder,
    pass: Pass,
    extent: vk::Extent2D,
    inputs: &DemodulateInputs,
    shading: &OwnedImage,
    counters: &CounterRange,
) {
    let material = inputs.material.unwrap_or(inputs.placeholder);
    let bound = rec.bind(pass, |writes| {
        writes
            .image(binding::COLOR, inputs.color)
            .image(binding::BASE_COLOR, inputs.base_color)
            .image(binding::MATERIAL, material)
            .image(binding::SHADING, shading)
            .buffer(binding::COUNTERS, counters)
    });
    let params = Params {
        extent: [extent.width, extent.height],
        has_material: inputs.material.is_some() as u32,
        ..Default::default()
    };
    rec.dispatch(&bound, &params, extent);
}
