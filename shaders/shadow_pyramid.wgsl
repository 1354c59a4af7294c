// One level of the shadow mask's pyramid: each texel is the mean of the 2x2 texels of the finer
// level it covers (the last row or column of an odd-sized level repeats). The finest level
// averages, in blocks of `mask_step` x `mask_step` pixels (src/passes/shadow_flow.rs), what the
// flow tracks of frame t: the engine's shadow mask, sanitised, on static pixels, and dynamic
// objects as lit (their shadows move with them). src/reference/separate_shadows.rs `flow_mask`
// mirrors that.
// #import gbuffer
// #import flow

struct Params {
    level_offset: vec2u,
    level_size: vec2u,
    finer_offset: vec2u,
    finer_size: vec2u,
    // 1: the finer level is the frame's mask; 0: the previous level of the atlas.
    from_mask: u32,
    // Edge of the block of finer texels each texel averages.
    block: u32,
}
var<immediate> params: Params;

// The engine's shadow mask of frame t, and frame t's packed normal and object id.
@group(0) @binding(0) var mask: texture_2d<f32>;
@group(0) @binding(3) var source_normal_id: texture_2d<u32>;
@group(0) @binding(1) var finer: texture_2d<f32>;
@group(0) @binding(2) var level: texture_storage_2d<r32float, write>;

fn finer_texel(q: vec2i) -> f32 {
    let texel = level_texel(params.finer_offset, params.finer_size, q);
    if (params.from_mask != 0u) {
        if (object_id(textureLoad(source_normal_id, texel, 0).r) != 0u) {
            return 1.0;
        }
        return sanitize_unit(vec3f(textureLoad(mask, texel, 0).r, 0.0, 0.0)).value.x;
    }
    return textureLoad(finer, texel, 0).r;
}

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    let p = id.xy;
    if (any(p >= params.level_size)) {
        return;
    }
    let n = i32(params.block);
    let q = n * vec2i(p);
    var sum = 0.0;
    for (var dy = 0; dy < n; dy++) {
        for (var dx = 0; dx < n; dx++) {
            sum += finer_texel(q + vec2i(dx, dy));
        }
    }
    textureStore(level, params.level_offset + p, vec4f(sum / f32(n * n), 0.0, 0.0, 0.0));
}
