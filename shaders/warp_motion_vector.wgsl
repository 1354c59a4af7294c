// Motion-vector backward warp, the classic reprojection: each target pixel takes frame t's
// shading, bilinearly, where its motion vector points. Where the texel there shows other
// geometry than the target pixel (it was hidden in frame t) the result ghosts; such pixels, and
// those whose source leaves the screen, are counted as holes.
// #import gbuffer
// #import cameras
// #import surface
// #import atlas
// #import warp
// #import warp_entry
// #import tallies

fn warp_pixel(p: vec2u, t: Surface, motion_vector: vec2f) -> WarpedPixel {
    let q = source_point(p, motion_vector);
    let agreement = agreement_at(t, texel(q));
    let offscreen = is_offscreen(q);
    return WarpedPixel(bilinear_fetch(q), offscreen || agreement < AGREEMENT_THRESHOLD, offscreen, false);
}
