//! Mirror of the segmentation passes: `object_bounds.wgsl`, `grow_regions.wgsl` and
//! `region_masks.wgsl`.

use glam::Vec2;

use super::Image;
use crate::abi::PatchexRegionRect;
use crate::passes::segmentation::{MAX_OBJECTS, REGION_FAR_BE, REGION_FI, REGION_NEAR_BE};

const MOTION_UNITS_PER_PIXEL: f32 = 16.0;
const MAX_COUNTED_MOTION: f32 = 65536.0;

pub struct Segmented {
    /// Sorted by object id, as `segmentation::read_back` returns them.
    pub rects: Vec<PatchexRegionRect>,
    /// One channel, a REGION_* id per pixel.
    pub regions: Image,
    pub fi_pixels: u32,
    pub near_be_pixels: u32,
}

#[derive(Clone, Copy, Default)]
struct Accumulator {
    min: [u32; 2],
    max: [u32; 2],
    pixels: u32,
    motion_units: [u64; 2],
}

/// `normal_id` is the target's packed normal+id image, `motion` its motion vectors.
pub fn segment(
    normal_id: &Image,
    motion: &Image,
    motion_scale: [f32; 2],
    growth: [f32; 2],
) -> Segmented {
    let (width, height) = (normal_id.width, normal_id.height);
    let object_at = |x: usize, y: usize| normal_id.at(x, y)[3] as usize;

    let mut objects = vec![
        Accumulator {
            min: [u32::MAX; 2],
            ..Default::default()
        };
        MAX_OBJECTS
    ];
    for y in 0..height {
        for x in 0..width {
            let object = object_at(x, y);
            if object == 0 || object >= MAX_OBJECTS {
                continue;
            }
            let o = &mut objects[object];
            let p = [x as u32, y as u32];
            for (axis, coordinate) in p.into_iter().enumerate() {
                o.min[axis] = o.min[axis].min(coordinate);
                o.max[axis] = o.max[axis].max(coordinate);
            }
            o.pixels += 1;
            let v = (Vec2::from_slice(motion.at(x, y)) * Vec2::from(motion_scale)).abs();
            let counted = if v.is_nan() {
                Vec2::ZERO
            } else {
                v.min(Vec2::splat(MAX_COUNTED_MOTION))
            };
            for axis in 0..2 {
                // WGSL's round() breaks ties to even; half-float motion lands on ties often.
                o.motion_units[axis] +=
                    (counted[axis] * MOTION_UNITS_PER_PIXEL).round_ties_even() as u64;
            }
        }
    }

    let extent = Vec2::new(width as f32, height as f32);
    let rects: Vec<PatchexRegionRect> = objects
        .iter()
        .enumerate()
        .filter(|(id, o)| *id != 0 && o.pixels > 0)
        .map(|(id, o)| {
            let pixels = o.pixels as f32;
            let mean =
                |axis: usize| o.motion_units[axis] as f32 / (MOTION_UNITS_PER_PIXEL * pixels);
            let motion = Vec2::new(mean(0), mean(1));
            let margin = Vec2::from(growth) * motion;
            let low = Vec2::new(o.min[0] as f32, o.min[1] as f32);
            let high = Vec2::new(o.max[0] as f32, o.max[1] as f32) + 1.0;
            let grown_low = (low - margin).floor().max(Vec2::ZERO);
            let grown_high = (high + margin).ceil().min(extent);
            PatchexRegionRect {
                object_id: id as u32,
                pixel_count: o.pixels,
                x: grown_low.x as u32,
                y: grown_low.y as u32,
                width: (grown_high.x - grown_low.x) as u32,
                height: (grown_high.y - grown_low.y) as u32,
                mean_motion_x: motion.x,
                mean_motion_y: motion.y,
            }
        })
        .collect();

    let mut regions = Image::new(width, height, 1);
    let (mut fi_pixels, mut near_be_pixels) = (0, 0);
    for y in 0..height {
        for x in 0..width {
            let inside = |r: &PatchexRegionRect| {
                (r.x..r.x + r.width).contains(&(x as u32))
                    && (r.y..r.y + r.height).contains(&(y as u32))
            };
            let region = if normal_id.at(x, y)[3] != 0.0 {
                fi_pixels += 1;
                REGION_FI
            } else if rects.iter().any(inside) {
                near_be_pixels += 1;
                REGION_NEAR_BE
            } else {
                REGION_FAR_BE
            };
            regions.set(x, y, &[region as f32]);
        }
    }
    Segmented {
        rects,
        regions,
        fi_pixels,
        near_be_pixels,
    }
}
