// One Farneback iteration's per-texel equations. Frame t's expansion (A0, b0) at texel x and
// frame t-1's (A1, b1) at x + d, where d is the current flow estimate, give
//   A = (A0 + A1) / 2,   db = -(b1 - b0) / 2 + A d,
// and the displacement to frame t-1 solves A d' = db. A window of texels is fitted by least
// squares, so each texel contributes G = A^T A and h = A^T db (summed by the next two passes).
// A small multiple of (I, d) is added so that a window without structure keeps its estimate
// instead of falling to zero. The estimate is this level's flow, the coarser level's flow
// scaled up (first iteration of a level), or at the coarsest level's first iteration the motion
// the cameras give a static receiver: a shadow on the ground moves with the ground as the camera
// pans, and only its drift across the ground (its caster's motion) is left for the flow to find.
// Started at zero, a fast pan's 20 pixels a frame were found only to within about 2 pixels.
// Writes (G11, G12, G22, h1) and h2 in two atlases.
// #import flow

struct Params {
    level_offset: vec2u,
    level_size: vec2u,
    prior_offset: vec2u,
    prior_size: vec2u,
    has_prior: u32,
    regularization: f32,
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

@group(0) @binding(0) var poly_current: texture_2d<f32>;
@group(0) @binding(1) var poly_xy_current: texture_2d<f32>;
@group(0) @binding(2) var poly_previous: texture_2d<f32>;
@group(0) @binding(3) var poly_xy_previous: texture_2d<f32>;
@group(0) @binding(4) var flow: texture_2d<f32>;
@group(0) @binding(5) var equations: texture_storage_2d<rgba32float, write>;
@group(0) @binding(6) var equations_h2: texture_storage_2d<r32float, write>;
// Frame t's linear depth, as the G-buffer packing wrote it.
@group(0) @binding(7) var source_depth: texture_2d<f32>;

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
    var d: vec2f;
    if (params.has_prior != 0u) {
        let ratio = vec2f(params.level_size) / vec2f(params.prior_size);
        let pos = (vec2f(p) + 0.5) / ratio - 0.5;
        d = level_bilinear(flow, params.prior_offset, params.prior_size, pos).xy * ratio;
    } else {
        d = camera_motion(p);
    }
    let texel = vec2i(params.level_offset + p);
    let current = textureLoad(poly_current, texel, 0);
    let current_xy = textureLoad(poly_xy_current, texel, 0).r;
    let at = vec2f(p) + d;
    let previous = level_bilinear(poly_previous, params.level_offset, params.level_size, at);
    let previous_xy = level_bilinear(poly_xy_previous, params.level_offset, params.level_size, at).r;
    let a11 = 0.5 * (current.z + previous.z);
    let a22 = 0.5 * (current.w + previous.w);
    // The xy coefficient is twice the off-diagonal of A.
    let a12 = 0.25 * (current_xy + previous_xy);
    let db = -0.5 * (previous.xy - current.xy) + vec2f(a11 * d.x + a12 * d.y, a12 * d.x + a22 * d.y);
    let eps = params.regularization;
    let g11 = a11 * a11 + a12 * a12 + eps;
    let g12 = a12 * (a11 + a22);
    let g22 = a22 * a22 + a12 * a12 + eps;
    let h1 = a11 * db.x + a12 * db.y + eps * d.x;
    let h2 = a12 * db.x + a22 * db.y + eps * d.y;
    textureStore(equations, texel, vec4f(g11, g12, g22, h1));
    textureStore(equations_h2, texel, vec4f(h2, 0.0, 0.0, 0.0));
}
