// Divides frame t's colour by its modulation factor, leaving shading that varies smoothly across
// textures and so warps and inpaints well: F' = F / (albedo + 0.08 * specular * (1 - metallic)).
// Alpha holds what the colour was divided by (gbuffer.wgsl `demodulated`), which remodulation
// reads. Unusable inputs are sanitised first and counted.
// #import gbuffer
// #import tallies

struct Params {
    extent: vec2u,
    has_material: u32,
}
var<immediate> params: Params;

@group(0) @binding(0) var color: texture_2d<f32>;
@group(0) @binding(1) var base_color: texture_2d<f32>;
@group(0) @binding(2) var material: texture_2d<f32>;
@group(0) @binding(3) var shading: texture_storage_2d<rgba16float, write>;
@group(0) @binding(4) var<storage, read_write> counters: SanitizeCounters;

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u, @builtin(local_invocation_index) lane: u32) {
    open_tallies(lane);
    let p = id.xy;
    if (all(p < params.extent)) {
        let m = pixel_modulation(base_color, material, p, params.has_material);
        let color = sanitize_input_color(textureLoad(color, p, 0).rgb);
        textureStore(shading, p, demodulated(color.value, m.factor));
        if (m.changed || color.changed) {
            atomicAdd(&group_tallies[0u], 1u);
        }
    }
    if (close_tallies(lane)) {
        atomicAdd(&counters.sanitized_pixels, atomicLoad(&group_tallies[0u]));
    }
}
