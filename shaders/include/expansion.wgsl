// Farneback's polynomial expansion of one texel of a mask level: around texel p the mask is
// fitted, in the least-squares sense with Gaussian weights w over a (2r+1)^2 neighbourhood, by
//   f(x, y) = c + b1 x + b2 y + a11 x^2 + a22 y^2 + a12 x y.
// The weights are separable and even, so x, y and xy are each orthogonal to every other basis
// function and take their coefficient from one weighted sum; c, a11 and a22 share a 3x3 system
// whose inverse the host computes once per settings (`FlowSettings::expansion`). The including
// shader declares the uniform `expansion` (the submit writes it with its counters) and a
// `mask_pyramid` atlas. shadow_poly.wgsl expands every level; shadow_flow_iterate.wgsl the
// coarsest, as it starts. src/reference/optical_flow.rs (`expand`) mirrors it. Needs atlas.wgsl
// and flow.wgsl.

struct ExpansionConstants {
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

// (b1, b2, a11, a22) and a12, as the expansion atlases hold them.
struct Expanded {
    coefficients: vec4f,
    xy: f32,
}

fn axis_weight(i: i32) -> f32 {
    let weights = vec4f(expansion.weight0, expansion.weight1, expansion.weight2, expansion.weight3);
    return weights[abs(i)];
}

fn expand(offset: vec2u, size: vec2u, p: vec2i) -> Expanded {
    let r = i32(unspecialised(u32(expansion.radius), mask_pyramid));
    // sum(w f), sum(w x f), sum(w y f), sum(w x^2 f), sum(w y^2 f), sum(w x y f)
    var s0 = 0.0;
    var sx = 0.0;
    var sy = 0.0;
    var sxx = 0.0;
    var syy = 0.0;
    var sxy = 0.0;
    for (var dy = -r; dy <= r; dy++) {
        for (var dx = -r; dx <= r; dx++) {
            let f = textureLoad(mask_pyramid, level_texel(offset, size, p + vec2i(dx, dy)), 0).r;
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
    let b1 = sx * expansion.inv_sum_xx;
    let b2 = sy * expansion.inv_sum_xx;
    let a11 = expansion.a_from_sum * s0 + expansion.a_from_xx * sxx + expansion.a_from_yy * syy;
    let a22 = expansion.a_from_sum * s0 + expansion.a_from_yy * sxx + expansion.a_from_xx * syy;
    return Expanded(vec4f(b1, b2, a11, a22), sxy * expansion.inv_sum_xxyy);
}
