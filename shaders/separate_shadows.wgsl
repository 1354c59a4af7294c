// Shadow separation, run in place of demodulate.wgsl when the engine gives a shadow input: the
// demodulated frame as usual, and the shadow layer, what the dynamic casters' shadows take
// away, demodulated the same way:
//   shading = F / m,   layer = (F - U) / m,
// with F the colour, U the colour without dynamic shadows and m the modulation factor. Nothing
// is divided by the mask, so fully shadowed pixels (mask 0) are as stable as lit ones.
// Dynamic objects keep the shadows on them (mostly their own, which move with them, as the
// warp moves them): there the layer is zero, and the flow's pyramid (shadow_pyramid.wgsl) takes
// the mask as lit, so the flow follows the shadows on static receivers only. Each pixel with
// any input sanitised, the mask included, is counted once. Runs after the G-buffer packing,
// whose object ids it reads.
// #import gbuffer
// #import tallies

struct Params {
    extent: vec2u,
    has_material: u32,
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
@group(0) @binding(9) var source_normal_id: texture_2d<u32>;

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u, @builtin(local_invocation_index) lane: u32) {
    open_tallies(lane);
    let p = id.xy;
    if (all(p < params.extent)) {
        let m = pixel_modulation(base_color, material, p, params.has_material);
        let lit = sanitize_color(textureLoad(color, p, 0).rgb);
        let unshadowed = sanitize_color(textureLoad(color_without_dynamic_shadows, p, 0).rgb);
        let visibility = sanitize_unit(vec3f(textureLoad(shadow_mask, p, 0).r, 0.0, 0.0));
        let s = demodulated(lit.value, m.factor);
        textureStore(shading, p, vec4f(s.value, 1.0));
        var changed = m.changed || lit.changed || unshadowed.changed || visibility.changed || s.changed;
        if (object_id(textureLoad(source_normal_id, p, 0).r) != 0u) {
            textureStore(shadow_layer, p, vec4f(0.0, 0.0, 0.0, 1.0));
        } else {
            let layer = demodulated(lit.value - unshadowed.value, m.factor);
            textureStore(shadow_layer, p, vec4f(layer.value, 1.0));
            changed = changed || layer.changed;
        }
        if (changed) {
            atomicAdd(&group_tallies[0u], 1u);
        }
    }
    if (close_tallies(lane)) {
        atomicAdd(&counters.sanitized_pixels, atomicLoad(&group_tallies[0u]));
    }
}
