// The warped frame's local binary pattern (include/lbp.wgsl), for the diagnostics to show: code
// / 255 in R16F.
// #import lbp

struct Params {
    extent: vec2u,
}
var<immediate> params: Params;

@group(0) @binding(0) var warped: texture_storage_2d<rgba16float, read>;
@group(0) @binding(1) var lbp: texture_storage_2d<r16float, write>;

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    let p = id.xy;
    if (any(p >= params.extent)) {
        return;
    }
    textureStore(lbp, p, vec4f(f32(lbp_code(p, params.extent)) / 255.0, 0.0, 0.0, 0.0));
}
