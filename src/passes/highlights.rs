//! The sun's highlights, moved with the view (`PatchexSunLight`): frame t's are taken out of
//! its shading in the submit (`shaders/remove_highlights.wgsl`), and the target's added to the
//! extrapolated colour (`shaders/place_highlights.wgsl`), both from the reflection model of
//! `shaders/include/sun_specular.wgsl`.

use ash::vk;
use glam::Vec3;

use crate::camera::PixelRays;
use crate::passes::pack_gbuffer::EngineGbuffer;
use crate::passes::{warp, CounterRange, Texture};
use crate::shaders::{place_highlights, remove_highlights};
use crate::vk::image::OwnedImage;
use crate::vk::recorder::{Pass, Recorder};

/// The sun of a `PatchexSunLight`, checked: a unit direction towards it, and its illuminance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sun {
    pub direction: Vec3,
    pub illuminance: Vec3,
}

/// What frame t's highlights are taken out with.
pub struct SourceHighlights<'a> {
    pub sun: Sun,
    /// `PatchexSunLight.visibility`.
    pub visibility: Texture,
    /// With a shadow input, how its shadows are in frame t's shading.
    pub shadows: Option<ShadowsInShading<'a>>,
    pub base_color: Texture,
    pub material: Option<Texture>,
    pub placeholder: Texture,
    /// Frame t's camera.
    pub rays: PixelRays,
    pub source_depth: &'a OwnedImage,
    pub source_normal_id: &'a OwnedImage,
    /// Where the sanitised pixels are counted (frame t's).
    pub sanitized: CounterRange,
}

/// Frame t's shadow input as its highlights' removal reads it.
pub struct ShadowsInShading<'a> {
    /// `PatchexShadowInput.mask`.
    pub mask: Texture,
    /// Separated (`submit::shadows_separated`): the input's colours, and the shadow layer the
    /// separation made of them, which is made again without the highlight. Where the shading
    /// holds the dynamic shadows (dynamic objects; every pixel when not separated), the
    /// visibility (through static casters) is multiplied by the mask.
    pub separated: Option<(Texture, Texture, &'a OwnedImage)>,
}

/// Takes frame t's highlights out of `shading`, and keeps its visibility of the sun in
/// `kept_visibility` for the extrapolations.
pub fn record_removal(
    rec: &mut Recorder,
    pass: Pass,
    extent: vk::Extent2D,
    inputs: &SourceHighlights,
    shading: &OwnedImage,
    kept_visibility: &OwnedImage,
) {
    let material = inputs.material.unwrap_or(inputs.placeholder);
    let shadows = inputs.shadows.as_ref();
    let separated = shadows.and_then(|s| s.separated);
    let placeholder = inputs.placeholder;
    let (color, color_without_dynamic_shadows) = separated
        .map_or((placeholder, placeholder), |(lit, unshadowed, _)| {
            (lit, unshadowed)
        });
    let bound = rec.bind(pass, |writes| {
        use remove_highlights::binding;
        let writes = match separated {
            Some((_, _, layer)) => writes.image(binding::SHADOW_LAYER, layer),
            // Never touched: any storage image of the format, which the placeholders are not.
            None => writes.image(
                binding::SHADOW_LAYER,
                Texture {
                    bytes: 0,
                    ..shading.into()
                },
            ),
        };
        writes
            .image(binding::SHADING, shading)
            .image(binding::VISIBILITY, inputs.visibility)
            .image(binding::BASE_COLOR, inputs.base_color)
            .image(binding::MATERIAL, material)
            .image(binding::SOURCE_DEPTH, inputs.source_depth)
            .image(binding::SOURCE_NORMAL_ID, inputs.source_normal_id)
            .image(binding::KEPT_VISIBILITY, kept_visibility)
            .image(
                binding::DYNAMIC_MASK,
                shadows.map_or(placeholder, |s| s.mask),
            )
            .image(binding::COLOR, color)
            .image(
                binding::COLOR_WITHOUT_DYNAMIC_SHADOWS,
                color_without_dynamic_shadows,
            )
            .buffer(binding::COUNTERS, &inputs.sanitized)
    });
    let params = remove_highlights::Params {
        extent: [extent.width, extent.height],
        has_material: inputs.material.is_some() as u32,
        has_shadow_input: shadows.is_some() as u32,
        separated: separated.is_some() as u32,
        ray_at_origin: inputs.rays.at_origin.into(),
        ray_per_x: inputs.rays.per_x.into(),
        ray_per_y: inputs.rays.per_y.into(),
        sun_direction: inputs.sun.direction.into(),
        sun_illuminance: inputs.sun.illuminance.into(),
        ..Default::default()
    };
    rec.dispatch(&bound, &params, extent);
}

