// The object table of the segmentation passes (object_bounds, grow_regions, region_masks) and
// of plan_patches: each object's totals, then the list of grown rectangles. It lives in the
// frame's counters, which each call copies to the host, so the engine reads the rectangles back
// through patchex_get_frame_stats; src/passes/segmentation.rs mirrors the layout. Each pass binds
// only the part it touches, so that the passes reading one part run beside the pass writing the
// other.

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

// One object's totals as object_bounds adds them up.
struct ObjectAccumulator {
    // 0xffffffff minus the smallest x and y, so that the zero-filled table means "no pixel".
    min_flipped: array<atomic<u32>, 2>,
    max: array<atomic<u32>, 2>,
    pixels: atomic<u32>,
    // Sum of |motion| per axis in MOTION_UNITS_PER_PIXEL, as (low, high) words.
    motion_low: array<atomic<u32>, 2>,
    motion_high: array<atomic<u32>, 2>,
}

struct ObjectAccumulators {
    objects: array<ObjectAccumulator, MAX_OBJECTS>,
}

// The same totals, read once object_bounds is done.
struct ObjectTotals {
    min_flipped: array<u32, 2>,
    max: array<u32, 2>,
    pixels: u32,
    motion_low: array<u32, 2>,
    motion_high: array<u32, 2>,
}

struct ObjectTable {
    objects: array<ObjectTotals, MAX_OBJECTS>,
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

// The rectangles as grow_regions appends them.
struct RectList {
    // Entries of `rects` in use.
    rect_count: atomic<u32>,
    reserved: array<u32, 3>,
    rects: array<RegionRect, MAX_OBJECTS>,
}

// The same list, read once grow_regions is done, or written by plan_patches alone.
struct RectTable {
    rect_count: u32,
    reserved: array<u32, 3>,
    rects: array<RegionRect, MAX_OBJECTS>,
}

fn mean_motion(object: ObjectTotals, axis: u32) -> f32 {
    let units = f32(object.motion_high[axis]) * 4294967296.0 + f32(object.motion_low[axis]);
    return units / (MOTION_UNITS_PER_PIXEL * f32(object.pixels));
}

// Algorithm 1 of PatchEX: the bounding rectangle of an object with pixels, grown by
// growth.x * mean|v_x| left and right and by growth.y * mean|v_y| above and below, where the
// background it uncovers will be, clamped to the image.
fn grown_rect(id: u32, object: ObjectTotals, growth: vec2f, extent: vec2u) -> RegionRect {
    let low = vec2f(f32(0xffffffffu - object.min_flipped[0]), f32(0xffffffffu - object.min_flipped[1]));
    let high = vec2f(f32(object.max[0]), f32(object.max[1])) + 1.0;
    let motion = vec2f(mean_motion(object, 0u), mean_motion(object, 1u));
    let margin = growth * motion;
    let grown_low = vec2u(max(floor(low - margin), vec2f(0.0)));
    let grown_high = vec2u(min(ceil(high + margin), vec2f(extent)));
    return RegionRect(id, object.pixels, grown_low.x, grown_low.y, grown_high.x, grown_high.y, motion);
}
