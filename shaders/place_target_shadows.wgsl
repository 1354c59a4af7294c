// With a target shadow input: the share of light the dynamic shadows take away at the target,
// from the engine's mask there, in place of the shadows the flow moves. On static target pixels
//   share = -(1 - mask) * sun,
// with `sun` the share of the receiver's light that the sun gives: frame t's own, where the warp
// carried the pixel from texels in shadow (their layer over their darkness), and the mean over
// frame t's shadows (estimate_sun_share.wgsl) where it did not: ground a leg's shadow has only
// now reached. Dynamic objects keep the shadows on them in their shading, which moves with
// them: zero there. Writes the share in place of the carried layer, for remodulate.wgsl.
// #import gbuffer
// #import tallies

struct Params {
    extent: vec2u,
    has_stencil: u32,
}
var<immediate> params: Params;

// Below this darkness a carried texel says too little about the sun's share: the mean is used.
const LOCAL_DARKNESS: f32 = 0.1;

// In: frame t's shadow layer as the frame's warp carried it (RGB the share lost, A the frame
// alpha of its darkness, `frame_alpha`). Out: the share of light lost at the target.
@group(0) @binding(0) var share: texture_storage_2d<rgba16float, read_write>;
@group(0) @binding(1) var target_mask: texture_2d<f32>;
@group(0) @binding(2) var target_stencil: texture_2d<u32>;
// estimate_sun_share.wgsl's fixed-point sums: share lost per channel, then darkness.
@group(0) @binding(3) var<storage, read> sun_share: array<u32, 4>;
@group(0) @binding(4) var<storage, read_write> counters: SanitizeCounters;

// The darkness-weighted mean of the sun's share over frame t's shadows; zero without any.
fn mean_sun_share() -> vec3f {
    let darkness = f32(sun_share[3]);
    if (darkness < 1.0) {
        return vec3f(0.0);
    }
    return min(vec3f(f32(sun_share[0]), f32(sun_share[1]), f32(sun_share[2])) / darkness, vec3f(1.0));
}

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u, @builtin(local_invocation_index) lane: u32) {
    open_tallies(lane);
    let p = id.xy;
    if (all(p < params.extent)) {
        let carried = textureLoad(share, p);
        let darkness = frame_divisor(carried.a);
        var sun = mean_sun_share();
        if (!is_hole(carried.a) && darkness >= LOCAL_DARKNESS) {
            sun = clamp(-carried.rgb / darkness, vec3f(0.0), vec3f(1.0));
        }
        let visibility = sanitize_unit(vec3f(textureLoad(target_mask, p, 0).r, 0.0, 0.0));
        var dynamic = false;
        if (params.has_stencil != ABSENT) {
            dynamic = textureLoad(target_stencil, p, 0).r != 0u;
        }
        let lost = select(-(1.0 - visibility.value.x) * sun, vec3f(0.0), dynamic);
        textureStore(share, p, vec4f(to_half(lost), 1.0));
        if (visibility.changed) {
            atomicAdd(&group_tallies[0], 1u);
        }
    }
    if (close_tallies(lane)) {
        atomicAdd(&counters.sanitized_pixels, atomicLoad(&group_tallies[0]));
    }
}
