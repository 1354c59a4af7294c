//! Foveated segmentation (PatchEX section 4, Algorithm 1), three dispatches over one object table
//! in the frame's counters (`shaders/include/segmentation.wgsl`):
//! `object_bounds` accumulates each dynamic object's bounds and motion, `grow_regions` turns them
//! into grown rectangles, `region_masks` labels every pixel FI, near-BE or far-BE. With the
//! networks, their patches' planning (`inpaint::record_plan`) lists the grown rectangles in
//! place of `grow_regions`, as it reads every object's totals anyway.

use ash::vk;

use crate::abi::*;
use crate::error::{bail, Result};
use crate::passes::pack_gbuffer::EngineObjects;
use crate::passes::{CounterRange, Texture};
use crate::shaders;
use crate::vk::buffer::Buffer;
use crate::vk::image::OwnedImage;
use crate::vk::recorder::{Pass, Recorder};

/// Largest growth factor accepted; beyond it every rectangle is the whole screen anyway.
pub const MAX_GROWTH: f32 = 64.0;

/// k_x and k_y of Algorithm 1, validated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SegmentationSettings {
    pub growth: [f32; 2],
}

impl Default for SegmentationSettings {
    /// PATCHEX_DEFAULT_GROWTH_X and _Y (README, "Calibration").
    fn default() -> Self {
        Self {
            growth: [PATCHEX_DEFAULT_GROWTH_X, PATCHEX_DEFAULT_GROWTH_Y],
        }
    }
}

impl SegmentationSettings {
    pub fn from_abi(settings: &PatchexSegmentationSettings) -> Result<Self> {
        for (name, k) in [
            ("growth_x", settings.growth_x),
            ("growth_y", settings.growth_y),
        ] {
            if !(k.is_finite() && (0.0..=MAX_GROWTH).contains(&k)) {
                bail!(
                    ErrorInvalidArgument,
                    "PatchexSegmentationSettings.{name} {k} must be finite and 0 to {MAX_GROWTH}"
                );
            }
        }
        Ok(Self {
            growth: [settings.growth_x, settings.growth_y],
        })
    }
}

/// Layout of the object table in `include/segmentation.wgsl`: every object's totals, then the
/// list of grown rectangles, at a multiple of 256 bytes (the largest storage-buffer offset
/// alignment Vulkan allows) so that each part binds on its own.
pub const MAX_OBJECTS: usize = 256;
/// Pixels on a side of the block one invocation of `object_bounds.wgsl` adds up (`BLOCK`).
const OBJECT_BOUNDS_BLOCK: u32 = 4;
const OBJECT_BYTES: u64 = 36;
const RECT_BYTES: u64 = 32;
const RECT_LIST_OFFSET: u64 = MAX_OBJECTS as u64 * OBJECT_BYTES;
const RECT_COUNT_OFFSET: u64 = RECT_LIST_OFFSET;
const RECTS_OFFSET: u64 = RECT_LIST_OFFSET + 16;
pub const TABLE_BYTES: u64 = RECTS_OFFSET + MAX_OBJECTS as u64 * RECT_BYTES;
const _: () = assert!(RECT_LIST_OFFSET % 256 == 0);

/// The objects' totals in `table` (`ObjectTable` in the shaders).
pub fn object_totals(table: &CounterRange) -> CounterRange {
    CounterRange {
        range: RECT_LIST_OFFSET,
        ..*table
    }
}

/// The grown rectangles in `table` (`RectList`, `RectTable`).
pub fn rect_list(table: &CounterRange) -> CounterRange {
    CounterRange {
        buffer: table.buffer,
        offset: table.offset + RECT_LIST_OFFSET,
        range: table.range - RECT_LIST_OFFSET,
    }
}

/// Region ids in the region mask, as the shaders write them.
pub const REGION_FAR_BE: u32 = 0;
pub const REGION_NEAR_BE: u32 = 1;
pub const REGION_FI: u32 = 2;

pub struct SegmentationInputs {
    /// The target's object ids (its stencil; without one, all static).
    pub target_objects: EngineObjects,
    pub motion: Texture,
    pub motion_scale: [f32; 2],
}

/// Records every object's bounds and motion into `table`, which must be zero-filled.
pub fn record_bounds(
    rec: &mut Recorder,
    object_bounds: Pass,
    extent: vk::Extent2D,
    inputs: &SegmentationInputs,
    table: &CounterRange,
) {
    use shaders::object_bounds as bounds;
    let object_bounds = rec.bind(object_bounds, |writes| {
        writes
            .image(
                bounds::binding::TARGET_STENCIL,
                inputs.target_objects.stencil,
            )
            .image(bounds::binding::MOTION, inputs.motion)
            .buffer(bounds::binding::TOTALS, &object_totals(table))
    });
    let params = bounds::Params {
        extent: [extent.width, extent.height],
        motion_scale: inputs.motion_scale,
        has_stencil: inputs.target_objects.has_stencil,
        ..Default::default()
    };
    // One invocation per OBJECT_BOUNDS_BLOCK x OBJECT_BOUNDS_BLOCK pixels.
    let blocks = vk::Extent2D {
        width: extent.width.div_ceil(OBJECT_BOUNDS_BLOCK),
        height: extent.height.div_ceil(OBJECT_BOUNDS_BLOCK),
    };
    rec.dispatch(&object_bounds, &params, blocks);
}

