// One Farneback iteration at one level of the pyramid. Frame t's expansion (A0, b0) at texel x
// and frame t-1's (A1, b1) at x + d, where d is the current estimate, give
//   A = (A0 + A1) / 2,   db = -(b1 - b0) / 2 + A d,
// and the displacement to frame t-1 solves A d' = db. A window of (2r+1)^2 texels is fitted by
// least squares: each texel contributes G = A^T A and h = A^T db, the window sums them (borders
// replicate), and the 2x2 system G d' = h gives the texel's new flow, in texels of the level.
// A small multiple of (I, d) is added so that a window without structure keeps its estimate
// instead of falling to zero, and keeps G positive definite.
//
// The estimate is this level's flow from the last iteration, or the coarser level's scaled up
// (a level's first iteration). The coarsest level's first iteration, the start, takes the motion
// the cameras give a static receiver (`camera_motion`), and expands frame t's mask there itself
// (expansion.wgsl): it runs beside shadow_poly.wgsl, which expands every level for the later
// iterations and the next frame, rather than after it. The estimate is read from one atlas and
// the new flow written to the other, so no workgroup reads what another writes.
//
// One workgroup solves an 8x8 tile. Its window reaches r texels past the tile, so it computes
// the equations of the tile and that border in workgroup memory (in strips of rows, for the
// wider windows), sums each row's window there, then each column's: the equations never leave
// the chip, and the iteration is one dispatch.
// #import atlas
// #import flow
// #import expansion

// The tile's edge, and the workgroup's.
const TILE: i32 = 8;
// shadow_flow::MAX_WINDOW_RADIUS.
const MAX_RADIUS: i32 = 15;
// Equations one strip holds: the whole span of the default window (22 x 22 texels for radius
// 7), so that it takes one strip and two barriers, each a coroutine switch on lavapipe.
const STRIP: i32 = 484;
// Row sums kept for every row of the widest span (TILE + 2 * MAX_RADIUS).
const MAX_SPAN: i32 = 38;

