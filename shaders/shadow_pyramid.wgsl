// One coarser level of the shadow mask's pyramid: each texel is the mean of the 2x2 texels of
// the finer level it covers (the last row or column of an odd-sized level repeats).
// shadow_mask_level.wgsl makes the finest level.
// #import flow

struct Params {
    level_offset: vec2u,
    level_size: vec2u,
    finer_offset: vec2u,
    finer_size: vec2u,
}
var<immediate> params: Params;

@group(0) @binding(0) var finer: texture_2d<f32>;
@group(0) @binding(1) var level: texture_storage_2d<r32float, write>;

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    let p = id.xy;
    if (any(p >= params.level_size)) {
        return;
    }
    let q = 2 * vec2i(p);
    var sum = 0.0;
    for (var dy = 0; dy < 2; dy++) {
        for (var dx = 0; dx < 2; dx++) {
            let texel = level_texel(params.finer_offset, params.finer_size, q + vec2i(dx, dy));
            sum += textureLoad(finer, texel, 0).r;
        }
    }
    textureStore(level, params.level_offset + p, vec4f(sum / 4.0, 0.0, 0.0, 0.0));
}
