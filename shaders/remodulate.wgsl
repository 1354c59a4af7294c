// Multiplies the extrapolated shading by the target instant's own modulation factor and writes the
// engine's output image: texture detail comes from the target's G-buffer, not from the warp.
// With a shadow input, the warped shadow layer is added back to the shading first.
// #import gbuffer

struct Params {
    extent: vec2u,
    has_material: u32,
    // With a shadow input: the warped shadow layer is added back first (separate_shadows.wgsl).
    has_shadow_layer: u32,
}
var<immediate> params: Params;

@group(0) @binding(0) var shading: texture_2d<f32>;
@group(0) @binding(1) var base_color: texture_2d<f32>;
@group(0) @binding(2) var material: texture_2d<f32>;
@group(0) @binding(3) var output: texture_storage_2d<rgba16float, write>;
@group(0) @binding(4) var<storage, read_write> counters: SanitizeCounters;
@group(0) @binding(5) var shadow_layer: texture_2d<f32>;

var<workgroup> group_sanitized: atomic<u32>;

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u, @builtin(local_invocation_index) lane: u32) {
    if (lane == 0u) {
        atomicStore(&group_sanitized, 0u);
    }
    workgroupBarrier();
    let p = id.xy;
    if (all(p < params.extent)) {
        let m = pixel_modulation(base_color, material, p, params.has_material);
        // The product can exceed what RGBA16F holds; clamp it there and count the pixel.
        var shading_rgb = textureLoad(shading, p, 0).rgb;
        if (params.has_shadow_layer != ABSENT) {
            // Where the layer's warp found no matching surface (alpha 0: a hole, such as a
            // dynamic object the shadow's flow points away from), no shadow is added. A shadow
            // moved onto an already darker surface cannot take more light than is there.
            let layer = textureLoad(shadow_layer, p, 0);
            shading_rgb = max(shading_rgb + layer.rgb * layer.a, vec3f(0.0));
        }
        let color = sanitize_color(shading_rgb * m.factor);
        textureStore(output, p, vec4f(color.value, 1.0));
        if (m.changed || color.changed) {
            atomicAdd(&group_sanitized, 1u);
        }
    }
    workgroupBarrier();
    if (lane == 0u) {
        atomicAdd(&counters.sanitized_pixels, atomicLoad(&group_sanitized));
    }
}
