// Occlusion-motion-vector backward warp (after Zeng et al. 2021). A disoccluded pixel's own
// motion vector points at the occluder that hid it in frame t, and reprojection ghosts the
// occluder. Where the pixel's own vector lands on disagreeing geometry, this warp tries the motion
// vectors of its neighbourhood (every second pixel within the search radius) and keeps the one
// that lands on the best-agreeing surface: at a disocclusion that is the occluder's own motion,
// which fetches the background beside the occluder in frame t instead of the occluder.
// #import gbuffer
// #import cameras
// #import surface
// #import atlas
// #import warp
// #import warp_entry
// #import tallies

// The bilinear fetch at q: plain, or weighted by agreement (`agreeing_bilinear`) where any
// texel agrees.
fn fetch(t: Surface, q: vec2f) -> Fetched {
    if (unspecialised(params.agreeing_bilinear) != 0u) {
        let footprint = agreeing_footprint(t, q);
        if (footprint.weight_sum > MIN_TOTAL_WEIGHT) {
            return divided(footprint.shading_sum, footprint.weight_sum);
        }
    }
    return bilinear_fetch(q);
}

fn warp_pixel(p: vec2u, t: Surface, motion_vector: vec2f) -> WarpedPixel {
    var q = source_point(p, motion_vector);
    var best_agreement = select(agreement_at(t, texel(q)), 0.0, is_offscreen(q));
    if (best_agreement < AGREEMENT_THRESHOLD) {
        let r = i32(unspecialised(u32(params.occlusion_search_radius)));
        let last = vec2i(params.extent) - 1;
        for (var dy = -r; dy <= r; dy += 2) {
            for (var dx = -r; dx <= r; dx += 2) {
                let neighbour = clamp(vec2i(p) + vec2i(dx, dy), vec2i(0), last);
                let candidate = source_point(p, motion_at(vec2u(neighbour)));
                if (is_offscreen(candidate)) {
                    continue;
                }
                let agreement = agreement_at(t, texel(candidate));
                if (agreement > best_agreement) {
                    best_agreement = agreement;
                    q = candidate;
                }
            }
        }
    }
    let offscreen = is_offscreen(q);
    return WarpedPixel(fetch(t, q), offscreen || best_agreement < AGREEMENT_THRESHOLD, offscreen, false);
}
