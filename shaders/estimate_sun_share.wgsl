// With a target shadow input: the share of a static receiver's light that the sun gives,
// summed over frame t's dynamic shadows for place_target_shadows.wgsl, which uses it where the
// warp brings no shadowed texel of frame t to read it from. Each texel of the shadow layer holds
// the share its shadow takes away and that shadow's darkness (1 - mask); their sums' ratio is
// the sun's share, weighted by darkness, so faint penumbrae count little. Sums are fixed point
// (SUN_SHARE_SCALE per unit) in u32: exact, and room for 2^32 / 64 pixels, past 8K.
// #import gbuffer
// #import tallies

struct Params {
    extent: vec2u,
}
var<immediate> params: Params;

// Fixed-point units per unit of share and darkness. src/reference/target_shadows.rs mirrors it.
const SUN_SHARE_SCALE: f32 = 64.0;

struct SunShareSums {
    // Share of light lost, per channel, then darkness.
    sums: array<atomic<u32>, 4>,
}

// Frame t's shadow layer (separate_shadows.wgsl): RGB the share lost, in [-1, 0]; A darkness.
@group(0) @binding(0) var shadow_layer: texture_2d<f32>;
@group(0) @binding(1) var<storage, read_write> sun_share: SunShareSums;

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u, @builtin(local_invocation_index) lane: u32) {
    open_tallies(lane);
    let p = id.xy;
    if (all(p < params.extent)) {
        let texel = textureLoad(shadow_layer, p, 0);
        let lost = vec3u(round(clamp(-texel.rgb, vec3f(0.0), vec3f(1.0)) * SUN_SHARE_SCALE));
        let darkness = u32(round(clamp(texel.a, 0.0, 1.0) * SUN_SHARE_SCALE));
        atomicAdd(&group_tallies[0], lost.r);
        atomicAdd(&group_tallies[1], lost.g);
        atomicAdd(&group_tallies[2], lost.b);
        atomicAdd(&group_tallies[3], darkness);
    }
    if (close_tallies(lane)) {
        atomicAdd(&sun_share.sums[0], atomicLoad(&group_tallies[0]));
        atomicAdd(&sun_share.sums[1], atomicLoad(&group_tallies[1]));
        atomicAdd(&sun_share.sums[2], atomicLoad(&group_tallies[2]));
        atomicAdd(&sun_share.sums[3], atomicLoad(&group_tallies[3]));
    }
}
