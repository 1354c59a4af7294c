// The G-buffer-guided warp's hole fill (fill_holes.wgsl), as a weighting any pass can spread a
// value of frame t's with: a weighted mean of frame t's texels around q, each weighted by how
// well its surface matches the target pixel's surface `t` and by its distance. Where the window
// holds none of that surface (sky entering at the frame's edge behind a tree that filled frame
// t's edge), a wider, sparser window finds it further in. The pass defines
// `FillValue` (a vector or a matrix) and `fill_value(s: vec2i) -> FillValue`, the value at
// texel s, and binds `source_depth` and `source_normal_id` (frame t's packed G-buffer); `t` has
// the target's depth, normal and id.
// Needs gbuffer.wgsl and surface_match.wgsl. src/reference/warp.rs (`fill_hole`) mirrors it.

// The window's radius and tap spacing, and the cost of another object's texel; the wider
// window's (chosen on the validation scenes).
const FILL_RADIUS: i32 = 12;
const FILL_STEP: i32 = 3;
const FILL_OTHER_OBJECT: f32 = 20.0;
// A window whose cheapest texel costs more than this holds none of the target's surface.
const FILL_NO_MATCH: f32 = 9.0;
const FILL_WIDE_RADIUS: i32 = 96;
const FILL_WIDE_STEP: i32 = 12;

// -log of texel `s`'s weight for the target surface `t` at window offset `offset`.
fn fill_cost(t: Surface, s: vec2i, offset: vec2i, radius: i32) -> f32 {
    let packed = textureLoad(source_normal_id, s, 0).r;
    let other_object = select(0.0, FILL_OTHER_OBJECT, object_id(packed) != t.id);
    return surface_cost(t.depth, t.normal, s, packed, offset, radius) + other_object;
}

// A window's weighted sum, its total weight, and its cheapest texel's cost.
struct FillWindow {
    sum: FillValue,
    total: f32,
    least: f32,
}

fn fill_window(centre: vec2i, t: Surface, radius: i32, step: i32) -> FillWindow {
    let last = vec2i(params.extent) - 1;
    // The weights are exp(least - cost), rescaled as a cheaper texel appears, so that no
    // window underflows however badly every texel matches.
    var window = FillWindow(FillValue(), 0.0, 3.4e38);
    for (var dy = -radius; dy <= radius; dy += step) {
        for (var dx = -radius; dx <= radius; dx += step) {
            let offset = vec2i(dx, dy);
            let s = clamp(centre + offset, vec2i(0), last);
            let cost = fill_cost(t, s, offset, radius);
            if (cost < window.least) {
                let rescale = exp(cost - window.least);
                window.sum *= rescale;
                window.total *= rescale;
                window.least = cost;
            }
            let w = exp(window.least - cost);
            window.sum += w * fill_value(s);
            window.total += w;
        }
    }
    return window;
}

fn fill_hole(q: vec2f, t: Surface) -> FillValue {
    let centre = clamp(vec2i(floor(q)), vec2i(0), vec2i(params.extent) - 1);
    var window = fill_window(centre, t, FILL_RADIUS, FILL_STEP);
    if (window.least > FILL_NO_MATCH) {
        let wide = fill_window(centre, t, FILL_WIDE_RADIUS, FILL_WIDE_STEP);
        if (wide.least < window.least) {
            window = wide;
        }
    }
    return window.sum * (1.0 / window.total);
}
