// Turns one instant's engine G-buffer (depth in any supported convention, normals in either
// encoding, optional stencil) into the plugin's canonical form, so every later pass reads one
// layout: geometry = (world position, linear depth), normal_id = (world normal, object id).
// Pixels with a NaN or infinite depth, normal or (for the target) motion vector are counted:
// later passes treat them as holes or static background, and the statistics say how many.
// #import gbuffer
// #import tallies

const DEPTH_LINEAR_VIEW_Z: u32 = 0u;
const DEPTH_HARDWARE: u32 = 1u;
const DEPTH_HARDWARE_REVERSED: u32 = 2u;
const NORMAL_UNORM: u32 = 1u;

struct Params {
    inv_view_proj: mat4x4f,
    camera_position: vec3f,
    far: f32,
    camera_forward: vec3f,
    depth_convention: u32,
    extent: vec2u,
    normal_encoding: u32,
    has_stencil: u32,
    has_motion: u32,
}
var<immediate> params: Params;

@group(0) @binding(0) var depth: texture_2d<f32>;
@group(0) @binding(1) var normal: texture_2d<f32>;
@group(0) @binding(2) var stencil: texture_2d<u32>;
@group(0) @binding(3) var geometry: texture_storage_2d<rgba32float, write>;
@group(0) @binding(4) var normal_id: texture_storage_2d<rgba16float, write>;
@group(0) @binding(5) var motion: texture_2d<f32>;
@group(0) @binding(6) var<storage, read_write> counters: GeometryCounters;

struct GeometryCounters {
    invalid_pixels: atomic<u32>,
}


fn unproject(ndc: vec2f, device_depth: f32) -> vec4f {
    return params.inv_view_proj * vec4f(ndc, device_depth, 1.0);
}

// World position and linear depth of the surface seen through pixel centre `ndc`.
fn surface(ndc: vec2f, stored_depth: f32) -> vec4f {
    if (params.depth_convention == DEPTH_LINEAR_VIEW_Z) {
        if (stored_depth >= params.far) {
            return vec4f(0.0, 0.0, 0.0, SKY_DEPTH);
        }
        // Any point on the pixel's ray gives its direction; scale it to the stored depth.
        let on_ray = unproject(ndc, 0.5);
        let ray = on_ray.xyz / on_ray.w - params.camera_position;
        let position = params.camera_position + ray * (stored_depth / dot(ray, params.camera_forward));
        return vec4f(position, stored_depth);
    }
    let at_far = select(stored_depth >= 1.0, stored_depth <= 0.0,
        params.depth_convention == DEPTH_HARDWARE_REVERSED);
    let clip = unproject(ndc, stored_depth);
    // w reaches zero at an infinite far plane.
    if (at_far || abs(clip.w) < 1e-20) {
        return vec4f(0.0, 0.0, 0.0, SKY_DEPTH);
    }
    let position = clip.xyz / clip.w;
    return vec4f(position, dot(position - params.camera_position, params.camera_forward));
}

fn pack_pixel(p: vec2u) -> bool {
    let ndc = (vec2f(p) + 0.5) / vec2f(params.extent) * 2.0 - 1.0;
    let stored_depth = textureLoad(depth, p, 0).r;
    textureStore(geometry, p, surface(ndc, stored_depth));

    let stored_normal = textureLoad(normal, p, 0).xyz;
    var n = stored_normal;
    if (params.normal_encoding == NORMAL_UNORM) {
        n = n * 2.0 - 1.0;
    }
    let n_length = length(n);
    n = select(vec3f(0.0), n / n_length, n_length > 1e-6);
    var object_id = 0u;
    if (params.has_stencil != ABSENT) {
        object_id = textureLoad(stencil, p, 0).r;
    }
    textureStore(normal_id, p, vec4f(n, f32(object_id)));

    var finite = is_finite(vec4f(stored_normal, stored_depth));
    if (params.has_motion != ABSENT) {
        finite = finite && is_finite(vec4f(textureLoad(motion, p, 0).xy, 0.0, 0.0));
    }
    return !finite;
}

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u, @builtin(local_invocation_index) lane: u32) {
    open_tallies(lane);
    let p = id.xy;
    if (all(p < params.extent) && pack_pixel(p)) {
        atomicAdd(&group_tallies[0u], 1u);
    }
    if (close_tallies(lane)) {
        atomicAdd(&counters.invalid_pixels, atomicLoad(&group_tallies[0u]));
    }
}
