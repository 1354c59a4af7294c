//! The sun's highlights and the sky's reflection, moved with the view (`PatchexSunLight`,
//! `PatchexSkyLight`): frame t's are taken out of its shading in the submit
//! (`shaders/remove_highlights.wgsl`), and the target's added to the extrapolated colour
//! (`shaders/place_highlights.wgsl`), both from the reflection models of
//! `shaders/include/sun_specular.wgsl` and `sky_specular.wgsl`.

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

/// A sky that lights the frame without a sun: no highlight anywhere.
pub const NO_SUN: Sun = Sun {
    direction: Vec3::Y,
    illuminance: Vec3::ZERO,
};

/// How a sky's octahedral map is laid out (`PatchexSkyLight`): its side and its mips, each half
/// the side of the one before. patchex keeps them side by side in one image, mip 0 at the left.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SkyMap {
    pub side: u32,
    pub levels: u32,
}

impl SkyMap {
    /// Where mip `level` starts in the kept image.
    pub fn offset(self, level: u32) -> u32 {
        (0..level).map(|m| self.side >> m).sum()
    }

    /// The kept image's extent: every mip side by side.
    pub fn kept_extent(self) -> vk::Extent2D {
        vk::Extent2D {
            width: self.offset(self.levels),
            height: self.side,
        }
    }
}

/// What frame t's highlights are taken out with.
pub struct SourceHighlights<'a> {
    /// The frame's sun and `PatchexSunLight.visibility`; without one (a sky alone), no pixel
    /// is lit by a sun.
    pub sun: Option<(Sun, Texture)>,
    /// With a sky: `PatchexSkyLight.radiance`, its layout, and where it is kept for the
    /// extrapolations.
    pub sky: Option<(Texture, SkyMap, &'a OwnedImage)>,
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
    let sun = inputs.sun.map_or(NO_SUN, |(sun, _)| sun);
    let shadows = inputs.shadows.as_ref();
    let separated = shadows.and_then(|s| s.separated);
    let placeholder = inputs.placeholder;
    let (color, color_without_dynamic_shadows) = separated
        .map_or((placeholder, placeholder), |(lit, unshadowed, _)| {
            (lit, unshadowed)
        });
    // Where a storage image is never touched: any of the format, which the placeholders are not.
    let untouched = Texture {
        bytes: 0,
        ..shading.into()
    };
    let bound = rec.bind(pass, |writes| {
        use remove_highlights::binding;
        let writes = match separated {
            Some((_, _, layer)) => writes.image(binding::SHADOW_LAYER, layer),
            None => writes.image(binding::SHADOW_LAYER, untouched),
        };
        let writes = match inputs.sky {
            Some((map, _, kept)) => writes
                .image(binding::SKY, map)
                .image(binding::KEPT_SKY, kept),
            None => writes
                .image(binding::SKY, placeholder)
                .image(binding::KEPT_SKY, untouched),
        };
        writes
            .image(binding::SHADING, shading)
            .image(
                binding::VISIBILITY,
                inputs.sun.map_or(placeholder, |(_, visibility)| visibility),
            )
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
        sky_levels: inputs.sky.map_or(0, |(_, sky, _)| sky.levels),
        sky_side: inputs.sky.map_or(0, |(_, sky, _)| sky.side),
        ray_at_origin: inputs.rays.at_origin.into(),
        ray_per_x: inputs.rays.per_x.into(),
        ray_per_y: inputs.rays.per_y.into(),
        has_sun: inputs.sun.is_some() as u32,
        sun_direction: sun.direction.into(),
        sun_illuminance: sun.illuminance.into(),
        ..Default::default()
    };
    // The frame, and the sky's mips, which the pass copies.
    let kept = inputs
        .sky
        .map_or(vk::Extent2D::default(), |(_, sky, _)| sky.kept_extent());
    let covered = vk::Extent2D {
        width: extent.width.max(kept.width),
        height: extent.height.max(kept.height),
    };
    rec.dispatch(&bound, &params, covered);
}

/// What the target's highlights are placed with.
pub struct TargetHighlights<'a> {
    /// Frame t's sun, or `NO_SUN`.
    pub sun: Sun,
    pub kept_visibility: &'a OwnedImage,
    /// With a sky on frame t: its mips as the removal kept them, and their layout.
    pub kept_sky: Option<(&'a OwnedImage, SkyMap)>,
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
            .image(
                binding::KEPT_SKY,
                inputs.kept_sky.map_or(placeholder, |(kept, _)| kept.into()),
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
        sky_levels: inputs.kept_sky.map_or(0, |(_, sky)| sky.levels),
        sky_side: inputs.kept_sky.map_or(0, |(_, sky)| sky.side),
        sun_direction: inputs.sun.direction.into(),
        sun_illuminance: inputs.sun.illuminance.into(),
        ..Default::default()
    };
    rec.dispatch(&bound, &params, extent);
}
