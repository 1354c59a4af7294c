// Gathers an inpainting network's input planes over its patch (training/patchex_net.py,
// INPUT_NAMES): the warped demodulated colour, the hole mask, roughness, metallic and the LBP
// code / 255 (include/lbp.wgsl, made here from the frame around each pixel). Patch texels
// outside the frame are zero, as in training's padding. With a resolution divisor d a texel is
// the mean of its d x d pixels (those outside the frame counting as zero), so the hole plane
// holds the share of holes among them.
// #import patch
// #import gbuffer
// #import lbp

struct Params {
    frame_extent: vec2u,
    has_material: u32,
}
var<immediate> params: Params;

@group(0) @binding(0) var warped: texture_storage_2d<rgba16float, read>;
@group(0) @binding(1) var material: texture_2d<f32>;
@group(0) @binding(2) var network_input: texture_storage_2d_array<rgba16float, write>;
@group(0) @binding(3) var<storage, read> network_patch: Patch;

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    if (any(id.xy >= network_patch.extent)) {
        return;
    }
    let d = network_patch.divisor;
    var colour_hole = vec4f(0.0);
    var surface = vec4f(0.0);
    for (var j = 0u; j < d; j++) {
        for (var i = 0u; i < d; i++) {
            let f = network_patch.origin + id.xy * d + vec2u(i, j);
            if (all(f < params.frame_extent)) {
                let w = textureLoad(warped, f);
                // The warp marks holes in alpha (`frame_alpha`); their colour is its best guess.
                colour_hole += vec4f(sanitize_color(w.rgb).value, select(0.0, 1.0, is_hole(w.a)));
                let metallic_roughness = metallic_roughness(material, f, params.has_material);
                surface += vec4f(metallic_roughness.y, metallic_roughness.x, f32(lbp_code(f, params.frame_extent)) / 255.0, 0.0);
            }
        }
    }
    let mean = 1.0 / f32(d * d);
    textureStore(network_input, id.xy, 0, colour_hole * mean);
    textureStore(network_input, id.xy, 1, surface * mean);
}
