//! Farneback dense optical flow between the dynamic-caster shadow masks of frames t and t-1
//! (Farneback 2003, "Two-frame motion estimation based on polynomial expansion"): a mask
//! pyramid, each level's polynomial expansion, then coarse to fine a few iterations of
//! per-texel equations, a box sum over the window and a 2x2 solve. The result is the finest
//! level's flow, which the occlusion-motion-vector warp of the shadow layer scales up to the
//! frame as it reads it (`FrameFlow`): the displacement of each pixel of frame t to frame t-1 in
//! pixels, the convention of motion vectors.
//!
//! The pyramid starts at half the frame's resolution, or coarser in a context whose frames have
//! been larger than 1280 pixels a side (`mask_step`): shadows are soft and move as wholes, and
//! the flow costs a quarter of what it would at full resolution (time and memory), and no more
//! at larger frames, for a field that is smooth anyway. Every quantity's pyramid is one atlas
//! image: level 0 at the origin, each coarser level in a column to its right (`pyramid`). One descriptor set per pass serves
//! every level; push constants say which. The expansion of frame t-1 is the one computed at the
//! previous submit.

use ash::vk;

use crate::abi::*;
use crate::camera::PixelRays;
use crate::error::{bail, Result};
use crate::passes::pack_gbuffer::EngineObjects;
use crate::shaders;
use crate::vk::buffer::CounterRange;
use crate::vk::image::{pixels, texel_bytes, OwnedImage, Texture};
use crate::vk::recorder::{Pass, Recorder};

/// The polynomial expansion's constants, as a uniform block.
pub use crate::shaders::shadow_poly::ExpansionConstants;
pub const EXPANSION_BYTES: u64 = size_of::<ExpansionConstants>() as u64;

// The expansion and the flow's start read one block, declared once in the shared include.
const _: () = assert!(
    size_of::<ExpansionConstants>()
        == size_of::<shaders::shadow_flow_iterate::ExpansionConstants>()
);

pub const MAX_LEVELS: u32 = 6;
/// Levels `shadow_mask_finest.wgsl` makes, halving its workgroup's 8x8 tile: the default
/// pyramid's, so that only a deeper one needs `shadow_mask_pyramid.wgsl`.
const FINEST_PASS_LEVELS: u32 = 4;
/// Base-level texels on a side of a workgroup's tile in `shadow_mask_pyramid.wgsl` (`TILE`):
/// one texel of the coarsest level.
const MASK_PYRAMID_TILE: u32 = 1 << (MAX_LEVELS - FINEST_PASS_LEVELS);
pub const MAX_ITERATIONS: u32 = 10;
pub const MAX_WINDOW_RADIUS: u32 = 15;
/// The expansion's weights travel as four fields of its constants.
pub const MAX_POLY_RADIUS: u32 = 3;
const POLY_SIGMA_RANGE: std::ops::RangeInclusive<f32> = 0.1..=4.0;

/// Added to each texel's normal equations as `eps * (I, d)`: small against the structure of a
/// shadow edge (a step of 1 in the mask gives |A|^2 of about 1e-2), it only decides texels
/// whose window holds no structure, which keep the coarser estimate.
pub const REGULARIZATION: f32 = 1e-5;

/// The flow's settings, validated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlowSettings {
    pub levels: u32,
    pub iterations: u32,
    pub window_radius: u32,
    pub poly_radius: u32,
    pub poly_sigma: f32,
}

impl Default for FlowSettings {
    /// The PATCHEX_DEFAULT_FLOW_* values of the header.
    fn default() -> Self {
        Self {
            levels: PATCHEX_DEFAULT_FLOW_LEVELS,
            iterations: PATCHEX_DEFAULT_FLOW_ITERATIONS,
            window_radius: PATCHEX_DEFAULT_FLOW_WINDOW_RADIUS,
            poly_radius: PATCHEX_DEFAULT_FLOW_POLY_RADIUS,
            poly_sigma: PATCHEX_DEFAULT_FLOW_POLY_SIGMA,
        }
    }
}