struct Params {
    level_offset: vec2u,
    level_size: vec2u,
    // Where the estimate lies in its atlas: this level, or the coarser one.
    prior_offset: vec2u,
    prior_size: vec2u,
    // Frame t's size in pixels.
    frame_extent: vec2u,
    radius: i32,
    regularization: f32,
    // 1 at the start: the estimate is the cameras' (`camera_motion`), not the atlas's, and frame
    // t's expansion is made from `mask_pyramid`, not read from `poly_current`.
    starts: u32,
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
@group(0) @binding(4) var estimate: texture_2d<f32>;
@group(0) @binding(5) var flow: texture_storage_2d<rg32float, write>;
// Frame t's linear depth, as the G-buffer packing wrote it: the cameras' estimate.
@group(0) @binding(6) var source_depth: texture_2d<f32>;
// The start's frame t: its mask, and how to expand it. The other iterations read
// `poly_current` instead.
@group(0) @binding(7) var mask_pyramid: texture_2d<f32>;
@group(0) @binding(8) var<uniform> expansion: ExpansionConstants;

// One strip of equations: (G11, G12, G22, h1) and h2 for as many whole rows of the span as
// fit. With the row sums, 15760 bytes: within the 16 KiB every Vulkan device offers.
var<workgroup> strip: array<vec4f, STRIP>;
var<workgroup> strip_h2: array<f32, STRIP>;
// Each row of the span summed over the window, at the tile's columns.
var<workgroup> rows: array<vec4f, MAX_SPAN * TILE>;
var<workgroup> rows_h2: array<f32, MAX_SPAN * TILE>;

struct Equations {
    g: vec4f,
    h2: f32,
}

// The window radius, within what the strips hold.
fn radius() -> i32 {
    return min(i32(unspecialised(u32(params.radius), estimate)), MAX_RADIUS);
}

// Where static surfaces under level texel p moved from frame t to frame t-1, in texels of this
// level; zero where that is not finite (sky at infinity). A shadow on the ground moves with the
// ground as the camera pans, and only its drift across the ground (its caster's motion) is left
// for the flow to find. Started at zero, a fast pan's 20 pixels a frame were found only to
// within about 2 pixels.
fn camera_motion(p: vec2i) -> vec2f {
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

fn starts() -> bool {
    return unspecialised(params.starts, estimate) != 0u;
}

// Frame t's expansion at level texel p.
fn current_at(p: vec2i) -> Expanded {
    if (starts()) {
        return expand(params.level_offset, params.level_size, p);
    }
    let texel = vec2i(params.level_offset) + p;
    return Expanded(textureLoad(poly_current, texel, 0), textureLoad(poly_xy_current, texel, 0).r);
}

// The estimate at level texel p: the cameras', or the atlas's scaled to this level.
fn estimate_at(p: vec2i) -> vec2f {
    if (starts()) {
        return camera_motion(p);
    }
    let ratio = vec2f(params.level_size) / vec2f(params.prior_size);
    let pos = (vec2f(p) + 0.5) / ratio - 0.5;
    return level_bilinear(estimate, params.prior_offset, params.prior_size, pos).xy * ratio;
}

// The equations of level texel p (inside the level).
fn equations(p: vec2i) -> Equations {
    let d = estimate_at(p);
    let expanded = current_at(p);
    let current = expanded.coefficients;
    let current_xy = expanded.xy;
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
    return Equations(vec4f(g11, g12, g22, h1), h2);
}

@compute @workgroup_size(8, 8, 1)
fn main(
    @builtin(workgroup_id) group: vec3u,
    @builtin(local_invocation_id) local: vec3u,
    @builtin(local_invocation_index) lane: u32,
) {
    let r = radius();
    let span = TILE + 2 * r;
    let size = vec2i(params.level_size);
    // The level texel at the span's corner.
    let corner = vec2i(group.xy) * TILE - r;
    let strip_rows = STRIP / span;
    for (var first_row = 0; first_row < span; first_row += strip_rows) {
        let count = min(strip_rows, span - first_row) * span;
        for (var i = i32(lane); i < count; i += TILE * TILE) {
            // A texel past the border has the equations of the border's: they replicate.
            let q = clamp(corner + vec2i(i % span, first_row + i / span), vec2i(0), size - 1);
            let e = equations(q);
            strip[i] = e.g;
            strip_h2[i] = e.h2;
        }
        workgroupBarrier();
        // Each invocation sums the windows of its column in every eighth row of the strip.
        for (var row = i32(local.y); row < min(strip_rows, span - first_row); row += TILE) {
            var sum = vec4f(0.0);
            var sum_h2 = 0.0;
            let start = row * span + i32(local.x);
            for (var k = 0; k <= 2 * r; k++) {
                sum += strip[start + k];
                sum_h2 += strip_h2[start + k];
            }
            let index = (first_row + row) * TILE + i32(local.x);
            rows[index] = sum;
            rows_h2[index] = sum_h2;
        }
        workgroupBarrier();
    }
    let p = vec2i(group.xy) * TILE + vec2i(local.xy);
    if (any(p >= size)) {
        return;
    }
    var sum = vec4f(0.0);
    var h2 = 0.0;
    for (var k = 0; k <= 2 * r; k++) {
        let index = (i32(local.y) + k) * TILE + i32(local.x);
        sum += rows[index];
        h2 += rows_h2[index];
    }
    let g11 = sum.x;
    let g12 = sum.y;
    let g22 = sum.z;
    let h1 = sum.w;
    let det = g11 * g22 - g12 * g12;
    let d = vec2f(g22 * h1 - g12 * h2, g11 * h2 - g12 * h1) / det;
    textureStore(flow, vec2i(params.level_offset) + p, vec4f(d, 0.0, 0.0));
}
