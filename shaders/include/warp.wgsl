// What every backward warp shares: its parameters, bindings and hole counters, the geometry
// agreement test, and the entry point. Each warp pass defines `warp_pixel`. Needs gbuffer.wgsl.
// src/reference/warp.rs mirrors this file.

// A source texel agrees with the target when its geometry weight reaches this value.
const AGREEMENT_THRESHOLD: f32 = 0.5;
// Grazing surfaces stretch a pixel's footprint by 1 / cos(angle), up to this cosine.
const MIN_FACING: f32 = 0.25;

struct Params {
    extent: vec2u,
    // Target jitter minus frame t's jitter, in pixels.
    jitter_delta: vec2f,
    // Turns the engine's motion vectors into backward motion in pixels.
    motion_scale: vec2f,
    kernel_radius: i32,
    inv_two_sigma_spatial_sq: f32,
    inv_sigma_depth: f32,
    inv_sigma_normal: f32,
    inv_sigma_position: f32,
    occlusion_search_radius: i32,
    // How much of the world-position distance along the target's surface counts: 1 for surface
    // points, which must land on themselves; 0 for shadows, which slide across their receiver
    // and need only land on the same plane.
    in_plane_weight: f32,
    // The target camera, to size a pixel's footprint on a surface.
    camera_position: vec3f,
    // Radians one pixel spans at the image centre.
    pixel_angle: f32,
    // G-buffer-guided warp: PATCHEX_HOLE_FILL_* (0 uncovered side, 1 nearest texel).
    hole_fill: u32,
}
var<immediate> params: Params;

struct WarpCounters {
    hole_pixels: atomic<u32>,
    offscreen_pixels: atomic<u32>,
    // The largest |motion| of a target pixel, in pixels, as f32 bits: non-negative floats
    // order as their bits, so atomicMax finds it.
    largest_motion_bits: atomic<u32>,
}

@group(0) @binding(0) var source_shading: texture_2d<f32>;
@group(0) @binding(1) var source_geometry: texture_2d<f32>;
@group(0) @binding(2) var source_normal_id: texture_2d<f32>;
@group(0) @binding(3) var target_geometry: texture_2d<f32>;
@group(0) @binding(4) var target_normal_id: texture_2d<f32>;
@group(0) @binding(5) var motion: texture_2d<f32>;
@group(0) @binding(6) var warped: texture_storage_2d<rgba16float, write>;
@group(0) @binding(7) var<storage, read_write> counters: WarpCounters;

// The workgroup's tallies (tallies.wgsl).
const TALLY_HOLES: u32 = 0u;
const TALLY_OFFSCREEN: u32 = 1u;
const TALLY_LARGEST_MOTION: u32 = 2u;

fn geometry_weight(target_geo: vec4f, target_nid: vec4f, source_geo: vec4f, source_nid: vec4f) -> f32 {
    if (target_nid.w != source_nid.w) {
        return 0.0;
    }
    if (is_sky(target_geo.w) || is_sky(source_geo.w)) {
        return select(0.0, 1.0, is_sky(target_geo.w) && is_sky(source_geo.w));
    }
    var weight = exp(-(1.0 - dot(target_nid.xyz, source_nid.xyz)) * params.inv_sigma_normal);
    if (target_nid.w == 0.0) {
        // Measured in pixel footprints on the target's surface, so the test means the same at
        // every resolution and viewing angle.
        let view = normalize(params.camera_position - target_geo.xyz);
        let facing = max(abs(dot(target_nid.xyz, view)), MIN_FACING);
        let footprint = target_geo.w * params.pixel_angle / facing;
        let offset = source_geo.xyz - target_geo.xyz;
        let across = dot(target_nid.xyz, offset) * target_nid.xyz;
        let e = length(across + params.in_plane_weight * (offset - across)) / footprint * params.inv_sigma_position;
        weight *= exp(-e * e);
    } else {
        let e = abs(target_geo.w - source_geo.w) / max(target_geo.w, source_geo.w) * params.inv_sigma_depth;
        weight *= exp(-e * e);
    }
    return weight;
}

// Where target pixel `p` lands in frame t when it follows `motion` (raw engine units).
fn source_point(p: vec2u, motion: vec2f) -> vec2f {
    return vec2f(p) + 0.5 + motion * params.motion_scale + params.jitter_delta;
}

// Written so that a NaN motion vector counts as off-screen.
fn is_offscreen(q: vec2f) -> bool {
    return !(all(q >= vec2f(0.0)) && all(q < vec2f(params.extent)));
}

fn texel(q: vec2f) -> vec2i {
    return clamp(vec2i(floor(q)), vec2i(0), vec2i(params.extent) - 1);
}

// Agreement of the target pixel's geometry with frame t's texel `s`.
fn agreement_at(target_geo: vec4f, target_nid: vec4f, s: vec2i) -> f32 {
    return geometry_weight(target_geo, target_nid,
        textureLoad(source_geometry, s, 0), textureLoad(source_normal_id, s, 0));
}

// Frame t's shading at `q`, bilinear over the texels around it.
fn bilinear_shading(q: vec2f) -> vec3f {
    let corner = vec2i(floor(q - 0.5));
    let f = q - 0.5 - floor(q - 0.5);
    let last = vec2i(params.extent) - 1;
    let s00 = textureLoad(source_shading, clamp(corner, vec2i(0), last), 0).rgb;
    let s10 = textureLoad(source_shading, clamp(corner + vec2i(1, 0), vec2i(0), last), 0).rgb;
    let s01 = textureLoad(source_shading, clamp(corner + vec2i(0, 1), vec2i(0), last), 0).rgb;
    let s11 = textureLoad(source_shading, clamp(corner + vec2i(1, 1), vec2i(0), last), 0).rgb;
    return mix(mix(s00, s10, f.x), mix(s01, s11, f.x), f.y);
}

struct WarpedPixel {
    shading: vec3f,
    hole: bool,
    offscreen: bool,
}

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u, @builtin(local_invocation_index) lane: u32) {
    open_tallies(lane);

    let p = id.xy;
    if (all(p < params.extent)) {
        let result = warp_pixel(p);
        textureStore(warped, p, vec4f(to_half(result.shading), select(1.0, 0.0, result.hole)));
        if (result.hole) {
            atomicAdd(&group_tallies[TALLY_HOLES], 1u);
        }
        if (result.offscreen) {
            atomicAdd(&group_tallies[TALLY_OFFSCREEN], 1u);
        }
        // NaN and infinite vectors fail the comparison and are left out; the length is spelled
        // out so that vectors whose square overflows are left out on every driver alike.
        let scaled = textureLoad(motion, p, 0).xy * params.motion_scale;
        let reach = sqrt(dot(scaled, scaled));
        if (reach <= MAX_FINITE) {
            atomicMax(&group_tallies[TALLY_LARGEST_MOTION], bitcast<u32>(reach));
        }
    }

    if (close_tallies(lane)) {
        atomicAdd(&counters.hole_pixels, atomicLoad(&group_tallies[TALLY_HOLES]));
        atomicAdd(&counters.offscreen_pixels, atomicLoad(&group_tallies[TALLY_OFFSCREEN]));
        atomicMax(&counters.largest_motion_bits, atomicLoad(&group_tallies[TALLY_LARGEST_MOTION]));
    }
}
