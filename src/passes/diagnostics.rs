//! Writes the engine's diagnostics images from three of the plugin's images:
//! - `shaders/write_diagnostics.wgsl` (`PatchexDiagnostics`): holes, regions and the LBP map;
//! - `shaders/write_shadow_diagnostics.wgsl` (`PatchexShadowDiagnostics`): the shadow
//!   sub-task's flow and layers.
//!
//! Both shaders bind their three sources at 0 to 2 and the diagnostics image at 3.

use ash::vk;

use crate::passes::Texture;
use crate::shaders::{write_diagnostics, write_shadow_diagnostics};
use crate::vk::image::OwnedImage;
use crate::vk::recorder::{Pass, Recorder};

/// What `write_diagnostics` reads: the warped shading (in the frame image), the region mask and
/// the LBP map.
pub fn frame_sources(warped: Texture, regions: &OwnedImage, lbp: &OwnedImage) -> [Texture; 3] {
    use write_diagnostics::binding;
    debug_assert_eq!([binding::WARPED, binding::REGIONS, binding::LBP], [0, 1, 2]);
    [warped, regions.into(), lbp.into()]
}

/// What `write_shadow_diagnostics` reads: the flow, the shadow layer and the shadows' share at
/// the target.
pub fn shadow_sources<'a>(
    flow: &'a OwnedImage,
    shadow_layer: &'a OwnedImage,
    shadow_share: &'a OwnedImage,
) -> [Texture; 3] {
    use write_shadow_diagnostics::binding;
    debug_assert_eq!(
        [binding::FLOW, binding::SHADOW_LAYER, binding::SHADOW_SHARE],
        [0, 1, 2]
    );
    [flow, shadow_layer, shadow_share].map(Texture::from)
}

/// Records either pass (`pass`) over `extent`.
pub fn record(
    rec: &mut Recorder,
    pass: Pass,
    extent: vk::Extent2D,
    sources: [Texture; 3],
    diagnostics: Texture,
) {
    use write_diagnostics::{binding, Params};
    debug_assert_eq!(
        binding::DIAGNOSTICS,
        write_shadow_diagnostics::binding::DIAGNOSTICS
    );
    let bound = rec.bind(pass, |writes| {
        writes
            .image(0, sources[0])
            .image(1, sources[1])
            .image(2, sources[2])
            .image(binding::DIAGNOSTICS, diagnostics)
    });
    let params = Params {
        extent: [extent.width, extent.height],
    };
    rec.dispatch(&bound, &params, extent);
}
