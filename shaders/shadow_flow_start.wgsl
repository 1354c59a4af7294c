// The flow's first estimate at the pyramid's coarsest level: the motion the cameras give a
// static receiver. A shadow on the ground moves with the ground as the camera pans, and only
// its drift across the ground (its caster's motion) is left for the flow to find. Started at
// zero, a fast pan's 20 pixels a frame were found only to within about 2 pixels. Written into
// the estimate atlas the first iteration reads (shadow_flow_iterate.wgsl).

struct Params {
    level_offset: vec2u,
    level_size: vec2u,
    // Frame t's size in pixels.
    frame_extent: vec2u,
    // Frame t's pixel (x, y) at linear depth z lies in frame t-1 at (w.y, w.z) / w.x, with
    // w = camera_offset + z * (camera_at_origin + x camera_per_x + y camera_per_y), for a static
    // surface (`Camera::reprojection_into` in src/camera.rs). camera_at_origin.w is this level's
    // frame pixels per texel; the other w are padding.
    camera_offset: vec4f,
    camera_at_origin: vec4f,
    camera_per_x: vec4f,
    camera_per_y: vec4f,
}
var<immediate> params: Params;

// Frame t's linear depth, as the G-buffer packing wrote it.
@group(0) @binding(0) var source_depth: texture_2d<f32>;
@group(0) @binding(1) var estimate: texture_storage_2d<rg32float, write>;

// Where static surfaces under level texel p moved from frame t to frame t-1, in texels of this
// level; zero where that is not finite (sky at infinity).
fn camera_motion(p: vec2u) -> vec2f {
    let step = params.camera_at_origin.w;
    let pixel = (vec2f(p) + 0.5) * step - 0.5;
    let frame = vec2i(params.frame_extent);
    let nearest = clamp(vec2i(floor(pixel + 0.5)), vec2i(0), frame - 1);
    let depth = textureLoad(source_depth, nearest, 0).r;
    let w = params.camera_offset.xyz + depth * (params.camera_at_origin.xyz
        + pixel.x * params.camera_per_x.xyz + pixel.y * params.camera_per_y.xyz);
    let motion = (w.yz / w.x - pixel) / step;
    // NaN fails both comparisons.
    if (!(w.x > 0.0) || !all(abs(motion) < vec2f(1e6))) {
        return vec2f(0.0);
    }
    return motion;
}

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    let p = id.xy;
    if (any(p >= params.level_size)) {
        return;
    }
    textureStore(estimate, params.level_offset + p, vec4f(camera_motion(p), 0.0, 0.0));
}
