// The object table the three segmentation passes share (object_bounds, grow_regions,
// region_masks). It lives in the frame's counters, which each call copies to the host, so the
// engine reads the rectangles back through patchex_get_frame_stats; src/passes/segmentation.rs
// mirrors the layout.

// Stencil ids are 8-bit, so every id has its own entry.
const MAX_OBJECTS: u32 = 256u;
// Motion sums are kept in 1/16 pixel, in two 32-bit words each, so no object can overflow them.
const MOTION_UNITS_PER_PIXEL: f32 = 16.0;
// A pixel's |motion| counts at most this much: a larger one leaves any image (16384 at most).
const MAX_COUNTED_MOTION: f32 = 65536.0;

// Region ids in the region mask.
const REGION_FAR_BE: u32 = 0u;
const REGION_NEAR_BE: u32 = 1u;
const REGION_FI: u32 = 2u;

struct ObjectAccumulator {
    // 0xffffffff minus the smallest x and y, so that the zero-filled table means "no pixel".
    min_flipped: array<atomic<u32>, 2>,
    max: array<atomic<u32>, 2>,
    pixels: atomic<u32>,
    // Sum of |motion| per axis in MOTION_UNITS_PER_PIXEL, as (low, high) words.
    motion_low: array<atomic<u32>, 2>,
    motion_high: array<atomic<u32>, 2>,
}

struct RegionRect {
    object_id: u32,
    pixels: u32,
    // The grown rectangle, clamped to the image: [left, right) x [top, bottom).
    left: u32,
    top: u32,
    right: u32,
    bottom: u32,
    // Mean |motion| of the object's pixels, in pixels.
    mean_motion: vec2f,
}

struct Segmentation {
    // Entries of `rects` in use.
    rect_count: atomic<u32>,
    reserved: array<u32, 3>,
    rects: array<RegionRect, MAX_OBJECTS>,
    objects: array<ObjectAccumulator, MAX_OBJECTS>,
}
