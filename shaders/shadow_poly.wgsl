// Farneback's polynomial expansion of every level of the pyramid, in one dispatch over the
// atlas: each invocation finds the level its texel lies in. Around each texel the mask is fitted,
// in the least-squares sense with Gaussian weights w over a (2r+1)^2 neighbourhood, by
//   f(x, y) = c + b1 x + b2 y + a11 x^2 + a22 y^2 + a12 x y.
// The weights are separable and even, so x, y and xy are each orthogonal to every other basis
// function and take their coefficient from one weighted sum; c, a11 and a22 share a 3x3 system
// whose inverse the host computes once per settings (src/passes/shadow_flow.rs).
// Writes (b1, b2, a11, a22) and a12 in two atlases.
// #import atlas
// #import flow

struct Params {
    // The finest level's size and how many levels the pyramid has (`shadow_flow::pyramid`).
    finest_size: vec2u,
    levels: u32,
    radius: i32,
    // Weights w(0) .. w(3) of one axis; w(x, y) = w(|x|) w(|y|).
    weight0: f32,
    weight1: f32,
    weight2: f32,
    weight3: f32,
    // 1 / sum(w x^2) and 1 / sum(w x^2 y^2).
    inv_sum_xx: f32,
    inv_sum_xxyy: f32,
    // a11 = from_sum * sum(w f) + from_xx * sum(w x^2 f) + from_yy * sum(w y^2 f); a22 swaps
    // the last two.
    a_from_sum: f32,
    a_from_xx: f32,
    a_from_yy: f32,
}
var<immediate> params: Params;

@group(0) @binding(0) var mask_pyramid: texture_2d<f32>;
@group(0) @binding(1) var poly: texture_storage_2d<rgba32float, write>;
@group(0) @binding(2) var poly_xy: texture_storage_2d<r32float, write>;

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

fn axis_weight(i: i32) -> f32 {
    let weights = vec4f(params.weight0, params.weight1, params.weight2, params.weight3);
    return weights[abs(i)];
}

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    let level = level_of(id.xy);
    if (!level.found) {
        return;
    }
    let p = id.xy - level.offset;
    let r = i32(unspecialised(u32(params.radius), mask_pyramid));
    // sum(w f), sum(w x f), sum(w y f), sum(w x^2 f), sum(w y^2 f), sum(w x y f)
    var s0 = 0.0;
    var sx = 0.0;
    var sy = 0.0;
    var sxx = 0.0;
    var syy = 0.0;
    var sxy = 0.0;
    for (var dy = -r; dy <= r; dy++) {
        for (var dx = -r; dx <= r; dx++) {
            let f = textureLoad(mask_pyramid, level_texel(level.offset, level.size, vec2i(p) + vec2i(dx, dy)), 0).r;
            let wf = axis_weight(dx) * axis_weight(dy) * f;
            let x = f32(dx);
            let y = f32(dy);
            s0 += wf;
            sx += wf * x;
            sy += wf * y;
            sxx += wf * x * x;
            syy += wf * y * y;
            sxy += wf * x * y;
        }
    }
    let b1 = sx * params.inv_sum_xx;
    let b2 = sy * params.inv_sum_xx;
    let a11 = params.a_from_sum * s0 + params.a_from_xx * sxx + params.a_from_yy * syy;
    let a22 = params.a_from_sum * s0 + params.a_from_yy * sxx + params.a_from_xx * syy;
    let texel = id.xy;
    textureStore(poly, texel, vec4f(b1, b2, a11, a22));
    textureStore(poly_xy, texel, vec4f(sxy * params.inv_sum_xxyy, 0.0, 0.0, 0.0));
}
