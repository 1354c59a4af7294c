// G-buffer-guided backward warp (after ExtraSS, Wu et al. 2023). Each target pixel follows its
// motion vector to a point q in frame t. Where the source texels around q show the same surface
// as the target pixel (same object id, close normals, and for static surfaces the same world
// position, for moving ones the same relative depth), it takes their bilinear blend, weighted by
// that agreement, so zero motion returns frame t exactly; on a static surface whose 4x4 texels
// around q all show it, a sharper Catmull-Rom fetch (PATCHEX_RESAMPLE_CATMULL_ROM, the default).
// Where they do not (disocclusions, silhouettes, motion-vector errors), it gathers from a
// (2r+1)^2 window with a joint bilateral kernel instead. A pixel whose source leaves the screen or finds no agreeing texel is a hole;
// a hole on screen is filled from the side the disocclusion uncovers, by fill_holes.wgsl.
// #import gbuffer
// #import cameras
// #import surface
// #import atlas
// #import warp
// #import warp_entry
// #import tallies

// The bilinear blend is kept when agreeing texels carry at least this share of its weight.
const BILINEAR_ACCEPT: f32 = 0.5;
const HOLE_FILL_BACKGROUND: u32 = 0u;
const RESAMPLE_CATMULL_ROM: u32 = 0u;

// The holes this warp leaves to fill_holes.wgsl: each entry is a pixel, x | y << 16, at list
// index i = x + y * width.
@group(0) @binding(12) var hole_list: texture_storage_2d<r32uint, write>;
@group(0) @binding(13) var<storage, read_write> deferred: DeferredHoles;

// Hands hole pixel p to the fill. The fill's many taps stay out of this shader: on a CPU driver
// every pixel paid for them, hole or not.
fn defer_hole(p: vec2u) {
    let slot = atomicAdd(&deferred.count, 1u);
    textureStore(hole_list, vec2u(slot % params.extent.x, slot / params.extent.x), vec4u(p.x | (p.y << 16u)));
    atomicMax(&deferred.groups, slot / 64u + 1u);
}

fn warp_pixel(p: vec2u, t: Surface, motion_vector: vec2f) -> WarpedPixel {
    let extent = vec2i(params.extent);
    let q = source_point(p, motion_vector);

    let footprint = agreeing_footprint(t, q);
    var shading_sum = footprint.shading_sum;
    var weight_sum = footprint.weight_sum;
    var best_agreement = footprint.best_agreement;

    if (weight_sum < BILINEAR_ACCEPT) {
        // Joint bilateral gather around q.
        shading_sum = Fetched();
        weight_sum = 0.0;
        let centre = texel(q);
        let r = i32(unspecialised(u32(params.kernel_radius)));
        for (var dy = -r; dy <= r; dy++) {
            for (var dx = -r; dx <= r; dx++) {
                let s = clamp(centre + vec2i(dx, dy), vec2i(0), extent - 1);
                let agreement = agreement_at(t, s);
                let d = vec2f(s) + 0.5 - q;
                let weight = exp(-dot(d, d) * params.inv_two_sigma_spatial_sq) * agreement;
                shading_sum += weight * source_texel(s);
                weight_sum += weight;
                best_agreement = max(best_agreement, agreement);
            }
        }
    }
    var fetched: Fetched;
    // Sharper on static surfaces only: a skinned object's motion vectors are less exact, and
    // a sharper fetch of a misplaced point is further off (measured on the validation scenes).
    let sharp = unspecialised(params.resample) == RESAMPLE_CATMULL_ROM && t.id == 0u
        && footprint.least_agreement >= AGREEMENT_THRESHOLD && surface_around(t, q);
    if (sharp) {
        fetched = catmull_rom_fetch(q);
    } else if (weight_sum > MIN_TOTAL_WEIGHT) {
        fetched = divided(shading_sum, weight_sum);
    } else {
        fetched = source_texel(texel(q));
    }
    let offscreen = is_offscreen(q);
    let hole = offscreen || best_agreement < AGREEMENT_THRESHOLD;
    let deferred = hole && unspecialised(params.hole_fill) == HOLE_FILL_BACKGROUND;
    if (deferred) {
        defer_hole(p);
    }
    return WarpedPixel(fetched, hole, offscreen, deferred);
}
