// One level of the shadow mask's pyramid: each texel is the mean of the 2x2 texels of the finer
// level it covers (the last row or column of an odd-sized level repeats). The finest level
// averages frame t's full-resolution mask, written by separate_shadows.wgsl, in blocks of
// `mask_step` x `mask_step` pixels (src/passes/shadow_flow.rs).
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

@group(0) @binding(0) var mask: texture_2d<f32>;
@group(0) @binding(1) var finer: texture_2d<f32>;
@group(0) @binding(2) var level: texture_storage_2d<r32float, write>;

fn finer_texel(q: vec2i) -> f32 {
    let texel = level_texel(params.finer_offset, params.finer_size, q);
    if (params.from_mask != 0u) {
        return textureLoad(mask, texel, 0).r;
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
