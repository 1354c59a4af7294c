// The shadow mask's pyramid, every level in one dispatch (as FidelityFX's single-pass
// downsampler makes mips). The finest level is the mean, over blocks of `block` x `block` pixels
// (`shadow_flow::mask_step`; the last row or column of blocks repeats the frame's edge), of what
// the flow tracks of frame t: the engine's shadow mask, sanitised, on static pixels, and dynamic
// objects as lit (their shadows move with them). Each coarser texel is the mean of the 2x2 finer
// texels it covers (the last row or column of an odd-sized level repeats). A workgroup makes a
// TILE x TILE tile of the finest level and halves it in workgroup memory, level by level: the
// texels a coarser texel covers, clamped at the level's edge, lie in its own tile, so no level
// waits for another workgroup. src/reference/separate_shadows.rs `flow_mask` mirrors the mask,
// src/reference/optical_flow.rs the pyramid.
// #import gbuffer
// #import flow

struct Params {
    frame_size: vec2u,
    // The finest level's size, its frame pixels per texel on each axis, and the level count.
    finest_size: vec2u,
    block: u32,
    levels: u32,
}
var<immediate> params: Params;

// The engine's shadow mask of frame t, and frame t's packed normal and object id.
@group(0) @binding(0) var mask: texture_2d<f32>;
@group(0) @binding(1) var source_normal_id: texture_2d<u32>;
@group(0) @binding(2) var pyramid: texture_storage_2d<r32float, write>;

// Finest-level texels on a tile's side: one texel of the coarsest of `shadow_flow::MAX_LEVELS`.
const TILE: u32 = 32u;
const LANES: u32 = 64u;
// Every level's part of the tile, the finest first: 32^2 + 16^2 + 8^2 + 4^2 + 2^2 + 1.
var<workgroup> tile: array<f32, 1365>;

fn tracked(q: vec2i) -> f32 {
    let pixel = clamp(q, vec2i(0), vec2i(params.frame_size) - 1);
    if (object_id(textureLoad(source_normal_id, pixel, 0).r) != 0u) {
        return 1.0;
    }
    return sanitize_unit(vec3f(textureLoad(mask, pixel, 0).r, 0.0, 0.0)).value.x;
}

fn finest_texel(p: vec2u) -> f32 {
    let n = i32(unspecialised(params.block, mask));
    let q = n * vec2i(p);
    var sum = 0.0;
    for (var dy = 0; dy < n; dy++) {
        for (var dx = 0; dx < n; dx++) {
            sum += tracked(q + vec2i(dx, dy));
        }
    }
    return sum / f32(n * n);
}

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(workgroup_id) group: vec3u, @builtin(local_invocation_index) lane: u32) {
    var side = TILE;
    var origin = group.xy * side;
    var size = params.finest_size;
    for (var i = lane; i < side * side; i += LANES) {
        let p = origin + vec2u(i % side, i / side);
        if (all(p < size)) {
            let value = finest_texel(p);
            tile[i] = value;
            textureStore(pyramid, p, vec4f(value, 0.0, 0.0, 0.0));
        }
    }
    // Coarser levels stack in a column right of the finest (`shadow_flow::pyramid`).
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
        for (var i = lane; i < side * side; i += LANES) {
            let local = vec2u(i % side, i / side);
            let p = origin + local;
            if (all(p < size)) {
                var sum = 0.0;
                for (var dy = 0u; dy < 2u; dy++) {
                    for (var dx = 0u; dx < 2u; dx++) {
                        let finer = min(2u * p + vec2u(dx, dy), finer_size - 1u) - finer_origin;
                        sum += tile[finer_base + finer.y * finer_side + finer.x];
                    }
                }
                let value = sum / 4.0;
                tile[base + i] = value;
                textureStore(pyramid, offset + p, vec4f(value, 0.0, 0.0, 0.0));
            }
        }
        finer_base = base;
        offset.y += size.y;
    }
}