/// Records the grown rectangles of the objects in `table` into its list.
pub fn record_growth(
    rec: &mut Recorder,
    grow_regions: Pass,
    extent: vk::Extent2D,
    settings: &SegmentationSettings,
    table: &CounterRange,
) {
    use shaders::grow_regions as grow;
    let grow_regions = rec.bind(grow_regions, |writes| {
        writes
            .buffer(grow::binding::TOTALS, &object_totals(table))
            .buffer(grow::binding::LIST, &rect_list(table))
    });
    let params = grow::Params {
        extent: [extent.width, extent.height],
        growth: settings.growth,
    };
    let one_per_object = vk::Extent2D {
        width: MAX_OBJECTS as u32,
        height: 1,
    };
    rec.dispatch(&grow_regions, &params, one_per_object);
}

/// Records the region of every pixel into `regions`, from the rectangles in `table`.
pub fn record_masks(
    rec: &mut Recorder,
    region_masks: Pass,
    extent: vk::Extent2D,
    inputs: &SegmentationInputs,
    table: &CounterRange,
    regions: &OwnedImage,
) {
    use shaders::region_masks as masks;
    let region_masks = rec.bind(region_masks, |writes| {
        writes
            .image(
                masks::binding::TARGET_STENCIL,
                inputs.target_objects.stencil,
            )
            .buffer(masks::binding::RECTS, &rect_list(table))
            .image(masks::binding::REGIONS, regions)
    });
    let params = masks::Params {
        extent: [extent.width, extent.height],
        has_stencil: inputs.target_objects.has_stencil,
        ..Default::default()
    };
    rec.dispatch(&region_masks, &params, extent);
}

/// What the host reads back from a finished object table.
pub struct SegmentationResult {
    pub fi_pixels: u32,
    pub near_be_pixels: u32,
    /// Every object's rectangle, sorted by object id.
    pub rects: Vec<PatchexRegionRect>,
}

pub fn read_back(counters: &Buffer, offset: u64) -> SegmentationResult {
    let word = |at: u64| counters.read_u32(offset + at);
    let count = (word(RECT_COUNT_OFFSET) as usize).min(MAX_OBJECTS);
    let mut rects: Vec<PatchexRegionRect> = (0..count as u64)
        .map(|i| {
            let field = |k: u64| word(RECTS_OFFSET + i * RECT_BYTES + 4 * k);
            let (left, top, right, bottom) = (field(2), field(3), field(4), field(5));
            PatchexRegionRect {
                object_id: field(0),
                pixel_count: field(1),
                x: left,
                y: top,
                width: right.saturating_sub(left),
                height: bottom.saturating_sub(top),
                mean_motion_x: f32::from_bits(field(6)),
                mean_motion_y: f32::from_bits(field(7)),
            }
        })
        .collect();
    rects.sort_by_key(|r| r.object_id);
    // Every FI pixel lies inside its own object's rectangle, and the near-BE pixels are the rest
    // of the rectangles' union: both follow from the table, with no pass over the frame.
    let fi_pixels = rects.iter().map(|r| r.pixel_count).sum();
    SegmentationResult {
        fi_pixels,
        near_be_pixels: union_area(&rects).saturating_sub(fi_pixels),
        rects,
    }
}

/// Pixels inside at least one of `rects`: column by column between the rectangles' x edges,
/// the merged length of the y intervals of those that span the column.
fn union_area(rects: &[PatchexRegionRect]) -> u32 {
    let mut edges: Vec<u32> = rects.iter().flat_map(|r| [r.x, r.x + r.width]).collect();
    edges.sort_unstable();
    edges.dedup();
    let mut area = 0;
    for column in edges.windows(2) {
        let (left, right) = (column[0], column[1]);
        let mut spans: Vec<(u32, u32)> = rects
            .iter()
            .filter(|r| r.x <= left && right <= r.x + r.width)
            .map(|r| (r.y, r.y + r.height))
            .collect();
        spans.sort_unstable();
        let (mut covered, mut reach) = (0, 0);
        for (top, bottom) in spans {
            let top = top.max(reach);
            if bottom > top {
                covered += bottom - top;
                reach = bottom;
            }
        }
        area += covered * (right - left);
    }
    area
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rect(x: u32, y: u32, width: u32, height: u32) -> PatchexRegionRect {
        PatchexRegionRect {
            x,
            y,
            width,
            height,
            ..Default::default()
        }
    }

    #[test]
    fn union_area_counts_overlaps_once() {
        assert_eq!(union_area(&[]), 0);
        assert_eq!(union_area(&[rect(2, 3, 4, 5)]), 20);
        // Two 4x4 squares overlapping in a 2x2 corner, and one inside the first.
        let rects = [rect(0, 0, 4, 4), rect(2, 2, 4, 4), rect(1, 1, 2, 2)];
        assert_eq!(union_area(&rects), 16 + 16 - 4);
        // Side by side, and an empty one.
        assert_eq!(
            union_area(&[rect(0, 0, 3, 2), rect(3, 0, 3, 2), rect(9, 9, 0, 4)]),
            12
        );
    }
}
