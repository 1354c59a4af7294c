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

// Rows in the window.
const FILL_ROWS: i32 = 2 * FILL_RADIUS / FILL_STEP + 1;

// Part of the window: its least cost, and the sums of its texels' values and weights, each
// weighted by exp(least - cost) so that no part underflows however badly every texel matches.
struct FillSums {
    least: f32,
    sum: FillValue,
    total: f32,
}

// Row `row` of the window around q, its weights rescaled as a cheaper texel appears.
fn fill_row(q: vec2f, t: Surface, row: i32) -> FillSums {
    let last = vec2i(params.extent) - 1;
    let centre = clamp(vec2i(floor(q)), vec2i(0), last);
    let dy = row * FILL_STEP - FILL_RADIUS;
    var sums = FillSums(3.4e38, FillValue(), 0.0);
    for (var dx = -FILL_RADIUS; dx <= FILL_RADIUS; dx += FILL_STEP) {
        let offset = vec2i(dx, dy);
        let s = clamp(centre + offset, vec2i(0), last);
        let cost = fill_cost(t, s, offset);
        if (cost < sums.least) {
            let rescale = exp(cost - sums.least);
            sums.sum *= rescale;
            sums.total *= rescale;
            sums.least = cost;
        }
        let w = exp(sums.least - cost);
        sums.sum += w * fill_value(s);
        sums.total += w;
    }
    return sums;
}

// Two parts of the window as one, each part's weights rescaled to the lesser least.
fn merge_fill(a: FillSums, b: FillSums) -> FillSums {
    let least = min(a.least, b.least);
    let wa = exp(least - a.least);
    let wb = exp(least - b.least);
    return FillSums(least, a.sum * wa + b.sum * wb, a.total * wa + b.total * wb);
}

// The weighted mean of the window's rows, merged in order.
fn fill_mean(rows: FillSums) -> FillValue {
    return rows.sum * (1.0 / rows.total);
}

fn fill_hole(q: vec2f, t: Surface) -> FillValue {
    var rows = fill_row(q, t, 0);
    for (var row = 1; row < FILL_ROWS; row++) {
        rows = merge_fill(rows, fill_row(q, t, row));
    }
    return fill_mean(rows);
}