/// What the target's highlights are placed with.
pub struct TargetHighlights<'a> {
    pub sun: Sun,
    pub kept_visibility: &'a OwnedImage,
    /// Frame t's packed G-buffer, which says where frame t saw the target's surface.
    pub source_depth: &'a OwnedImage,
    pub source_normal_id: &'a OwnedImage,
    pub target: &'a EngineGbuffer,
    pub base_color: Texture,
    pub material: Option<Texture>,
    pub motion: Texture,
    /// The call's warp: its motion scale and jitter, and its agreement test, which finds where
    /// frame t saw each target pixel.
    pub warp: &'a warp::Params,
    /// Both instants' `Cameras` (`warp::cameras`).
    pub cameras: &'a CounterRange,
    /// With a shadow input: the dynamic shadows' share at the target.
    pub shadow_share: Option<Texture>,
    /// With a target shadow input placing the shadows: its mask.
    pub target_mask: Option<Texture>,
    /// Bound where a pass reads nothing: a float and an integer image.
    pub placeholders: (Texture, Texture),
    /// Where the sanitised pixels are counted (the target's).
    pub sanitized: CounterRange,
}

/// Adds the target's highlights to `frame`, the extrapolated colour.
pub fn record_placement(
    rec: &mut Recorder,
    pass: Pass,
    extent: vk::Extent2D,
    inputs: &TargetHighlights,
    frame: Texture,
) {
    let (placeholder, placeholder_uint) = inputs.placeholders;
    let bound = rec.bind(pass, |writes| {
        use place_highlights::binding;
        writes
            .image(binding::FRAME, frame)
            .image(binding::TARGET_DEPTH, inputs.target.depth)
            .image(binding::TARGET_NORMAL, inputs.target.normal)
            .image(
                binding::TARGET_STENCIL,
                inputs.target.stencil.unwrap_or(placeholder_uint),
            )
            .image(binding::BASE_COLOR, inputs.base_color)
            .image(binding::MATERIAL, inputs.material.unwrap_or(placeholder))
            .image(binding::MOTION, inputs.motion)
            .image(binding::KEPT_VISIBILITY, inputs.kept_visibility)
            .image(binding::SOURCE_DEPTH, inputs.source_depth)
            .image(binding::SOURCE_NORMAL_ID, inputs.source_normal_id)
            .image(
                binding::SHADOW_SHARE,
                inputs.shadow_share.unwrap_or(placeholder),
            )
            .image(
                binding::TARGET_MASK,
                inputs.target_mask.unwrap_or(placeholder),
            )
            .buffer(binding::CAMERAS, inputs.cameras)
            .buffer(binding::COUNTERS, &inputs.sanitized)
    });
    let warp = inputs.warp;
    let params = place_highlights::Params {
        extent: [extent.width, extent.height],
        motion_scale: warp.motion_scale,
        jitter_delta: warp.jitter_delta,
        has_material: inputs.material.is_some() as u32,
        has_shadow_share: inputs.shadow_share.is_some() as u32,
        has_target_mask: inputs.target_mask.is_some() as u32,
        inv_sigma_depth: warp.inv_sigma_depth,
        inv_sigma_normal: warp.inv_sigma_normal,
        inv_sigma_position: warp.inv_sigma_position,
        in_plane_weight: warp.in_plane_weight,
        pixel_angle: warp.pixel_angle,
        sun_direction: inputs.sun.direction.into(),
        sun_illuminance: inputs.sun.illuminance.into(),
        ..Default::default()
    };
    rec.dispatch(&bound, &params, extent);
}
