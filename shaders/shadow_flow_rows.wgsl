// The horizontal half of the box sum of Farneback's equations over the (2r+1)^2 window
// (borders replicate); shadow_flow_solve.wgsl sums the columns.
// #import flow

struct Params {
    level_offset: vec2u,
    level_size: vec2u,
    radius: i32,
}
var<immediate> params: Params;

@group(0) @binding(0) var equations: texture_2d<f32>;
@group(0) @binding(1) var equations_h2: texture_2d<f32>;
@group(0) @binding(2) var rows: texture_storage_2d<rgba32float, write>;
@group(0) @binding(3) var rows_h2: texture_storage_2d<r32float, write>;

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    let p = id.xy;
    if (any(p >= params.level_size)) {
        return;
    }
    var sum = vec4f(0.0);
    var sum_h2 = 0.0;
    for (var dx = -params.radius; dx <= params.radius; dx++) {
        let q = level_texel(params.level_offset, params.level_size, vec2i(p) + vec2i(dx, 0));
        sum += textureLoad(equations, q, 0);
        sum_h2 += textureLoad(equations_h2, q, 0).r;
    }
    let texel = params.level_offset + p;
    textureStore(rows, texel, sum);
    textureStore(rows_h2, texel, vec4f(sum_h2, 0.0, 0.0, 0.0));
}
