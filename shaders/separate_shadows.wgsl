// Shadow separation, run in place of demodulate.wgsl when the engine gives a shadow input. When
// frame t-1's shadows were tracked, static pixels store the frame as lit without the dynamic
// casters' shadows, demodulated, and the shadow layer, the share of that light those shadows
// take away:
//   shading = U / m,   layer = (min(F, U) - U) / U   (in [-1, 0]; 0 where U is black),
// with F the colour, U the colour without dynamic shadows and m the modulation factor; the
// layer's alpha holds the shadow's darkness, 1 - mask, which the warps carry with it so that a
// target shadow input can read the sun's share, layer / darkness (place_target_shadows.wgsl). The frame
// is warped without those shadows, and remodulation puts back the layer where the shadows are
// at the target, as a share of the light the receiver has there: a shadow moved onto ground
// that static casters already shade takes away only the little light that is left. Nothing is
// divided by the mask, so fully shadowed pixels (mask 0) are as stable as lit ones. Dynamic
// objects keep the shadows on them (mostly their own, which move with them): there the shading
// is F / m, the layer zero, and the flow's pyramid (shadow_mask_pyramid.wgsl) takes the mask as
// lit, so the flow follows the shadows on static receivers only. Untracked (no frame t-1 to
// measure a drift from), every pixel is F / m and the layer zero: the shadows stay where the warp
// carries them. Each pixel with any input sanitised, the mask included, is counted once. It reads
// the object ids from the engine's stencil, beside the G-buffer packing.
// #import gbuffer
// #import tallies

struct Params {
    extent: vec2u,
    has_material: u32,
    // Not 0 when frame t-1's shadows were tracked: their layer is moved at the target.
    tracked: u32,
    has_stencil: u32,
}
var<immediate> params: Params;

@group(0) @binding(0) var color: texture_2d<f32>;
@group(0) @binding(1) var color_without_dynamic_shadows: texture_2d<f32>;
@group(0) @binding(2) var shadow_mask: texture_2d<f32>;
@group(0) @binding(3) var base_color: texture_2d<f32>;
@group(0) @binding(4) var material: texture_2d<f32>;
@group(0) @binding(5) var shading: texture_storage_2d<rgba16float, write>;
@group(0) @binding(6) var shadow_layer: texture_storage_2d<rgba16float, write>;
@group(0) @binding(8) var<storage, read_write> counters: SanitizeCounters;
@group(0) @binding(9) var source_stencil: texture_2d<u32>;

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u, @builtin(local_invocation_index) lane: u32) {
    open_tallies(lane);
    let p = id.xy;
    if (all(p < params.extent)) {
        let m = pixel_modulation(base_color, material, p, params.has_material);
        let lit = sanitize_input_color(textureLoad(color, p, 0).rgb);
        let unshadowed = sanitize_input_color(textureLoad(color_without_dynamic_shadows, p, 0).rgb);
        let visibility = sanitize_unit(vec3f(textureLoad(shadow_mask, p, 0).r, 0.0, 0.0));
        let separates = params.tracked != 0u
            && stencil_object_id(source_stencil, p, params.has_stencil) == 0u;
        textureStore(shading, p, demodulated(select(lit.value, unshadowed.value, separates), m.factor));
        var layer = vec4f(0.0);
        if (separates) {
            layer = vec4f(share_lost_to_shadows(lit.value, unshadowed.value), 1.0 - visibility.value.x);
        }
        textureStore(shadow_layer, p, layer);
        let changed = m.changed || lit.changed || unshadowed.changed || visibility.changed;
        if (changed) {
            atomicAdd(&group_tallies[0u], 1u);
        }
    }
    if (close_tallies(lane)) {
        atomicAdd(&counters.sanitized_pixels, atomicLoad(&group_tallies[0u]));
    }
}
