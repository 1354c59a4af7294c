// The shadow mask's pyramid, its finest level and the next three: the mean, over blocks of
// `block` x `block` pixels (`shadow_flow::mask_step`; the last row or column of blocks repeats
// the frame's edge), of what the flow tracks of frame t: the engine's shadow mask, sanitised,
// on static pixels, and dynamic objects as lit (their shadows move with them). One invocation
// per finest texel: the level is small (at most `shadow_flow::FINEST_MAX_SIDE` on a side) and
// each texel reads a block of up to 8x8 pixels, so a GPU needs every texel in flight at once.
// Each coarser texel is the mean of the 2x2 finer texels it covers (the last row or column of
// an odd-sized level repeats); a workgroup halves its 8x8 tile in workgroup memory, so the
// default pyramid's four levels need no pass of their own. shadow_mask_pyramid.wgsl makes any
// levels beyond. src/reference/separate_shadows.rs `flow_mask` mirrors the mask,
// src/reference/optical_flow.rs the levels.
// #import gbuffer
// #import flow
// #import mask_tile

struct Params {
    frame_size: vec2u,
    // The finest level's size, and its frame pixels per texel on each axis.
    level_size: vec2u,
    block: u32,
    has_stencil: u32,
    // Levels this pass writes: 1 to `shadow_flow::FINEST_PASS_LEVELS`.
    levels: u32,
}
var<immediate> params: Params;

// The engine's shadow mask and stencil of frame t.
@group(0) @binding(0) var mask: texture_2d<f32>;
@group(0) @binding(1) var source_stencil: texture_2d<u32>;
// Level 0 sits at the atlas's origin, the coarser levels in a column right of it
// (`shadow_flow::pyramid`).
@group(0) @binding(2) var pyramid: texture_storage_2d<r32float, write>;

const TILE: u32 = 8u;
// Every level's part of the tile, the finest first: 8^2 + 4^2 + 2^2 + 1.
var<workgroup> tile: array<f32, 85>;

fn tracked(q: vec2i) -> f32 {
    let pixel = clamp(q, vec2i(0), vec2i(params.frame_size) - 1);
    if (stencil_object_id(source_stencil, vec2u(pixel), params.has_stencil) != 0u) {
        return 1.0;
    }
    return sanitize_unit(vec3f(textureLoad(mask, pixel, 0).r, 0.0, 0.0)).value.x;
}

@compute @workgroup_size(8, 8, 1)
fn main(
    @builtin(global_invocation_id) id: vec3u,
    @builtin(workgroup_id) group: vec3u,
    @builtin(local_invocation_index) lane: u32,
) {
    let p = id.xy;
    var size = params.level_size;
    if (all(p < size)) {
        let n = i32(unspecialised(params.block, mask));
        let q = n * vec2i(p);
        var sum = 0.0;
        for (var dy = 0; dy < n; dy++) {
            for (var dx = 0; dx < n; dx++) {
                sum += tracked(q + vec2i(dx, dy));
            }
        }
        let value = sum / f32(n * n);
        tile[lane] = value;
        textureStore(pyramid, p, vec4f(value, 0.0, 0.0, 0.0));
    }
    // The texels a coarser texel covers, clamped at the level's edge, lie in its own tile.
    var side = TILE;
    var origin = group.xy * side;
    var offset = vec2u(size.x, 0u);
    var finer_base = 0u;
    let levels = unspecialised(params.levels, mask);
    for (var level = 1u; level < levels; level++) {
        workgroupBarrier();
        let finer_side = side;
        let finer_size = size;
        let finer_origin = origin;
        let base = finer_base + finer_side * finer_side;
        side /= 2u;
        origin /= 2u;
        size = (size + 1u) / 2u;
        let local = vec2u(lane % side, lane / side);
        let c = origin + local;
        if (lane < side * side && all(c < size)) {
            let value = coarser_texel(c, finer_base, finer_side, finer_origin, finer_size);
            tile[base + lane] = value;
            textureStore(pyramid, offset + c, vec4f(value, 0.0, 0.0, 0.0));
        }
        finer_base = base;
        offset.y += size.y;
    }
}
