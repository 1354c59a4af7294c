// Multiplies the extrapolated shading by the target instant's own modulation factor, in place in
// the frame image (the engine's output, where the warp wrote its shading): texture detail comes
// from the target's G-buffer, not from the warp. The frame's alpha holds the warped value's
// divisor, which says where the shading cannot carry light (gbuffer.wgsl `remodulation`).
// With a shadow input, the shading (warped without the dynamic casters' shadows) first loses
// the share of its light that those shadows take away at the target.
// #import gbuffer
// #import tallies

struct Params {
    extent: vec2u,
    has_material: u32,
    // With a shadow input: the shadows are put back first (see below).
    has_shadow_share: u32,
}
var<immediate> params: Params;

@group(0) @binding(0) var frame: texture_storage_2d<rgba16float, read_write>;
@group(0) @binding(1) var base_color: texture_2d<f32>;
@group(0) @binding(2) var material: texture_2d<f32>;
@group(0) @binding(4) var<storage, read_write> counters: SanitizeCounters;
// The share of light the dynamic shadows take away at the target, in [-1, 0]: the shadow layer
// as its flow moved it where that found a receiver, as the frame's warp carried it elsewhere
// (include/warp.wgsl, `shadow_share`).
@group(0) @binding(5) var shadow_share: texture_2d<f32>;

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u, @builtin(local_invocation_index) lane: u32) {
    open_tallies(lane);
    let p = id.xy;
    if (all(p < params.extent)) {
        let m = pixel_modulation(base_color, material, p, params.has_material);
        // The product can exceed what RGBA16F holds; clamp it there and count the pixel.
        let warped = textureLoad(frame, p);
        var shading_rgb = warped.rgb;
        if (params.has_shadow_share != ABSENT) {
            // A share, not an amount: a shadow moved onto an already darker surface takes away
            // only the light that is there. Dynamic objects carry a zero layer and keep the
            // shadows on them in their shading, which moves with them.
            shading_rgb = shading_rgb * (1.0 + textureLoad(shadow_share, p, 0).rgb);
        }
        let factor = remodulation(m.factor, warped.rgb, frame_divisor(warped.a));
        let color = sanitize_color(shading_rgb * factor);
        textureStore(frame, p, vec4f(to_half(color.value), 1.0));
        if (m.changed || color.changed) {
            atomicAdd(&group_tallies[0u], 1u);
        }
    }
    if (close_tallies(lane)) {
        atomicAdd(&counters.sanitized_pixels, atomicLoad(&group_tallies[0u]));
    }
}
