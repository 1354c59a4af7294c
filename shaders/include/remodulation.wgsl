// One pixel's remodulation, for remodulate.wgsl and for blend_patches.wgsl, which remodulates as
// it writes: the extrapolated shading times the target instant's own modulation factor, so that
// texture detail comes from the target's G-buffer, not from the warp. The frame's alpha holds the
// warped value's divisor, which says where the shading cannot carry light (gbuffer.wgsl
// `remodulation`). With a shadow input, the shading (warped without the dynamic casters'
// shadows) first loses the share of its light that those shadows take away at the target.
// Needs gbuffer.wgsl and tallies.wgsl; counts into tally 0 the pixels it sanitised, which the
// pass adds to `counters`. src/reference/remodulate.rs mirrors it.

@group(0) @binding(1) var base_color: texture_2d<f32>;
@group(0) @binding(2) var material: texture_2d<f32>;
@group(0) @binding(4) var<storage, read_write> counters: SanitizeCounters;
// The share of light the dynamic shadows take away at the target, in [-1, 0]: the shadow layer
// as its flow moved it where that found a receiver, as the frame's warp carried it elsewhere
// (include/warp.wgsl, `shadow_share`).
@group(0) @binding(5) var shadow_share: texture_2d<f32>;

// The output colour at `p` of the warped shading `warped` (alpha: its divisor).
fn remodulated(p: vec2u, warped: vec4f, has_material: u32, has_shadow_share: u32) -> vec4f {
    let m = pixel_modulation(base_color, material, p, has_material);
    var shading_rgb = warped.rgb;
    if (has_shadow_share != ABSENT) {
        // A share, not an amount: a shadow moved onto an already darker surface takes away
        // only the light that is there. Dynamic objects carry a zero layer and keep the
        // shadows on them in their shading, which moves with them.
        shading_rgb = shading_rgb * (1.0 + textureLoad(shadow_share, p, 0).rgb);
    }
    let factor = remodulation(m.factor, warped.rgb, frame_divisor(warped.a));
    // The product can exceed what RGBA16F holds; clamp it there and count the pixel.
    let color = sanitize_color(shading_rgb * factor);
    if (m.changed || color.changed) {
        atomicAdd(&group_tallies[0u], 1u);
    }
    return vec4f(to_half(color.value), 1.0);
}
