//! Writes the engine's diagnostics images from three of the plugin's images:
//! - `shaders/write_diagnostics.wgsl` (`PatchexDiagnostics`): holes, regions and the LBP map;
//! - `shaders/write_shadow_diagnostics.wgsl` (`PatchexShadowDiagnostics`): the shadow
//!   sub-task's flow and layers.
//!
//! Both shaders bind their three sources at 0 to 2 and the diagnostics image at 3.

use ash::vk;

use crate::passes::shadow_flow::FrameFlow;
use crate::passes::Texture;
use crate::shaders::{write_diagnostics, write_shadow_diagnostics, PushConstants};
use crate::vk::image::OwnedImage;
use crate::vk::recorder::{Pass, Recorder};

/// What `write_diagnostics` reads: the warped shading (in the frame image), the region mask and
/// the LBP map.
pub fn frame_sources(warped: Texture, regions: &OwnedImage, lbp: &OwnedImage) -> [Texture; 3] {
    use write_diagnostics::binding;
    debug_assert_eq!([binding::WARPED, binding::REGIONS, binding::LBP], [0, 1, 2]);
    [warped, regions.into(), lbp.into()]
}

/// What `write_shadow_diagnostics` reads: the flow's atlas, the shadow layer and the shadows'
/// share at the target.
pub fn shadow_sources(
    flow_atlas: Texture,
    shadow_layer: &OwnedImage,
    shadow_share: &OwnedImage,
) -> [Texture; 3] {
    use write_shadow_diagnostics::binding;
    debug_assert_eq!(
        [
            binding::FLOW_ATLAS,
            binding::SHADOW_LAYER,
            binding::SHADOW_SHARE
        ],
        [0, 1, 2]
    );
    [flow_atlas, shadow_layer.into(), shadow_share.into()]
}

pub fn frame_params(extent: vk::Extent2D) -> write_diagnostics::Params {
    write_diagnostics::Params {
        extent: [extent.width, extent.height],
    }
}

/// `write_shadow_diagnostics`'s parameters, and the flow's atlas where the last submit measured
/// a flow (zero flow without).
pub fn shadow_params(
    extent: vk::Extent2D,
    flow: Option<FrameFlow>,
) -> (Option<Texture>, write_shadow_diagnostics::Params) {
    let params = write_shadow_diagnostics::Params {
        extent: [extent.width, extent.height],
        level_offset: flow.map_or([0; 2], |f| f.finest.offset),
        level_size: flow.map_or([0; 2], |f| f.finest.size),
    };
    (flow.map(|f| f.atlas.into()), params)
}

/// Records either pass (`pass`) over `extent`.
pub fn record<P: PushConstants>(
    rec: &mut Recorder,
    pass: Pass,
    params: &P,
    extent: vk::Extent2D,
    sources: [Texture; 3],
    diagnostics: Texture,
) {
    use write_diagnostics::binding;
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
    rec.dispatch(&bound, params, extent);
}
