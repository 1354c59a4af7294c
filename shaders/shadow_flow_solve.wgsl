// Sums the row sums of Farneback's equations down the window's columns and solves the 2x2
// system G d = h for this level's flow: the displacement from frame t to frame t-1, in texels
// of the level. The regularisation of shadow_flow_matrices.wgsl keeps G positive definite.
// #import flow

struct Params {
    level_offset: vec2u,
    level_size: vec2u,
    radius: i32,
}
var<immediate> params: Params;

@group(0) @binding(0) var rows: texture_2d<f32>;
@group(0) @binding(1) var rows_h2: texture_2d<f32>;
@group(0) @binding(2) var flow: texture_storage_2d<rg32float, write>;

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    let p = id.xy;
    if (any(p >= params.level_size)) {
        return;
    }
    var sum = vec4f(0.0);
    var h2 = 0.0;
    for (var dy = -params.radius; dy <= params.radius; dy++) {
        let q = level_texel(params.level_offset, params.level_size, vec2i(p) + vec2i(0, dy));
        sum += textureLoad(rows, q, 0);
        h2 += textureLoad(rows_h2, q, 0).r;
    }
    let g11 = sum.x;
    let g12 = sum.y;
    let g22 = sum.z;
    let h1 = sum.w;
    let det = g11 * g22 - g12 * g12;
    let d = vec2f(g22 * h1 - g12 * h2, g11 * h2 - g12 * h1) / det;
    textureStore(flow, params.level_offset + p, vec4f(d, 0.0, 0.0));
}
