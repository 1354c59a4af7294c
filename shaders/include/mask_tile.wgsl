// The shadow mask pyramid's halving in workgroup memory, shared by shadow_mask_finest.wgsl and
// shadow_mask_pyramid.wgsl: the importing shader declares its tile as `tile`, every level's
// part of it from `finer_base` on, `finer_side` texels a row.

// Coarser texel c: the mean of the 2x2 finer texels it covers, the last row or column of an
// odd-sized finer level (`finer_size`) repeated; `finer_origin` is the tile's first finer texel.
fn coarser_texel(c: vec2u, finer_base: u32, finer_side: u32, finer_origin: vec2u, finer_size: vec2u) -> f32 {
    var sum = 0.0;
    for (var dy = 0u; dy < 2u; dy++) {
        for (var dx = 0u; dx < 2u; dx++) {
            let finer = min(2u * c + vec2u(dx, dy), finer_size - 1u) - finer_origin;
            sum += tile[finer_base + finer.y * finer_side + finer.x];
        }
    }
    return sum / 4.0;
}
