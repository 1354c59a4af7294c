// Segmentation, step 1 of 3: every target pixel of a dynamic object (stencil id != 0) adds itself
// to its object's bounds, pixel count and sum of |motion|, by blocks. The totals start
// zero-filled.
// #import gbuffer
// #import segmentation

struct Params {
    extent: vec2u,
    // Turns the engine's motion vectors into pixels.
    motion_scale: vec2f,
    has_stencil: u32,
}
var<immediate> params: Params;

@group(0) @binding(0) var target_stencil: texture_2d<u32>;
@group(0) @binding(1) var motion: texture_2d<f32>;
@group(0) @binding(2) var<storage, read_write> totals: ObjectAccumulators;

// Pixels on a side of the block one invocation adds up. Neighbouring pixels mostly belong to one
// object, so a block reaches the table in one set of atomics rather than one per pixel: atomics
// on one address take turns on a GPU, and every pixel of an object shares its entry's.
const BLOCK: u32 = 4u;

// What a block has added up of one object so far.
struct Running {
    object: u32,
    low: vec2u,
    high: vec2u,
    pixels: u32,
    // |motion| in MOTION_UNITS_PER_PIXEL: at most 16 pixels of 2^20 units each.
    units: vec2u,
}

// Adds `units` to a (low, high) pair; the atomic's old value tells whether the low word wrapped.
fn add_motion(object: u32, axis: u32, units: u32) {
    let before = atomicAdd(&totals.objects[object].motion_low[axis], units);
    if (before > 0xffffffffu - units) {
        atomicAdd(&totals.objects[object].motion_high[axis], 1u);
    }
}

fn add_to_table(r: Running) {
    if (r.object == 0u) {
        return;
    }
    atomicMax(&totals.objects[r.object].min_flipped[0], 0xffffffffu - r.low.x);
    atomicMax(&totals.objects[r.object].min_flipped[1], 0xffffffffu - r.low.y);
    atomicMax(&totals.objects[r.object].max[0], r.high.x);
    atomicMax(&totals.objects[r.object].max[1], r.high.y);
    atomicAdd(&totals.objects[r.object].pixels, r.pixels);
    add_motion(r.object, 0u, r.units.x);
    add_motion(r.object, 1u, r.units.y);
}

fn motion_units(p: vec2u) -> vec2u {
    let v = abs(textureLoad(motion, p, 0).xy * params.motion_scale);
    // NaN counts as no motion; the warp already treats such a pixel as off-screen.
    let counted = select(vec2f(0.0), min(v, vec2f(MAX_COUNTED_MOTION)), v == v);
    return vec2u(round(counted * MOTION_UNITS_PER_PIXEL));
}

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    let origin = id.xy * BLOCK;
    let end = min(origin + BLOCK, params.extent);
    var r = Running(0u, vec2u(0u), vec2u(0u), 0u, vec2u(0u));
    for (var y = origin.y; y < end.y; y++) {
        for (var x = origin.x; x < end.x; x++) {
            let p = vec2u(x, y);
            let object = select(0u, textureLoad(target_stencil, p, 0).r, params.has_stencil != ABSENT);
            if (object == 0u || object >= MAX_OBJECTS) {
                continue;
            }
            if (object != r.object) {
                add_to_table(r);
                r = Running(object, p, p, 0u, vec2u(0u));
            }
            r.low = min(r.low, p);
            r.high = max(r.high, p);
            r.pixels += 1u;
            r.units += motion_units(p);
        }
    }
    add_to_table(r);
}