impl FlowSettings {
    /// The defaults with the flow switched off (levels 0), for an engine that gives a
    /// `PatchexTargetShadowInput` on every extrapolation.
    pub fn off() -> Self {
        Self {
            levels: 0,
            ..Self::default()
        }
    }

    /// Levels 0 switch the flow off (`PatchexShadowFlowSettings.levels`).
    pub fn runs(&self) -> bool {
        self.levels > 0
    }

    /// These settings as the struct an engine chains.
    pub fn to_abi(&self) -> PatchexShadowFlowSettings {
        PatchexShadowFlowSettings {
            header: PatchexStructHeader::of::<PatchexShadowFlowSettings>(
                PATCHEX_STRUCT_TYPE_SHADOW_FLOW_SETTINGS,
            ),
            levels: self.levels,
            iterations: self.iterations,
            window_radius: self.window_radius,
            poly_radius: self.poly_radius,
            poly_sigma: self.poly_sigma,
        }
    }

    pub fn from_abi(settings: &PatchexShadowFlowSettings) -> Result<Self> {
        if settings.levels > MAX_LEVELS {
            bail!(
                ErrorInvalidArgument,
                "PatchexShadowFlowSettings.levels {} must be 0 (no flow) to {MAX_LEVELS}",
                settings.levels
            );
        }
        for (name, value, max) in [
            ("iterations", settings.iterations, MAX_ITERATIONS),
            ("window_radius", settings.window_radius, MAX_WINDOW_RADIUS),
            ("poly_radius", settings.poly_radius, MAX_POLY_RADIUS),
        ] {
            if !(1..=max).contains(&value) {
                bail!(
                    ErrorInvalidArgument,
                    "PatchexShadowFlowSettings.{name} {value} must be 1 to {max}"
                );
            }
        }
        if !POLY_SIGMA_RANGE.contains(&settings.poly_sigma) {
            bail!(
                ErrorInvalidArgument,
                "PatchexShadowFlowSettings.poly_sigma {} must be {} to {}",
                settings.poly_sigma,
                POLY_SIGMA_RANGE.start(),
                POLY_SIGMA_RANGE.end()
            );
        }
        Ok(Self {
            levels: settings.levels,
            iterations: settings.iterations,
            window_radius: settings.window_radius,
            poly_radius: settings.poly_radius,
            poly_sigma: settings.poly_sigma,
        })
    }

    /// The polynomial expansion's constants (`shaders/include/expansion.wgsl`), which the submit
    /// writes into its counters for the expansion and the flow's start.
    pub fn expansion(&self) -> ExpansionConstants {
        let r = self.poly_radius as i32;
        let sigma = self.poly_sigma as f64;
        let weight = |i: i32| (-((i * i) as f64) / (2.0 * sigma * sigma)).exp();
        let (mut sum, mut sum_xx, mut sum_xxxx, mut sum_xxyy) = (0.0, 0.0, 0.0, 0.0);
        for y in -r..=r {
            for x in -r..=r {
                let w = weight(x) * weight(y);
                let (x, y) = (x as f64, y as f64);
                sum += w;
                sum_xx += w * x * x;
                sum_xxxx += w * x * x * x * x;
                sum_xxyy += w * x * x * y * y;
            }
        }
        // Normal equations of (c, a11, a22): [[S, Sxx, Sxx], [Sxx, Sxxxx, Sxxyy],
        // [Sxx, Sxxyy, Sxxxx]]. The second row of its inverse gives a11.
        let m = glam::DMat3::from_cols_array(&[
            sum, sum_xx, sum_xx, sum_xx, sum_xxxx, sum_xxyy, sum_xx, sum_xxyy, sum_xxxx,
        ]);
        let inverse = m.inverse();
        let a_row = inverse.row(1);
        let w: Vec<f32> = (0..=3).map(|i| weight(i) as f32).collect();
        ExpansionConstants {
            radius: r,
            weight0: w[0],
            weight1: w[1],
            weight2: w[2],
            weight3: w[3],
            inv_sum_xx: (1.0 / sum_xx) as f32,
            inv_sum_xxyy: (1.0 / sum_xxyy) as f32,
            a_from_sum: a_row.x as f32,
            a_from_xx: a_row.y as f32,
            a_from_yy: a_row.z as f32,
        }
    }
}

