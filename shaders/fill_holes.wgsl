// The G-buffer-guided warp's hole fill, over the holes that warp listed (warp_gbuffer.wgsl,
// `defer_hole`): a hole takes a weighted mean of frame t's texels
// around its source point, weighted by how well each texel's surface matches the target
// pixel's own (the target's G-buffer knows the uncovered surface's normal, depth and object
// id) and by its distance. The occluder that hid the surface in frame t is nearer, or another
// object, so it weighs next to nothing; the wide window reaches the background on every side
// of it, and scenery that enters at the frame's edge takes the texels inside the edge that
// face the same way. Each of a hole's FILL_ROWS invocations weighs one row of the window and the
// first merges them: the holes are few, and one invocation walking the whole window kept a GPU
// waiting on its loads in turn. Dispatched indirectly from the warp's count
// (HOLES_PER_WORKGROUP holes a workgroup), so a frame without holes runs no workgroup.
// src/reference/warp.rs (`fill_hole`) mirrors it.
// #import gbuffer
// #import cameras
// #import surface
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

// Each hole's rows, for its first invocation to merge.
var<workgroup> rows: array<array<FillSums, FILL_ROWS>, HOLES_PER_WORKGROUP>;

// FILL_ROWS x HOLES_PER_WORKGROUP.
@compute @workgroup_size(9, 8, 1)
fn main(
    @builtin(workgroup_id) group: vec3u,
    @builtin(local_invocation_id) local: vec3u,
    @builtin(local_invocation_index) lane: u32,
) {
    open_tallies(lane);
    let i = group.x * HOLES_PER_WORKGROUP + local.y;
    let listed = i < atomicLoad(&deferred.count);
    var p = vec2u(0u);
    if (listed) {
        let entry = textureLoad(hole_list, vec2u(i % params.extent.x, i / params.extent.x), 0).r;
        p = vec2u(entry & 0xffffu, entry >> 16u);
        let q = source_point(p, textureLoad(motion, p, 0).xy);
        rows[local.y][local.x] = fill_row(q, target_surface(p), i32(local.x));
    }
    workgroupBarrier();
    if (listed && local.x == 0u) {
        var merged = rows[local.y][0];
        for (var row = 1; row < FILL_ROWS; row++) {
            merged = merge_fill(merged, rows[local.y][row]);
        }
        store_pixel(p, fill_mean(merged), true);
    }
    if (close_tallies(lane)) {
        atomicAdd(&counters.sanitized_pixels, atomicLoad(&group_tallies[TALLY_SANITIZED]));
    }
}
