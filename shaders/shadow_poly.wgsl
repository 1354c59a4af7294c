// Farneback's polynomial expansion (expansion.wgsl) of every level of the pyramid, in one
// dispatch over the atlas: each invocation finds the level its texel lies in. Writes
// (b1, b2, a11, a22) and a12 in two atlases.
// #import atlas
// #import flow
// #import expansion

struct Params {
    // The finest level's size and how many levels the pyramid has (`shadow_flow::pyramid`).
    finest_size: vec2u,
    levels: u32,
}
var<immediate> params: Params;

@group(0) @binding(0) var mask_pyramid: texture_2d<f32>;
@group(0) @binding(1) var poly: texture_storage_2d<rgba32float, write>;
@group(0) @binding(2) var poly_xy: texture_storage_2d<r32float, write>;
@group(0) @binding(3) var<uniform> expansion: ExpansionConstants;

struct Place {
    offset: vec2u,
    size: vec2u,
    found: bool,
}

// The level holding atlas texel t: level 0 at the origin, each coarser one half the one before
// (rounded up), stacked in a column right of level 0.
fn level_of(t: vec2u) -> Place {
    var size = params.finest_size;
    if (all(t < size)) {
        return Place(vec2u(0u), size, true);
    }
    var offset = vec2u(size.x, 0u);
    for (var level = 1u; level < unspecialised(params.levels, mask_pyramid); level++) {
        size = (size + 1u) / 2u;
        if (all(t >= offset) && all(t < offset + size)) {
            return Place(offset, size, true);
        }
        offset.y += size.y;
    }
    return Place(vec2u(0u), vec2u(1u), false);
}

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    let level = level_of(id.xy);
    if (!level.found) {
        return;
    }
    let expanded = expand(level.offset, level.size, vec2i(id.xy - level.offset));
    textureStore(poly, id.xy, expanded.coefficients);
    textureStore(poly_xy, id.xy, vec4f(expanded.xy, 0.0, 0.0, 0.0));
}
