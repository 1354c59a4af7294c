// Segmentation, step 1 of 3: every target pixel of a dynamic object (stencil id != 0) adds itself
// to its object's bounds, pixel count and sum of |motion|. The table starts zero-filled.
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
@group(0) @binding(2) var<storage, read_write> segmentation: Segmentation;

// Adds `units` to a (low, high) pair; the atomic's old value tells whether the low word wrapped.
fn add_motion(object: u32, axis: u32, units: u32) {
    let before = atomicAdd(&segmentation.objects[object].motion_low[axis], units);
    if (before > 0xffffffffu - units) {
        atomicAdd(&segmentation.objects[object].motion_high[axis], 1u);
    }
}

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    let p = id.xy;
    if (any(p >= params.extent)) {
        return;
    }
    let object = select(0u, textureLoad(target_stencil, p, 0).r, params.has_stencil != ABSENT);
    if (object == 0u || object >= MAX_OBJECTS) {
        return;
    }
    atomicMax(&segmentation.objects[object].min_flipped[0], 0xffffffffu - p.x);
    atomicMax(&segmentation.objects[object].min_flipped[1], 0xffffffffu - p.y);
    atomicMax(&segmentation.objects[object].max[0], p.x);
    atomicMax(&segmentation.objects[object].max[1], p.y);
    atomicAdd(&segmentation.objects[object].pixels, 1u);
    let v = abs(textureLoad(motion, p, 0).xy * params.motion_scale);
    // NaN counts as no motion; the warp already treats such a pixel as off-screen.
    let counted = select(vec2f(0.0), min(v, vec2f(MAX_COUNTED_MOTION)), v == v);
    let units = vec2u(round(counted * MOTION_UNITS_PER_PIXEL));
    add_motion(object, 0u, units.x);
    add_motion(object, 1u, units.y);
}
