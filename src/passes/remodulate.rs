//! Remodulation: multiplies the extrapolated shading by the target instant's own material in
//! place in the frame image (the engine's output, or the staging frame), counting the pixels
//! whose inputs or result it had to sanitise. With a shadow input, the shading first loses the
//! share of light the dynamic shadows take away at the target (`shaders/include/remodulation.wgsl`).
//! With the networks the blend remodulates as it writes (`inpaint::record_blend`), and this pass
//! does not run.

use ash::vk;

use crate::passes::{CounterRange, Texture};
use crate::shaders::remodulate::{binding, Params};
use crate::shaders::{blend_patches, remodulate};
use crate::vk::pipeline::DescriptorWrites;
use crate::vk::recorder::{Pass, Recorder};

pub struct RemodulateInputs {
    pub base_color: Texture,
    pub material: Option<Texture>,
    /// The share of light the shadows take away at the target (`warp::CarriedLayer::share`);
    /// `None` without a shadow input.
    pub shadow_share: Option<Texture>,
    pub placeholder: Texture,
}

// Every pass that remodulates binds include/remodulation.wgsl's inputs at its numbers.
const _: () = assert!(
    blend_patches::binding::BASE_COLOR == remodulate::binding::BASE_COLOR
        && blend_patches::binding::MATERIAL == remodulate::binding::MATERIAL
        && blend_patches::binding::SHADOW_SHARE == remodulate::binding::SHADOW_SHARE
        && blend_patches::binding::COUNTERS == remodulate::binding::COUNTERS
        && blend_patches::binding::FRAME == remodulate::binding::FRAME
);

impl RemodulateInputs {
    /// Binds the frame and what include/remodulation.wgsl reads, with `counters` for what it
    /// sanitises.
    pub fn bind<'p>(
        &self,
        writes: DescriptorWrites<'p>,
        frame: Texture,
        counters: &CounterRange,
    ) -> DescriptorWrites<'p> {
        writes
            .image(binding::FRAME, frame)
            .image(binding::BASE_COLOR, self.base_color)
            .image(binding::MATERIAL, self.material.unwrap_or(self.placeholder))
            .image(
                binding::SHADOW_SHARE,
                self.shadow_share.unwrap_or(self.placeholder),
            )
            .buffer(binding::COUNTERS, counters)
    }

    /// Which of the optional inputs there are, as the shaders' parameters take them.
    pub fn present(&self) -> (u32, u32) {
        (
            self.material.is_some() as u32,
            self.shadow_share.is_some() as u32,
        )
    }
}

pub fn record(
    rec: &mut Recorder,
    pass: Pass,
    extent: vk::Extent2D,
    inputs: &RemodulateInputs,
    frame: Texture,
    counters: &CounterRange,
) {
    let bound = rec.bind(pass, |writes| inputs.bind(writes, frame, counters));
    let (has_material, has_shadow_share) = inputs.present();
    let params = Params {
        extent: [extent.width, extent.height],
        has_material,
        has_shadow_share,
    };
    rec.dispatch(&bound, &params, extent);
}
