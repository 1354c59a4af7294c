// Segmentation, step 2 of 3 (Algorithm 1 of PatchEX): one invocation per object id. An object
// with pixels gets its bounding rectangle grown by k_x * mean|v_x| left and right and by
// k_y * mean|v_y| above and below, where the background it uncovers will be, clamped to the
// image, and appended to the list of rectangles.
// #import segmentation

struct Params {
    extent: vec2u,
    growth: vec2f,
}
var<immediate> params: Params;

@group(0) @binding(0) var<storage, read_write> segmentation: Segmentation;

fn mean_motion(object: u32, axis: u32, pixels: f32) -> f32 {
    let low = atomicLoad(&segmentation.objects[object].motion_low[axis]);
    let high = atomicLoad(&segmentation.objects[object].motion_high[axis]);
    return (f32(high) * 4294967296.0 + f32(low)) / (MOTION_UNITS_PER_PIXEL * pixels);
}

@compute @workgroup_size(64, 1, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    let object = id.x;
    if (object == 0u || object >= MAX_OBJECTS) {
        return;
    }
    let pixels = atomicLoad(&segmentation.objects[object].pixels);
    if (pixels == 0u) {
        return;
    }
    let low = vec2f(
        f32(0xffffffffu - atomicLoad(&segmentation.objects[object].min_flipped[0])),
        f32(0xffffffffu - atomicLoad(&segmentation.objects[object].min_flipped[1])));
    let high = vec2f(
        f32(atomicLoad(&segmentation.objects[object].max[0])),
        f32(atomicLoad(&segmentation.objects[object].max[1]))) + 1.0;
    let motion = vec2f(mean_motion(object, 0u, f32(pixels)), mean_motion(object, 1u, f32(pixels)));
    let margin = params.growth * motion;
    let grown_low = vec2u(max(floor(low - margin), vec2f(0.0)));
    let grown_high = vec2u(min(ceil(high + margin), vec2f(params.extent)));
    let slot = atomicAdd(&segmentation.rect_count, 1u);
    segmentation.rects[slot] = RegionRect(object, pixels,
        grown_low.x, grown_low.y, grown_high.x, grown_high.y, motion);
}
