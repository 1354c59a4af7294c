// G-buffer-guided backward warp (after ExtraSS, Wu et al. 2023). Each target pixel follows its
// motion vector to a point q in frame t. Where the source texels around q show the same surface
// as the target pixel (same object id, close normals, and for static surfaces the same world
// position, for moving ones the same relative depth), it takes their bilinear blend, weighted by
// that agreement, so zero motion returns frame t exactly. Where they do not (disocclusions,
// silhouettes, motion-vector errors), it gathers from a (2r+1)^2 window with a joint bilateral
// kernel instead. A pixel whose source leaves the screen or finds no agreeing texel is a hole;
// a hole on screen is filled from the side the disocclusion uncovers (`fill_hole`).
// #import gbuffer
// #import warp
// #import tallies

// The bilinear blend is kept when agreeing texels carry at least this share of its weight.
const BILINEAR_ACCEPT: f32 = 0.5;
// Below this total weight the kernel found nothing usable; take the nearest texel instead.
const MIN_TOTAL_WEIGHT: f32 = 1e-6;
// The hole fill looks this far around the source point (chosen on the validation scenes), and
// averages the texels whose depth mismatch is within this much of the best one's.
const FILL_RADIUS: i32 = 3;
const DEPTH_BAND: f32 = 0.02;
const HOLE_FILL_BACKGROUND: u32 = 0u;

// How far texel `s` of frame t is from the target pixel's surface: its relative depth
// difference (at most 1; a non-finite depth counts 1), plus 1 for another object id, so that a
// texel of the right object always wins.
fn depth_mismatch(t: Surface, s: vec2i) -> f32 {
    let source_w = textureLoad(source_depth, s, 0).r;
    let id_differs = object_id(textureLoad(source_normal_id, s, 0).r) != t.id;
    let relative = abs(source_w - t.depth) / max(max(source_w, t.depth), 1e-30);
    return select(1.0, relative, relative <= 1.0) + select(0.0, 1.0, id_differs);
}

// A hole's colour from the side the disocclusion uncovers: the mean of the texels around `q`
// whose depth (and object id) is nearest the target pixel's own. The target's G-buffer knows the
// uncovered surface's depth; the occluder that hid it in frame t is nearer, so it is left out.
fn fill_hole(q: vec2f, t: Surface) -> vec3f {
    let extent = vec2i(params.extent);
    let centre = texel(q);
    var least = 3.0;
    for (var dy = -FILL_RADIUS; dy <= FILL_RADIUS; dy++) {
        for (var dx = -FILL_RADIUS; dx <= FILL_RADIUS; dx++) {
            let s = clamp(centre + vec2i(dx, dy), vec2i(0), extent - 1);
            let mismatch = depth_mismatch(t, s);
            if (mismatch < least) {
                least = mismatch;
            }
        }
    }
    var sum = vec3f(0.0);
    var count = 0.0;
    for (var dy = -FILL_RADIUS; dy <= FILL_RADIUS; dy++) {
        for (var dx = -FILL_RADIUS; dx <= FILL_RADIUS; dx++) {
            let s = clamp(centre + vec2i(dx, dy), vec2i(0), extent - 1);
            if (depth_mismatch(t, s) <= least + DEPTH_BAND) {
                sum += textureLoad(source_shading, s, 0).rgb;
                count += 1.0;
            }
        }
    }
    return sum / max(count, 1.0);
}

fn warp_pixel(p: vec2u, t: Surface, motion_vector: vec2f) -> WarpedPixel {
    let extent = vec2i(params.extent);
    let q = source_point(p, motion_vector);

    // Bilinear footprint of q, each texel weighted by its agreement with the target.
    let corner = vec2i(floor(q - 0.5));
    let f = q - 0.5 - floor(q - 0.5);
    var shading_sum = vec3f(0.0);
    var weight_sum = 0.0;
    var best_agreement = 0.0;
    for (var i = 0; i < 4; i++) {
        let offset = vec2i(i & 1, i >> 1u);
        let s = clamp(corner + offset, vec2i(0), extent - 1);
        let agreement = agreement_at(t, s);
        let bilinear = select(1.0 - f, f, vec2<bool>(offset == vec2i(1)));
        let footprint = bilinear.x * bilinear.y;
        shading_sum += footprint * agreement * textureLoad(source_shading, s, 0).rgb;
        weight_sum += footprint * agreement;
        if (footprint > 0.0) {
            best_agreement = max(best_agreement, agreement);
        }
    }

    if (weight_sum < BILINEAR_ACCEPT) {
        // Joint bilateral gather around q.
        shading_sum = vec3f(0.0);
        weight_sum = 0.0;
        let centre = texel(q);
        let r = params.kernel_radius;
        for (var dy = -r; dy <= r; dy++) {
            for (var dx = -r; dx <= r; dx++) {
                let s = clamp(centre + vec2i(dx, dy), vec2i(0), extent - 1);
                let agreement = agreement_at(t, s);
                let d = vec2f(s) + 0.5 - q;
                let weight = exp(-dot(d, d) * params.inv_two_sigma_spatial_sq) * agreement;
                shading_sum += weight * textureLoad(source_shading, s, 0).rgb;
                weight_sum += weight;
                best_agreement = max(best_agreement, agreement);
            }
        }
    }
    var shading: vec3f;
    if (weight_sum > MIN_TOTAL_WEIGHT) {
        shading = shading_sum / weight_sum;
    } else {
        shading = textureLoad(source_shading, texel(q), 0).rgb;
    }
    let offscreen = is_offscreen(q);
    let hole = offscreen || best_agreement < AGREEMENT_THRESHOLD;
    if (hole && !offscreen && params.hole_fill == HOLE_FILL_BACKGROUND) {
        shading = fill_hole(q, t);
    }
    return WarpedPixel(shading, hole, offscreen);
}
