// Scatters the networks' repaired colour back into the warped frame under the region masks
// (PatchEX's F = M1*F1 + M2*F2 + M3*F3; each pixel's region from the target's stencil and the
// grown rectangles, `region_of`, where a network could repair it) and remodulates as it writes (include/remodulation.wgsl),
// in place in the frame image, over every pixel: FI pixels take the FI network's result, near-BE
// pixels the near-BE network's, far-BE pixels keep the warp's. Unless `correct_valid_pixels` (the
// paper's blend), only the warp's holes take a correction: where the warp found its source,
// corrections did not improve on it on unseen scenes. With `whole_frame` (the ablation of
// foveated segmentation) every pixel of the FI patch takes the FI network's result. A network's
// result is its correction (output minus its input colour) added to the warped colour: at a
// resolution divisor d the correction is upsampled bilinearly (texel centres at d-pixel spacing,
// clamped at the patch's edges) and the frame keeps its own detail. The repaired colour is
// rounded to half floats (`to_half`), as the frame image would store it, before it is remodulated.
// src/reference/inpaint.rs and src/reference/remodulate.rs mirror this pass.
// #import gbuffer
// #import patch
// #import segmentation
// #import regions
// #import tallies
// #import remodulation

struct Params {
    extent: vec2u,
    has_material: u32,
    // With a shadow input: the shadows are put back first.
    has_shadow_share: u32,
    whole_frame: u32,
    correct_valid_pixels: u32,
    has_stencil: u32,
}
var<immediate> params: Params;

// Bindings 1, 2, 4 and 5 are include/remodulation.wgsl's.
@group(0) @binding(0) var frame: texture_storage_2d<rgba16float, read_write>;
@group(0) @binding(6) var target_stencil: texture_2d<u32>;
@group(0) @binding(12) var<storage, read> rects: RectTable;
@group(0) @binding(7) var fi_input: texture_2d_array<f32>;
@group(0) @binding(8) var fi_output: texture_2d_array<f32>;
@group(0) @binding(9) var near_be_input: texture_2d_array<f32>;
@group(0) @binding(10) var near_be_output: texture_2d_array<f32>;
@group(0) @binding(11) var<storage, read> patches: array<PatchSlot, 3>;

// Where a patch lies: its record's fields that the blend reads, loaded one by one rather than
// the whole record (with its dispatches) at every pixel.
struct Placement {
    origin: vec2u,
    extent: vec2u,
    divisor: u32,
}

fn placement(slot: u32) -> Placement {
    return Placement(patches[slot].value.origin, patches[slot].value.extent, patches[slot].value.divisor);
}

fn inside(p: vec2u, rect: Placement) -> bool {
    return all(p >= rect.origin) && all(p - rect.origin < rect.extent * rect.divisor);
}

// The network's correction at one texel of its patch: its output minus its input colour.
fn correction_at(input: texture_2d_array<f32>, output: texture_2d_array<f32>, texel: vec2u) -> vec3f {
    return textureLoad(output, texel, 0, 0).rgb - textureLoad(input, texel, 0, 0).rgb;
}

// The warped colour `here` at frame pixel `p` of `rect`, corrected by the network.
fn repaired(input: texture_2d_array<f32>, output: texture_2d_array<f32>, rect: Placement, p: vec2u, here: vec4f) -> vec4f {
    let q = p - rect.origin;
    let last = rect.extent - vec2u(1u);
    let t = clamp((vec2f(q) + 0.5) / f32(rect.divisor) - 0.5, vec2f(0.0), vec2f(last));
    let lo = vec2u(floor(t));
    let hi = min(lo + vec2u(1u), last);
    let f = t - floor(t);
    let top = mix(correction_at(input, output, lo), correction_at(input, output, vec2u(hi.x, lo.y)), f.x);
    let bottom = mix(correction_at(input, output, vec2u(lo.x, hi.y)), correction_at(input, output, hi), f.x);
    let correction = mix(top, bottom, f.y);
    // Light is not negative (patchex sanitises negative input colour to 0), so a correction
    // stops at zero. The warp's alpha (`frame_alpha`) is kept: remodulation reads it.
    return vec4f(to_half(clamp(here.rgb + correction, vec3f(0.0), vec3f(MAX_HALF))), here.a);
}

// The warped colour at `p`, repaired where a network's region and patch cover it.
fn blended(p: vec2u, here: vec4f) -> vec4f {
    let origin = patches[PATCH_BLEND].value.origin;
    let in_blend = all(p >= origin) && all(p - origin < patches[PATCH_BLEND].value.extent);
    if (!in_blend || (!is_hole(here.a) && params.correct_valid_pixels == 0u)) {
        return here;
    }
    let fi_patch = placement(PATCH_FI);
    let near_be_patch = placement(PATCH_NEAR_BE);
    let region = region_of(p, params.has_stencil);
    if ((region == REGION_FI || params.whole_frame != 0u) && inside(p, fi_patch)) {
        return repaired(fi_input, fi_output, fi_patch, p, here);
    }
    if (region == REGION_NEAR_BE && inside(p, near_be_patch)) {
        return repaired(near_be_input, near_be_output, near_be_patch, p, here);
    }
    return here;
}

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u, @builtin(local_invocation_index) lane: u32) {
    open_tallies(lane);
    let p = id.xy;
    if (all(p < params.extent)) {
        let here = blended(p, textureLoad(frame, p));
        textureStore(frame, p, remodulated(p, here, params.has_material, params.has_shadow_share));
    }
    if (close_tallies(lane)) {
        atomicAdd(&counters.sanitized_pixels, atomicLoad(&group_tallies[0u]));
    }
}
