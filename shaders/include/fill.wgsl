// The G-buffer-guided warp's hole fill (fill_holes.wgsl), as a weighting any pass can spread a
// value of frame t's with: a weighted mean of frame t's texels around q, each weighted by how
// well its surface matches the target pixel's surface `t` and by its distance. The pass defines
// `FillValue` (a vector or a matrix) and `fill_value(s: vec2i) -> FillValue`, the value at
// texel s, and binds `source_depth` and `source_normal_id` (frame t's packed G-buffer); `t` has
// the target's depth, normal and id.
// Needs gbuffer.wgsl and surface_match.wgsl. src/reference/warp.rs (`fill_hole`) mirrors it.

// The window's radius and tap spacing, and the cost of another object's texel (chosen on the
// validation scenes).
const FILL_RADIUS: i32 = 12;
const FILL_STEP: i32 = 3;
const FILL_OTHER_OBJECT: f32 = 20.0;

// -log of texel `s`'s weight for the target surface `t` at window offset `offset`.
fn fill_cost(t: Surface, s: vec2i, offset: vec2i) -> f32 {
    let packed = textureLoad(source_normal_id, s, 0).r;
    let other_object = select(0.0, FILL_OTHER_OBJECT, object_id(packed) != t.id);
    return surface_cost(t.depth, t.normal, s, packed, offset, FILL_RADIUS) + other_object;
}

fn fill_hole(q: vec2f, t: Surface) -> FillValue {
    let last = vec2i(params.extent) - 1;
    let centre = clamp(vec2i(floor(q)), vec2i(0), last);
    // The weights are exp(least - cost), rescaled as a cheaper texel appears, so that no
    // window underflows however badly every texel matches.
    var least = 3.4e38;
    var sum = FillValue();
    var total = 0.0;
    for (var dy = -FILL_RADIUS; dy <= FILL_RADIUS; dy += FILL_STEP) {
        for (var dx = -FILL_RADIUS; dx <= FILL_RADIUS; dx += FILL_STEP) {
            let offset = vec2i(dx, dy);
            let s = clamp(centre + offset, vec2i(0), last);
            let cost = fill_cost(t, s, offset);
            if (cost < least) {
                let rescale = exp(cost - least);
                sum *= rescale;
                total *= rescale;
                least = cost;
            }
            let w = exp(least - cost);
            sum += w * fill_value(s);
            total += w;
        }
    }
    return sum * (1.0 / total);
}