/// One pyramid level's place in the atlases, in texels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Level {
    pub offset: [u32; 2],
    pub size: [u32; 2],
}

/// The levels of a pyramid over `extent`: level 0 at the origin, level k + 1 half of level k
/// (rounded up), stacked in a column right of level 0.
pub fn pyramid(extent: vk::Extent2D, levels: u32) -> Vec<Level> {
    let mut result = vec![Level {
        offset: [0, 0],
        size: [extent.width, extent.height],
    }];
    let mut y = 0;
    for _ in 1..levels {
        let finer = result.last().expect("level 0 is there").size;
        let size = [finer[0].div_ceil(2), finer[1].div_ceil(2)];
        result.push(Level {
            offset: [extent.width, y],
            size,
        });
        y += size[1];
    }
    result
}

/// The most texels the pyramid's finest level spans on either axis: about 640 x 360, enough for
/// a soft shadow's edge at 720p, and the cost of the flow at any larger frame.
pub const FINEST_MAX_SIDE: u32 = 640;

/// Frame pixels per texel of the pyramid's finest level on each axis, for frames up to
/// `largest` (the shadow images' extent): 2, or the next power of two that brings the level
/// within `FINEST_MAX_SIDE`.
pub fn mask_step(largest: vk::Extent2D) -> u32 {
    let mut step = 2;
    while largest.width.max(largest.height).div_ceil(step) > FINEST_MAX_SIDE {
        step *= 2;
    }
    step
}

/// The extent of the pyramid's finest level for a frame of `extent`: a `step`-th of it, rounded
/// up.
pub fn flow_extent(extent: vk::Extent2D, step: u32) -> vk::Extent2D {
    vk::Extent2D {
        width: extent.width.div_ceil(step),
        height: extent.height.div_ceil(step),
    }
}

/// The part of the atlas `levels` cover, from the origin.
pub fn span(levels: &[Level]) -> vk::Extent2D {
    levels
        .iter()
        .fold(vk::Extent2D::default(), |span, level| vk::Extent2D {
            width: span.width.max(level.offset[0] + level.size[0]),
            height: span.height.max(level.offset[1] + level.size[1]),
        })
}

/// The size of an atlas holding the pyramid of every frame up to `extent`, at every level count:
/// level 0, and the column of coarser levels, which rounding up can make taller than level 0.
pub fn atlas_extent(extent: vk::Extent2D) -> vk::Extent2D {
    span(&pyramid(flow_extent(extent, mask_step(extent)), MAX_LEVELS))
}

/// What the flow reads of frame t: the engine's shadow mask, the object ids that tell dynamic
/// pixels (taken as lit), and the packed linear depth, which with both cameras gives the flow's
/// first estimate.
#[derive(Clone, Copy)]
pub struct FrameMask<'a> {
    pub mask: Texture,
    pub source_objects: EngineObjects,
    pub source_depth: &'a OwnedImage,
}

/// The first iteration's camera constants: `reprojection` is `Camera::reprojection_into` from
/// frame t's camera into frame t-1's; `step` is the level's frame pixels per texel.
fn camera_params(reprojection: &PixelRays, step: u32) -> [[f32; 4]; 4] {
    [
        reprojection.position.extend(0.0).into(),
        reprojection.at_origin.extend(step as f32).into(),
        reprojection.per_x.extend(0.0).into(),
        reprojection.per_y.extend(0.0).into(),
    ]
}

