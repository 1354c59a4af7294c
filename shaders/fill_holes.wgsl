// The G-buffer-guided warp's hole fill, over the holes that warp listed (warp_gbuffer.wgsl,
// `defer_hole`), one invocation per hole: a hole takes a weighted mean of frame t's texels
// around its source point, weighted by how well each texel's surface matches the target
// pixel's own (the target's G-buffer knows the uncovered surface's normal, depth and object
// id) and by its distance. The occluder that hid the surface in frame t is nearer, or another
// object, so it weighs next to nothing; the wide window reaches the background on every side
// of it, and scenery that enters at the frame's edge takes the texels inside the edge that
// face the same way. Dispatched indirectly from the warp's count, so a frame without holes
// runs no workgroup. src/reference/warp.rs (`fill_hole`) mirrors it.
// #import gbuffer
// #import cameras
// #import surface
// #import atlas
// #import warp
// #import surface_match
// #import fill
// #import tallies

@group(0) @binding(13) var<storage, read_write> deferred: DeferredHoles;
@group(0) @binding(14) var hole_list: texture_2d<u32>;

// What the fill spreads (fill.wgsl): what the warp fetches, frame t's shading and shadow layer.
alias FillValue = Fetched;

fn fill_value(s: vec2i) -> Fetched {
    return source_texel(s);
}

@compute @workgroup_size(64, 1, 1)
fn main(@builtin(global_invocation_id) id: vec3u, @builtin(local_invocation_index) lane: u32) {
    open_tallies(lane);
    let i = id.x;
    if (i < atomicLoad(&deferred.count)) {
        let entry = textureLoad(hole_list, vec2u(i % params.extent.x, i / params.extent.x), 0).r;
        let p = vec2u(entry & 0xffffu, entry >> 16u);
        let q = source_point(p, motion_at(p));
        store_pixel(p, fill_hole(q, target_surface(p)), true);
    }
    if (close_tallies(lane)) {
        atomicAdd(&counters.sanitized_pixels, atomicLoad(&group_tallies[TALLY_SANITIZED]));
    }
}
