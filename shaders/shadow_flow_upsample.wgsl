// The flow of the pyramid's finest level (half the frame's resolution) scaled up to the frame:
// bilinear in position, multiplied by the size ratio in length, stored in half floats as the
// engine's motion vectors usually are (1/32 pixel up to 64 pixels).
// #import flow

struct Params {
    extent: vec2u,
    level_offset: vec2u,
    level_size: vec2u,
}
var<immediate> params: Params;

@group(0) @binding(0) var flow_pyramid: texture_2d<f32>;
@group(0) @binding(1) var flow: texture_storage_2d<rg16float, write>;

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    let p = id.xy;
    if (any(p >= params.extent)) {
        return;
    }
    let ratio = vec2f(params.extent) / vec2f(params.level_size);
    let pos = (vec2f(p) + 0.5) / ratio - 0.5;
    let d = level_bilinear(flow_pyramid, params.level_offset, params.level_size, pos).xy * ratio;
    textureStore(flow, p, vec4f(d, 0.0, 0.0));
}
