//! What is drawn over the surfaces after lighting (`PatchexTranslucencyInput`): taken apart from
//! frame t's surfaces in the submit (`shaders/separate_translucency.wgsl`), then moved by its own
//! motion and blended over the extrapolated frame (`shaders/place_translucency.wgsl`).

use ash::vk;

use crate::frame::images::TranslucencyImages;
use crate::passes::pack_gbuffer::EngineGbuffer;
use crate::passes::{warp, CounterRange, Texture};
use crate::shaders::{place_translucency, separate_translucency};
use crate::vk::image::OwnedImage;
use crate::vk::recorder::{Pass, Recorder};

/// Frame t's inputs to the separation.
pub struct SourceTranslucency<'a> {
    pub color: Texture,
    pub base_color: Texture,
    pub material: Option<Texture>,
    /// `PatchexTranslucencyInput.mask`.
    pub mask: Texture,
    /// `PatchexTranslucencyInput.motion_vectors`, with its scale.
    pub motion: Option<(Texture, [f32; 2])>,
    /// Frame t's geometry motion vectors, with their scale, when it came with them.
    pub surface_motion: Option<(Texture, [f32; 2])>,
    /// `PatchexTranslucencyInput.opaque_color`: frame t's colour before its translucency.
    pub opaque: Option<Texture>,
    pub placeholder: Texture,
    pub source_depth: &'a OwnedImage,
    pub source_normal_id: &'a OwnedImage,
    /// Where the sanitised pixels are counted (frame t's).
    pub sanitized: CounterRange,
}

/// Replaces the shading of covered pixels by the surface's behind, and keeps the layer over it
/// and its motion in `kept`.
pub fn record_separation(
    rec: &mut Recorder,
    pass: Pass,
    extent: vk::Extent2D,
    inputs: &SourceTranslucency,
    shading: &OwnedImage,
    kept: &TranslucencyImages,
) {
    let bound = rec.bind(pass, |writes| {
        use separate_translucency::binding;
        writes
            .image(binding::COLOR, inputs.color)
            .image(binding::BASE_COLOR, inputs.base_color)
            .image(
                binding::MATERIAL,
                inputs.material.unwrap_or(inputs.placeholder),
            )
            .image(binding::MASK, inputs.mask)
            .image(
                binding::MOTION,
                inputs
                    .motion
                    .map_or(inputs.placeholder, |(motion, _)| motion),
            )
            .image(binding::SHADING, shading)
            .image(binding::LAYER, &kept[TranslucencyImages::LAYER])
            .image(binding::LAYER_MOTION, &kept[TranslucencyImages::MOTION])
            .image(binding::SOURCE_DEPTH, inputs.source_depth)
            .image(binding::SOURCE_NORMAL_ID, inputs.source_normal_id)
            .buffer(binding::COUNTERS, &inputs.sanitized)
            .image(
                binding::SURFACE_MOTION,
                inputs
                    .surface_motion
                    .map_or(inputs.placeholder, |(motion, _)| motion),
            )
            .image(
                binding::OPAQUE_COLOR,
                inputs.opaque.unwrap_or(inputs.placeholder),
            )
    });
    let params = separate_translucency::Params {
        extent: [extent.width, extent.height],
        has_material: inputs.material.is_some() as u32,
        has_motion: inputs.motion.is_some() as u32,
        motion_scale: inputs.motion.map_or([0.0; 2], |(_, scale)| scale),
        surface_motion_scale: inputs.surface_motion.map_or([0.0; 2], |(_, scale)| scale),
        has_surface_motion: inputs.surface_motion.is_some() as u32,
        has_opaque: inputs.opaque.is_some() as u32,
    };
    rec.dispatch(&bound, &params, extent);
}

/// What the layer is placed at the target with.
pub struct TargetTranslucency<'a> {
    pub kept: &'a TranslucencyImages,
    /// Frame t's layer came with motion of its own.
    pub has_motion: bool,
    pub target: &'a EngineGbuffer,
    pub target_motion: Texture,
    /// Frame t's packed G-buffer, which says where frame t saw the target's surface.
    pub source_depth: &'a OwnedImage,
    pub source_normal_id: &'a OwnedImage,
    /// Both instants' `Cameras` (`warp::cameras`).
    pub cameras: &'a CounterRange,
    /// The call's warp: its motion scale and jitter, and its agreement test.
    pub warp: &'a warp::Params,
    pub placeholder_uint: Texture,
    pub alpha: f32,
    /// Where the sanitised pixels are counted (the target's).
    pub sanitized: CounterRange,
}

/// Blends frame t's layer, moved to the target instant, over `frame`.
pub fn record_placement(
    rec: &mut Recorder,
    pass: Pass,
    extent: vk::Extent2D,
    inputs: &TargetTranslucency,
    frame: Texture,
) {
    let bound = rec.bind(pass, |writes| {
        use place_translucency::binding;
        writes
            .image(binding::FRAME, frame)
            .image(binding::TARGET_MOTION, inputs.target_motion)
            .image(binding::TARGET_DEPTH, inputs.target.depth)
            .image(binding::TARGET_NORMAL, inputs.target.normal)
            .image(
                binding::TARGET_STENCIL,
                inputs.target.stencil.unwrap_or(inputs.placeholder_uint),
            )
            .image(binding::SOURCE_DEPTH, inputs.source_depth)
            .image(binding::SOURCE_NORMAL_ID, inputs.source_normal_id)
            .buffer(binding::CAMERAS, inputs.cameras)
            .image(binding::LAYER, &inputs.kept[TranslucencyImages::LAYER])
            .image(
                binding::LAYER_MOTION,
                &inputs.kept[TranslucencyImages::MOTION],
            )
            .buffer(binding::COUNTERS, &inputs.sanitized)
    });
    let warp = inputs.warp;
    let params = place_translucency::Params {
        extent: [extent.width, extent.height],
        motion_scale: warp.motion_scale,
        jitter_delta: warp.jitter_delta,
        alpha: inputs.alpha,
        has_motion: inputs.has_motion as u32,
        inv_sigma_depth: warp.inv_sigma_depth,
        inv_sigma_normal: warp.inv_sigma_normal,
        inv_sigma_position: warp.inv_sigma_position,
        in_plane_weight: warp.in_plane_weight,
        pixel_angle: warp.pixel_angle,
        ..Default::default()
    };
    rec.dispatch(&bound, &params, extent);
}
