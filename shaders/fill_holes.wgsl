// The G-buffer-guided warp's hole fill, over the holes that warp listed (warp_gbuffer.wgsl,
// `defer_hole`), one invocation per hole: a hole takes the mean of the texels around its source
// point whose depth (and object id) is nearest the target pixel's own. The target's G-buffer
// knows the uncovered surface's depth; the occluder that hid it in frame t is nearer, so it is
// left out. Dispatched indirectly from the warp's count, so a frame without holes runs no
// workgroup. src/reference/warp.rs (`fill_hole`) mirrors it.
// #import gbuffer
// #import warp
// #import tallies

// The fill looks this far around the source point (chosen on the validation scenes), and
// averages the texels whose depth mismatch is within this much of the best one's.
const FILL_RADIUS: i32 = 3;
const DEPTH_BAND: f32 = 0.02;

@group(0) @binding(13) var<storage, read_write> deferred: DeferredHoles;
@group(0) @binding(14) var hole_list: texture_2d<u32>;

// How far texel `s` of frame t is from the target pixel's surface: its relative depth
// difference (at most 1; a non-finite depth counts 1), plus 1 for another object id, so that a
// texel of the right object always wins.
fn depth_mismatch(t: Surface, s: vec2i) -> f32 {
    let source_w = textureLoad(source_depth, s, 0).r;
    let id_differs = object_id(textureLoad(source_normal_id, s, 0).r) != t.id;
    let relative = abs(source_w - t.depth) / max(max(source_w, t.depth), 1e-30);
    return select(1.0, relative, relative <= 1.0) + select(0.0, 1.0, id_differs);
}

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

@compute @workgroup_size(64, 1, 1)
fn main(@builtin(global_invocation_id) id: vec3u, @builtin(local_invocation_index) lane: u32) {
    open_tallies(lane);
    let i = id.x;
    if (i < atomicLoad(&deferred.count)) {
        let entry = textureLoad(hole_list, vec2u(i % params.extent.x, i / params.extent.x), 0).r;
        let p = vec2u(entry & 0xffffu, entry >> 16u);
        let q = source_point(p, textureLoad(motion, p, 0).xy);
        store_pixel(p, fill_hole(q, target_surface(p)), true);
    }
    if (close_tallies(lane)) {
        atomicAdd(&counters.sanitized_pixels, atomicLoad(&group_tallies[TALLY_SANITIZED]));
    }
}
