// Each target pixel's region, for region_masks.wgsl and blend_patches.wgsl. Needs gbuffer.wgsl
// and segmentation.wgsl. src/reference/segmentation.rs mirrors it.

// Target pixel p's region: FI where a dynamic object covers it, near-BE where it lies inside a
// grown rectangle but shows the background, far-BE elsewhere. The importing shader binds the
// target's stencil as `target_stencil` and the finished list of rectangles as `rects` (a
// `RectTable`).
fn region_of(p: vec2u, has_stencil: u32) -> u32 {
    if (has_stencil != ABSENT && textureLoad(target_stencil, p, 0).r != 0u) {
        return REGION_FI;
    }
    let count = min(rects.rect_count, MAX_OBJECTS);
    for (var i = 0u; i < count; i++) {
        let rect = rects.rects[i];
        if (all(p >= vec2u(rect.left, rect.top)) && all(p < vec2u(rect.right, rect.bottom))) {
            return REGION_NEAR_BE;
        }
    }
    return REGION_FAR_BE;
}
