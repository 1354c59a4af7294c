// Multiplies the extrapolated shading by the target instant's own modulation factor, in place in
// the frame image (the engine's output, where the warp wrote its shading): texture detail comes
// from the target's G-buffer, not from the warp.
// With a shadow input, the shadow's change is added to the shading first.
// #import gbuffer
// #import tallies

struct Params {
    extent: vec2u,
    has_material: u32,
    // With a shadow input: the shadow is moved first (see below).
    has_shadow_change: u32,
    has_stencil: u32,
}
var<immediate> params: Params;

@group(0) @binding(0) var frame: texture_storage_2d<rgba16float, read_write>;
@group(0) @binding(1) var base_color: texture_2d<f32>;
@group(0) @binding(2) var material: texture_2d<f32>;
@group(0) @binding(4) var<storage, read_write> counters: SanitizeCounters;
// The shadow layer as its flow moved it less as the frame's warp carried it, where the flow
// found a receiver (include/warp.wgsl, `shadow_delta`).
@group(0) @binding(5) var shadow_change: texture_2d<f32>;
// The target's object ids (the engine's stencil): shadows are moved on static surfaces only.
@group(0) @binding(7) var target_stencil: texture_2d<u32>;

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u, @builtin(local_invocation_index) lane: u32) {
    open_tallies(lane);
    let p = id.xy;
    if (all(p < params.extent)) {
        let m = pixel_modulation(base_color, material, p, params.has_material);
        // The product can exceed what RGBA16F holds; clamp it there and count the pixel.
        var shading_rgb = textureLoad(frame, p).rgb;
        if (params.has_shadow_change != ABSENT && (params.has_stencil == ABSENT || textureLoad(target_stencil, p, 0).r == 0u)) {
            // The frame's warp carried frame t's shadows with the surfaces. On static surfaces,
            // the change takes them away and adds the layer as its flow moved it, where that
            // found a receiver; elsewhere, such as ground that was under a character, it is
            // zero and the warp's stays. Dynamic objects keep their shadows, which move with
            // them. A shadow moved onto an already darker surface cannot take more light than
            // is there.
            shading_rgb = max(shading_rgb + textureLoad(shadow_change, p, 0).rgb, vec3f(0.0));
        }
        let color = sanitize_color(shading_rgb * m.factor);
        textureStore(frame, p, vec4f(to_half(color.value), 1.0));
        if (m.changed || color.changed) {
            atomicAdd(&group_tallies[0u], 1u);
        }
    }
    if (close_tallies(lane)) {
        atomicAdd(&counters.sanitized_pixels, atomicLoad(&group_tallies[0u]));
    }
}
