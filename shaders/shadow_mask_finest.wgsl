// The finest level of the shadow mask's pyramid: the mean, over blocks of `block` x `block`
// pixels (`shadow_flow::mask_step`; the last row or column of blocks repeats the frame's edge),
// of what the flow tracks of frame t: the engine's shadow mask, sanitised, on static pixels,
// and dynamic objects as lit (their shadows move with them). One invocation per texel: the
// level is small (at most `shadow_flow::FINEST_MAX_SIDE` on a side) and each texel reads a
// block of up to 8x8 pixels, so a GPU needs every texel in flight at once.
// shadow_mask_pyramid.wgsl makes the coarser levels. src/reference/separate_shadows.rs
// `flow_mask` mirrors the mask, src/reference/optical_flow.rs the level.
// #import gbuffer
// #import flow

struct Params {
    frame_size: vec2u,
    // The level's size, and its frame pixels per texel on each axis.
    level_size: vec2u,
    block: u32,
    has_stencil: u32,
}
var<immediate> params: Params;

// The engine's shadow mask and stencil of frame t.
@group(0) @binding(0) var mask: texture_2d<f32>;
@group(0) @binding(1) var source_stencil: texture_2d<u32>;
// Level 0 sits at the atlas's origin.
@group(0) @binding(2) var pyramid: texture_storage_2d<r32float, write>;

fn tracked(q: vec2i) -> f32 {
    let pixel = clamp(q, vec2i(0), vec2i(params.frame_size) - 1);
    if (stencil_object_id(source_stencil, vec2u(pixel), params.has_stencil) != 0u) {
        return 1.0;
    }
    return sanitize_unit(vec3f(textureLoad(mask, pixel, 0).r, 0.0, 0.0)).value.x;
}

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    let p = id.xy;
    if (any(p >= params.level_size)) {
        return;
    }
    let n = i32(unspecialised(params.block, mask));
    let q = n * vec2i(p);
    var sum = 0.0;
    for (var dy = 0; dy < n; dy++) {
        for (var dx = 0; dx < n; dx++) {
            sum += tracked(q + vec2i(dx, dy));
        }
    }
    textureStore(pyramid, p, vec4f(sum / f32(n * n), 0.0, 0.0, 0.0));
}
