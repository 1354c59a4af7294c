// An inpainting network's input planes over its patch (training/patchex_net.py, INPUT_NAMES):
// the warped demodulated colour, the hole mask, roughness, metallic and the LBP code / 255
// (include/lbp.wgsl, made here from the frame around each pixel). Patch texels outside the frame
// are zero, as in training's padding. With a resolution divisor d a texel is the mean of its
// d x d pixels (those outside the frame counting as zero), so the hole plane holds the share of
// holes among them. The networks' first layer gathers them as it convolves
// (`network::codegen`), so no pass of their own precedes it. Needs gbuffer.wgsl and lbp.wgsl.
// src/reference/inpaint.rs `gather_inputs` mirrors it.

struct GatherParams {
    frame_extent: vec2u,
    has_material: u32,
}
var<immediate> gather_params: GatherParams;

@group(0) @binding(10) var warped: texture_storage_2d<rgba16float, read>;
@group(0) @binding(11) var material: texture_2d<f32>;

// The two input images of a texel, as the RGBA16F input tensor holds them.
struct Gathered {
    colour_hole: vec4f,
    surface: vec4f,
}

// Texel `texel` of a patch at `origin` whose texels span `d` x `d` pixels.
fn gather(texel: vec2u, origin: vec2u, d: u32) -> Gathered {
    var colour_hole = vec4f(0.0);
    var surface = vec4f(0.0);
    for (var j = 0u; j < d; j++) {
        for (var i = 0u; i < d; i++) {
            let f = origin + texel * d + vec2u(i, j);
            if (all(f < gather_params.frame_extent)) {
                let w = textureLoad(warped, f);
                // The warp marks holes in alpha (`frame_alpha`); their colour is its best guess.
                colour_hole += vec4f(sanitize_color(w.rgb).value, select(0.0, 1.0, is_hole(w.a)));
                let metallic_roughness = metallic_roughness(material, f, gather_params.has_material);
                surface += vec4f(metallic_roughness.y, metallic_roughness.x, f32(lbp_code(f, gather_params.frame_extent)) / 255.0, 0.0);
            }
        }
    }
    let mean = 1.0 / f32(d * d);
    return Gathered(quantizeToF16(colour_hole * mean), quantizeToF16(surface * mean));
}
