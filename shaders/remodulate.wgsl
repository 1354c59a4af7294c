// Remodulates the extrapolated shading in place in the frame image (the engine's output, where
// the warp wrote its shading): include/remodulation.wgsl, over every pixel.
// #import gbuffer
// #import tallies
// #import remodulation

struct Params {
    extent: vec2u,
    has_material: u32,
    // With a shadow input: the shadows are put back first.
    has_shadow_share: u32,
}
var<immediate> params: Params;

@group(0) @binding(0) var frame: texture_storage_2d<rgba16float, read_write>;

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u, @builtin(local_invocation_index) lane: u32) {
    open_tallies(lane);
    let p = id.xy;
    if (all(p < params.extent)) {
        let warped = textureLoad(frame, p);
        textureStore(frame, p, remodulated(p, warped, params.has_material, params.has_shadow_share));
    }
    if (close_tallies(lane)) {
        atomicAdd(&counters.sanitized_pixels, atomicLoad(&group_tallies[0u]));
    }
}
