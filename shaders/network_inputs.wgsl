// Gathers an inpainting network's input planes over its patch (training/patchex_net.py,
// INPUT_NAMES): the warped demodulated colour, the hole mask, roughness, metallic and the LBP
// code / 255 (include/lbp.wgsl, made here from the frame around each pixel). Patch texels
// outside the frame are zero, as in training's padding. With a resolution divisor d a texel is
// the mean of its d x d pixels (those outside the frame counting as zero), so the hole plane
// holds the share of holes among them. One dispatch gathers for both networks run side by side,
// each over its own patch (`step_group`).
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
@group(0) @binding(2) var first_input: texture_storage_2d_array<rgba16float, write>;
@group(0) @binding(3) var<storage, read> first_patch: Patch;
@group(0) @binding(4) var second_input: texture_storage_2d_array<rgba16float, write>;
@group(0) @binding(5) var<storage, read> second_patch: Patch;

// The two input images of texel `texel` of a patch at `origin` whose texels span `d` x `d`.
struct Gathered {
    colour_hole: vec4f,
    surface: vec4f,
}

fn gather(texel: vec2u, origin: vec2u, d: u32) -> Gathered {
    var colour_hole = vec4f(0.0);
    var surface = vec4f(0.0);
    for (var j = 0u; j < d; j++) {
        for (var i = 0u; i < d; i++) {
            let f = origin + texel * d + vec2u(i, j);
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
    return Gathered(colour_hole * mean, surface * mean);
}

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(workgroup_id) group: vec3u, @builtin(local_invocation_id) local: vec3u) {
    // Read before the branch, where every invocation reads the same (llvmpipe reads a storage
    // buffer lane by lane inside control flow).
    let step = step_group(group.xy, first_patch.dispatch[0]);
    let origin = select(first_patch.origin, second_patch.origin, step.second);
    let extent = select(first_patch.extent, second_patch.extent, step.second);
    let divisor = select(first_patch.divisor, second_patch.divisor, step.second);
    let texel = step.group * 8u + local.xy;
    if (all(texel < extent)) {
        let g = gather(texel, origin, divisor);
        if (step.second) {
            textureStore(second_input, texel, 0, g.colour_hole);
            textureStore(second_input, texel, 1, g.surface);
        } else {
            textureStore(first_input, texel, 0, g.colour_hole);
            textureStore(first_input, texel, 1, g.surface);
        }
    }
}
