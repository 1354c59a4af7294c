// Turns frame t's engine G-buffer (depth in any supported convention, normals in either
// encoding, optional stencil) into the plugin's canonical form, which the warps read around each
// target pixel: linear depth, and the world normal with the object id packed in 32 bits
// (gbuffer.wgsl). The target's G-buffer is read by the warps themselves, through the same
// functions. Pixels whose depth is NaN or outside its convention's range, or whose normal is NaN
// or infinite, are counted (gbuffer.wgsl `valid_geometry`): the statistics say how many.
// #import gbuffer
// #import tallies

struct Params {
    // How this instant's depth reads (gbuffer.wgsl `linear_depth`).
    depth_curve: vec4f,
    far: f32,
    depth_convention: u32,
    extent: vec2u,
    normal_encoding: u32,
    has_stencil: u32,
}
var<immediate> params: Params;

@group(0) @binding(0) var depth: texture_2d<f32>;
@group(0) @binding(1) var normal: texture_2d<f32>;
@group(0) @binding(2) var stencil: texture_2d<u32>;
@group(0) @binding(3) var packed_depth: texture_storage_2d<r32float, write>;
@group(0) @binding(4) var normal_id: texture_storage_2d<r32uint, write>;
@group(0) @binding(6) var<storage, read_write> counters: GeometryCounters;

struct GeometryCounters {
    invalid_pixels: atomic<u32>,
}

fn pack_pixel(p: vec2u) -> bool {
    let stored_depth = textureLoad(depth, p, 0).r;
    let depth = linear_depth(stored_depth, p, params.depth_curve, params.far, params.depth_convention);
    textureStore(packed_depth, p, vec4f(depth, 0.0, 0.0, 0.0));
    let stored_normal = textureLoad(normal, p, 0).xyz;
    let object_id = stencil_object_id(stencil, p, params.has_stencil);
    let packed = pack_normal_id(unit_normal(stored_normal, params.normal_encoding), object_id);
    textureStore(normal_id, p, vec4u(packed, 0u, 0u, 0u));
    return !valid_geometry(stored_depth, stored_normal, params.depth_convention);
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