/// The images of the flow stage. `poly_*[current]` receive frame t's expansion; the other
/// pair holds frame t-1's.
pub struct FlowImages<'a> {
    pub frame: FrameMask<'a>,
    pub mask_pyramid: &'a OwnedImage,
    pub poly: [&'a OwnedImage; 2],
    pub poly_xy: [&'a OwnedImage; 2],
    pub current: usize,
    /// The flow of every level, twice: each iteration reads its estimate from one and writes
    /// into the other, the last into the first (`FrameFlow`).
    pub flow_pyramid: [&'a OwnedImage; 2],
    /// Frame pixels per texel of the finest level (`mask_step` of the images' extent).
    pub mask_step: u32,
    /// The expansion's constants (`FlowSettings::expansion`), in the submit's counters.
    pub expansion: CounterRange,
    /// Bound where a pass reads nothing.
    pub unread: Texture,
}

/// The flow stage's passes; `iterate[i]` reads `flow_pyramid[i]` and writes the other, and
/// `start` is the coarsest level's first iteration.
pub struct FlowPasses<'a> {
    pub mask_finest: Pass<'a>,
    pub mask_pyramid: Pass<'a>,
    pub poly: Pass<'a>,
    pub iterate: [Pass<'a>; 2],
    pub start: Pass<'a>,
}

/// The flow a submit measured, as the extrapolations read it: its finest level, in the first
/// of the flow atlases, which `warp_occlusion_motion.wgsl` scales up to the frame
/// (`frame_flow` in `include/atlas.wgsl`).
#[derive(Clone, Copy)]
pub struct FrameFlow<'a> {
    pub atlas: &'a OwnedImage,
    pub finest: Level,
}

impl<'a> FrameFlow<'a> {
    /// The flow of a frame of `extent` in `atlas`, made with `mask_step` (`FlowImages`).
    pub fn of(atlas: &'a OwnedImage, mask_step: u32, extent: vk::Extent2D) -> Self {
        Self {
            atlas,
            finest: pyramid(flow_extent(extent, mask_step), 1)[0],
        }
    }
}

/// The atlases a flow iteration reads or writes over its level: both frames' expansions, the
/// estimate and the new flow.
const ITERATION_ATLASES: [u32; 6] = {
    use shaders::shadow_flow_iterate::binding::*;
    [
        POLY_CURRENT,
        POLY_XY_CURRENT,
        POLY_PREVIOUS,
        POLY_XY_PREVIOUS,
        ESTIMATE,
        FLOW,
    ]
};

/// The start's: frame t's mask in place of its expansion, and no estimate (the cameras give it,
/// from a depth texel per texel).
const START_ATLASES: [u32; 4] = {
    use shaders::shadow_flow_iterate::binding::*;
    [MASK_PYRAMID, POLY_PREVIOUS, POLY_XY_PREVIOUS, FLOW]
};

fn extent_of(level: &Level) -> vk::Extent2D {
    vk::Extent2D {
        width: level.size[0],
        height: level.size[1],
    }
}

/// Records the mask pyramid and frame t's expansion; then, when `tracked` (frame t-1's expansion
/// is there), the flow. `tracked` holds `Camera::reprojection_into` from frame t's camera into
/// frame t-1's, which starts the flow at the motion of static receivers.
pub fn record(
    rec: &mut Recorder,
    passes: &FlowPasses,
    extent: vk::Extent2D,
    settings: &FlowSettings,
    images: &FlowImages,
    tracked: Option<&PixelRays>,
) {
    let levels = pyramid(flow_extent(extent, images.mask_step), settings.levels);
    record_expansion(rec, passes, extent, settings, images, &levels);
    // Without frame t-1 to track from, the shadows stay where they are (`ShadowHistory`).
    if let Some(reprojection) = tracked {
        record_flow(rec, passes, settings, images, &levels, extent, reprojection);
    }
}

/// The mask pyramid of frame t and every level's expansion.
fn record_expansion(
    rec: &mut Recorder,
    passes: &FlowPasses,
    extent: vk::Extent2D,
    settings: &FlowSettings,
    images: &FlowImages,
    levels: &[Level],
) {
    use shaders::{shadow_mask_finest as f, shadow_mask_pyramid as m, shadow_poly as p};
    let finest = extent_of(&levels[0]);
    let mask_finest = rec.bind(passes.mask_finest, |writes| {
        writes
            .image(f::binding::MASK, images.frame.mask)
            .image(
                f::binding::SOURCE_STENCIL,
                images.frame.source_objects.stencil,
            )
            .image(f::binding::PYRAMID, images.mask_pyramid)
    });
    let params = f::Params {
        frame_size: [extent.width, extent.height],
        level_size: levels[0].size,
        block: images.mask_step,
        has_stencil: images.frame.source_objects.has_stencil,
        levels: (levels.len() as u32).min(FINEST_PASS_LEVELS),
        ..Default::default()
    };
    rec.dispatch(&mask_finest, &params, finest);
    // A deeper pyramid goes on from the coarsest level the finest pass made.
    let base = FINEST_PASS_LEVELS as usize - 1;
    if levels.len() > base + 1 {
        let mask_pyramid = rec.bind(passes.mask_pyramid, |writes| {
            writes.image(m::binding::PYRAMID, images.mask_pyramid)
        });
        let params = m::Params {
            base_offset: levels[base].offset,
            base_size: levels[base].size,
            column_offset: levels[base + 1].offset,
            levels: (levels.len() - base) as u32,
            ..Default::default()
        };
        // A workgroup per MASK_PYRAMID_TILE texels of the base level on a side.
        let [group_x, group_y, _] = m::SHADER.workgroup_size;
        let groups = vk::Extent2D {
            width: levels[base].size[0].div_ceil(MASK_PYRAMID_TILE) * group_x,
            height: levels[base].size[1].div_ceil(MASK_PYRAMID_TILE) * group_y,
        };
        rec.dispatch(&mask_pyramid, &params, groups);
    }
    let poly = rec.bind(passes.poly, |writes| {
        writes
            .image(p::binding::MASK_PYRAMID, images.mask_pyramid)
            .image(p::binding::POLY, images.poly[images.current])
            .image(p::binding::POLY_XY, images.poly_xy[images.current])
            .buffer(p::binding::EXPANSION, &images.expansion)
    });
    // Every level's expansion at once.
    let params = p::Params {
        finest_size: [finest.width, finest.height],
        levels: settings.levels,
        ..Default::default()
    };
    rec.dispatch(&poly, &params, span(levels));
}

/// The flow from frame t's and frame t-1's expansions, coarse to fine, into `flow_pyramid[0]`.
fn record_flow(
    rec: &mut Recorder,
    passes: &FlowPasses,
    settings: &FlowSettings,
    images: &FlowImages,
    levels: &[Level],
    extent: vk::Extent2D,
    reprojection: &PixelRays,
) {
    use shaders::shadow_flow_iterate as i;
    let (current, previous) = (images.current, 1 - images.current);
    // Iteration n of `total` writes flow_pyramid[(total - 1 - n) % 2], so that the last writes
    // the first, and reads its estimate from the other.
    let total = levels.len() * settings.iterations as usize;
    // The start expands frame t's mask itself, so that it can run beside the expansion.
    let bind = |rec: &mut Recorder, pass, from: usize, starts: bool| {
        let (poly_current, poly_xy_current, mask): (Texture, Texture, Texture) = match starts {
            true => (images.unread, images.unread, images.mask_pyramid.into()),
            false => (
                images.poly[current].into(),
                images.poly_xy[current].into(),
                images.unread,
            ),
        };
        rec.bind(pass, |writes| {
            writes
                .image(i::binding::POLY_CURRENT, poly_current)
                .image(i::binding::POLY_XY_CURRENT, poly_xy_current)
                .image(i::binding::POLY_PREVIOUS, images.poly[previous])
                .image(i::binding::POLY_XY_PREVIOUS, images.poly_xy[previous])
                .image(i::binding::ESTIMATE, images.flow_pyramid[from])
                .image(i::binding::FLOW, images.flow_pyramid[1 - from])
                .image(i::binding::SOURCE_DEPTH, images.frame.source_depth)
                .image(i::binding::MASK_PYRAMID, mask)
                .buffer(i::binding::EXPANSION, &images.expansion)
        })
    };
    let iterate = [0, 1].map(|from| bind(rec, passes.iterate[from], from, false));
    let start = bind(rec, passes.start, total % 2, true);
    let depth = images.frame.source_depth;
    let depth_texel_bytes = texel_bytes(depth.format, vk::ImageAspectFlags::COLOR);
    // The coarsest level starts where the cameras put static receivers.
    let [camera_offset, camera_at_origin, camera_per_x, camera_per_y] =
        camera_params(reprojection, images.mask_step << (levels.len() - 1));
    let atlas = images.mask_pyramid.extent;
    let mut n = 0;
    for (index, level) in levels.iter().enumerate().rev() {
        for iteration in 0..settings.iterations {
            // A level's first estimate is the coarser level's flow; at the coarsest, the
            // cameras'.
            let prior = match iteration {
                0 => levels.get(index + 1),
                _ => Some(level),
            };
            let estimate_level = prior.unwrap_or(level);
            let params = i::Params {
                level_offset: level.offset,
                level_size: level.size,
                prior_offset: estimate_level.offset,
                prior_size: estimate_level.size,
                frame_extent: [extent.width, extent.height],
                radius: settings.window_radius as i32,
                regularization: REGULARIZATION,
                starts: prior.is_none() as u32,
                camera_offset,
                camera_at_origin,
                camera_per_x,
                camera_per_y,
                ..Default::default()
            };
            // One workgroup per tile of the level; it reads this level and the coarser one (or
            // a depth texel per texel), and writes this level.
            let (bound, atlases, depth_bytes) = match prior {
                Some(_) => (&iterate[(total - n) % 2], &ITERATION_ATLASES[..], 0),
                None => (
                    &start,
                    &START_ATLASES[..],
                    pixels(extent_of(level)) * depth_texel_bytes,
                ),
            };
            rec.dispatch_level(
                bound,
                &params,
                (extent_of(level), atlas),
                atlases,
                depth_bytes,
            );
            n += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rounding each level up stacks the coarser levels taller than level 0 on some sizes
    /// (160 x 90: 45 rows against 23 + 12 + 6 + 3 + 2): every level of every level count, at
    /// every frame the atlas serves, lies inside it.
    #[test]
    fn every_level_lies_inside_the_atlas() {
        for (width, height) in [
            (160, 90),
            (1344, 96),
            (1920, 1080),
            (3840, 2160),
            (1, 1),
            (7, 3),
        ] {
            let largest = vk::Extent2D { width, height };
            let atlas = atlas_extent(largest);
            // The largest frame, and smaller ones the same images serve.
            let smaller = vk::Extent2D {
                width: width.div_ceil(3),
                height: height.div_ceil(2),
            };
            for extent in [largest, smaller, vk::Extent2D { width: 1, height }] {
                let finest = flow_extent(extent, mask_step(largest));
                for levels in 1..=MAX_LEVELS {
                    for level in pyramid(finest, levels) {
                        assert!(
                            level.offset[0] + level.size[0] <= atlas.width
                                && level.offset[1] + level.size[1] <= atlas.height,
                            "{level:?} of {levels} levels at {extent:?} outside {atlas:?}"
                        );
                    }
                }
            }
        }
    }
}
