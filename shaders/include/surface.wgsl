// The target pixel's surface, read from the engine's G-buffer, and its agreement with frame t's
// texels: the test by which the warps, the hole fill and the highlights' placement decide that
// a texel of frame t shows the target's surface. The pass binds `target_depth`,
// `target_normal`, `target_stencil`, `source_depth` and `source_normal_id`, the `cameras`
// uniform (cameras.wgsl), and defines `unspecialised` and Params fields `pixel_angle`,
// `in_plane_weight` and the `inv_sigma_*` of the warp settings. Needs gbuffer.wgsl and
// cameras.wgsl. src/reference/warp.rs mirrors it.

// A source texel agrees with the target when its geometry weight reaches this value.
const AGREEMENT_THRESHOLD: f32 = 0.5;
// -ln(AGREEMENT_THRESHOLD).
const LN_AGREEMENT_THRESHOLD: f32 = 0.6931472;
// Grazing surfaces stretch a pixel's footprint by 1 / cos(angle), up to this cosine.
const MIN_FACING: f32 = 0.25;

// The target pixel's surface, unpacked, with the size of a pixel's footprint on it, which every
// texel it is compared with needs.
struct Surface {
    position: vec3f,
    depth: f32,
    normal: vec3f,
    id: u32,
    footprint: f32,
    // Its stored depth is in range and its normal finite (`valid_geometry`).
    valid: bool,
}

fn target_surface(p: vec2u) -> Surface {
    let stored_depth = textureLoad(target_depth, p, 0).r;
    let depth = linear_depth(stored_depth, p, cameras.target_depth_curve, cameras.target_far,
        unspecialised(cameras.target_depth_convention));
    var id = 0u;
    if (unspecialised(cameras.target_has_stencil) != ABSENT) {
        id = textureLoad(target_stencil, p, 0).r;
    }
    let stored_normal = textureLoad(target_normal, p, 0).xyz;
    let normal = unit_normal(stored_normal, unspecialised(cameras.target_normal_encoding));
    let valid = valid_geometry(stored_depth, stored_normal, unspecialised(cameras.target_depth_convention));
    if (!valid) {
        // Agrees with no source texel: a hole, as the header promises.
        id = NO_OBJECT;
    }
    let ray = cameras.target_at_origin + f32(p.x) * cameras.target_per_x
        + f32(p.y) * cameras.target_per_y;
    let position = cameras.target_position + depth * ray;
    // Grazing surfaces stretch the footprint, so the agreement test means the same at every
    // resolution and viewing angle.
    let view = normalize(cameras.target_position - position);
    let facing = max(abs(dot(normal, view)), MIN_FACING);
    let footprint = depth * params.pixel_angle / facing;
    return Surface(position, depth, normal, id, footprint, valid);
}

fn source_position(s: vec2i, depth: f32) -> vec3f {
    let ray = cameras.source_at_origin + f32(s.x) * cameras.source_per_x
        + f32(s.y) * cameras.source_per_y;
    return cameras.source_position + depth * ray;
}

// An object id no 8-bit stencil holds: a target pixel whose geometry is unusable takes it, and
// so agrees with no source texel.
const NO_OBJECT: u32 = 0x100u;

// Agreement of the target's surface with frame t's texel `s`. Both loads come first, so that a
// GPU waits on them together.
fn agreement_at(t: Surface, s: vec2i) -> f32 {
    let packed = textureLoad(source_normal_id, s, 0).r;
    let depth = textureLoad(source_depth, s, 0).r;
    return agreement_of(t, s, packed, depth);
}

// Agreement of the target's surface with frame t's texel `s`, whose normal and id are `packed`
// and whose depth is `depth`. What is not needed (another object's texel) is not unpacked.
fn agreement_of(t: Surface, s: vec2i, packed: u32, depth: f32) -> f32 {
    if (object_id(packed) != t.id) {
        return 0.0;
    }
    if (is_sky(t.depth) || is_sky(depth)) {
        return select(0.0, 1.0, is_sky(t.depth) && is_sky(depth));
    }
    let normal_term = (1.0 - dot(t.normal, unpack_normal(packed))) * params.inv_sigma_normal;
    var e: f32;
    if (t.id == 0u) {
        // Measured in pixel footprints on the target's surface.
        let offset = source_position(s, depth) - t.position;
        let across = dot(t.normal, offset) * t.normal;
        e = length(across + params.in_plane_weight * (offset - across)) / t.footprint * params.inv_sigma_position;
    } else {
        e = abs(t.depth - depth) / max(t.depth, depth) * params.inv_sigma_depth;
    }
    // exp(-normal_term) * exp(-e^2), as one exp.
    return exp(-(normal_term + e * e));
}
