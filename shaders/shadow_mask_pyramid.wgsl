// The shadow mask's levels beyond the `shadow_flow::FINEST_PASS_LEVELS` that
// shadow_mask_finest.wgsl makes, in one dispatch (as FidelityFX's single-pass downsampler makes
// mips), from the coarsest of those. Each coarser texel is the mean of the 2x2 finer texels it
// covers (the last row or column of an odd-sized level repeats). A workgroup reads a
// TILE x TILE tile of its base level and halves it in workgroup memory, level by level: the
// texels a coarser texel covers, clamped at the level's edge, lie in its own tile, so no level
// waits for another workgroup. src/reference/optical_flow.rs mirrors it.
// #import mask_tile

struct Params {
    // The level it starts from: its place in the atlas and its size.
    base_offset: vec2u,
    base_size: vec2u,
    // Where the next level starts the column of coarser levels (`shadow_flow::pyramid`).
    column_offset: vec2u,
    // The base level and the levels it makes.
    levels: u32,
}
var<immediate> params: Params;

@group(0) @binding(0) var pyramid: texture_storage_2d<r32float, read_write>;
// Base-level texels on a tile's side: one texel of the coarsest of `shadow_flow::MAX_LEVELS`.
const TILE: u32 = 4u;
const LANES: u32 = 16u;
// Every level's part of the tile, the base first: 4^2 + 2^2 + 1.
var<workgroup> tile: array<f32, 21>;

@compute @workgroup_size(4, 4, 1)
fn main(@builtin(workgroup_id) group: vec3u, @builtin(local_invocation_index) lane: u32) {
    var side = TILE;
    var origin = group.xy * side;
    var size = params.base_size;
    for (var i = lane; i < side * side; i += LANES) {
        let p = origin + vec2u(i % side, i / side);
        if (all(p < size)) {
            tile[i] = textureLoad(pyramid, params.base_offset + p).r;
        }
    }
    var offset = params.column_offset;
    var finer_base = 0u;
    // `unspecialised` (include/flow.wgsl), for a storage image.
    let levels = select(0u, params.levels, textureDimensions(pyramid).x != 0u);
    for (var level = 1u; level < levels; level++) {
        workgroupBarrier();
        let finer_side = side;
        let finer_size = size;
        let finer_origin = origin;
        let base = finer_base + finer_side * finer_side;
        side /= 2u;
        origin /= 2u;
        size = (size + 1u) / 2u;
        for (var i = lane; i < side * side; i += LANES) {
            let local = vec2u(i % side, i / side);
            let p = origin + local;
            if (all(p < size)) {
                let value = coarser_texel(p, finer_base, finer_side, finer_origin, finer_size);
                tile[base + i] = value;
                textureStore(pyramid, offset + p, vec4f(value, 0.0, 0.0, 0.0));
            }
        }
        finer_base = base;
        offset.y += size.y;
    }
}
