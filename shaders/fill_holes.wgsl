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
// #import warp
// #import tallies

// The window's radius and tap spacing, and the widths of the weights' terms (chosen on the
// validation scenes): normal difference (length of the vectors' difference), relative depth
// difference, and the cost of another object's texel.
const FILL_RADIUS: i32 = 12;
const FILL_STEP: i32 = 3;
const FILL_SIGMA_NORMAL: f32 = 0.15;
const FILL_SIGMA_DEPTH: f32 = 0.03;
const FILL_OTHER_OBJECT: f32 = 20.0;

@group(0) @binding(13) var<storage, read_write> deferred: DeferredHoles;
@group(0) @binding(14) var hole_list: texture_2d<u32>;

// -log of texel `s`'s weight for the target surface `t` at window offset `offset`. A
// non-finite depth on either side counts as relative difference 1.
fn fill_cost(t: Surface, s: vec2i, offset: vec2i) -> f32 {
    let packed = textureLoad(source_normal_id, s, 0).r;
    let source_w = textureLoad(source_depth, s, 0).r;
    let relative = abs(source_w - t.depth) / max(max(source_w, t.depth), 1e-30);
    let depth_term = select(1.0, relative, relative <= 1.0) / FILL_SIGMA_DEPTH;
    let normal_delta = unpack_normal(packed) - t.normal;
    let normal_term = dot(normal_delta, normal_delta) / (FILL_SIGMA_NORMAL * FILL_SIGMA_NORMAL);
    let distance_term = f32(dot(offset, offset)) / f32(FILL_RADIUS * FILL_RADIUS);
    let other_object = select(0.0, FILL_OTHER_OBJECT, object_id(packed) != t.id);
    return depth_term * depth_term + normal_term + distance_term + other_object;
}

fn fill_hole(q: vec2f, t: Surface) -> vec4f {
    let last = vec2i(params.extent) - 1;
    let centre = texel(q);
    // The weights are exp(least - cost), rescaled as a cheaper texel appears, so that no
    // window underflows however badly every texel matches.
    var least = 3.4e38;
    var sum = vec4f(0.0);
    var total = 0.0;
    for (var dy = -FILL_RADIUS; dy <= FILL_RADIUS; dy += FILL_STEP) {
        for (var dx = -FILL_RADIUS; dx <= FILL_RADIUS; dx += FILL_STEP) {
            let offset = vec2i(dx, dy);
            let s = clamp(centre + offset, vec2i(0), last);
            let cost = fill_cost(t, s, offset);
            if (cost < least) {
                let rescale = exp(cost - least);
                sum *= rescale;
                total *= rescale;
                least = cost;
            }
            let w = exp(least - cost);
            sum += w * textureLoad(source_shading, s, 0);
            total += w;
        }
    }
    return sum / total;
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
