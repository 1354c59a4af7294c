// Copies the shadow sub-task's intermediate results into the engine's shadow diagnostics image:
// RG = the mask's flow at this pixel of frame t (displacement to frame t-1, pixels),
// B = luminance of frame t's shadow layer (the share of light the dynamic shadows take away),
// A = luminance of that share at the target (the layer as its flow moved it where that found a
// receiver, as the frame's warp carried it elsewhere).
// #import atlas

struct Params {
    extent: vec2u,
    // The flow's finest level in its atlas; 0 x 0 where no flow was measured (zero flow).
    level_offset: vec2u,
    level_size: vec2u,
}
var<immediate> params: Params;

@group(0) @binding(0) var flow_atlas: texture_2d<f32>;
@group(0) @binding(1) var shadow_layer: texture_2d<f32>;
@group(0) @binding(2) var shadow_share: texture_2d<f32>;
@group(0) @binding(3) var diagnostics: texture_storage_2d<rgba16float, write>;

const LUMINANCE: vec3f = vec3f(0.2126, 0.7152, 0.0722);

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    let p = id.xy;
    if (any(p >= params.extent)) {
        return;
    }
    let layer = dot(textureLoad(shadow_layer, p, 0).rgb, LUMINANCE);
    let share = dot(textureLoad(shadow_share, p, 0).rgb, LUMINANCE);
    var flow = vec2f(0.0);
    if (params.level_size.x != 0u) {
        flow = frame_flow(flow_atlas, params.level_offset, params.level_size, params.extent, p);
    }
    textureStore(diagnostics, p, vec4f(flow, layer, share));
}
