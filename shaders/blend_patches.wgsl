// Scatters the networks' repaired colour back into the warped frame under the region masks
// (PatchEX's F = M1*F1 + M2*F2 + M3*F3): FI pixels take the FI network's result, near-BE pixels
// the near-BE network's, far-BE pixels keep the warp's. It runs over the blend patch only, so
// its cost follows the patches' area. The warp's hole flag (alpha) is kept: it says what was
// guessed, and the diagnostics report it. With `whole_frame` (the ablation of foveated
// segmentation) every pixel takes the FI network's result. src/reference/inpaint.rs mirrors
// this pass.
// #import patch
// #import segmentation

struct Params {
    whole_frame: u32,
}
var<immediate> params: Params;

@group(0) @binding(0) var regions: texture_2d<u32>;
@group(0) @binding(1) var fi_input: texture_2d_array<f32>;
@group(0) @binding(2) var fi_output: texture_2d_array<f32>;
@group(0) @binding(3) var near_be_input: texture_2d_array<f32>;
@group(0) @binding(4) var near_be_output: texture_2d_array<f32>;
@group(0) @binding(5) var<storage, read> patches: array<PatchSlot, 3>;
@group(0) @binding(6) var warped: texture_storage_2d<rgba32float, write>;

fn inside(p: vec2u, origin: vec2u, extent: vec2u) -> bool {
    return all(p >= origin) && all(p - origin < extent);
}

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    let blend = patches[PATCH_BLEND].value;
    if (any(id.xy >= blend.extent)) {
        return;
    }
    let fi_patch = patches[PATCH_FI].value;
    let near_be_patch = patches[PATCH_NEAR_BE].value;
    let p = blend.origin + id.xy;
    let region = textureLoad(regions, p, 0).r;
    if ((region == REGION_FI || params.whole_frame != 0u) && inside(p, fi_patch.origin, fi_patch.extent)) {
        let q = p - fi_patch.origin;
        // The gathered input's alpha is the hole mask.
        let hole = textureLoad(fi_input, q, 0, 0).a;
        textureStore(warped, p, vec4f(textureLoad(fi_output, q, 0, 0).rgb, 1.0 - hole));
    } else if (region == REGION_NEAR_BE && inside(p, near_be_patch.origin, near_be_patch.extent)) {
        let q = p - near_be_patch.origin;
        let hole = textureLoad(near_be_input, q, 0, 0).a;
        textureStore(warped, p, vec4f(textureLoad(near_be_output, q, 0, 0).rgb, 1.0 - hole));
    }
}
