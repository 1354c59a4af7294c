// G-buffer-guided backward warp (after ExtraSS, Wu et al. 2023). Each target pixel follows its
// motion vector to a point q in frame t. Where the source texels around q show the same surface
// as the target pixel (same object id, close normals, and for static surfaces the same world
// position, for moving ones the same relative depth), it takes their bilinear blend, weighted by
// that agreement, so zero motion returns frame t exactly. Where they do not (disocclusions,
// silhouettes, motion-vector errors), it gathers from a (2r+1)^2 window with a joint bilateral
// kernel instead. A pixel whose source leaves the screen or finds no agreeing texel is a hole
// (alpha 0).
// #import gbuffer

// A source texel agrees with the target when its geometry weight reaches this value.
const AGREEMENT_THRESHOLD: f32 = 0.5;
// The bilinear blend is kept when agreeing texels carry at least this share of its weight.
const BILINEAR_ACCEPT: f32 = 0.5;
// Below this total weight the kernel found nothing usable; take the nearest texel instead.
const MIN_TOTAL_WEIGHT: f32 = 1e-6;

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
}
var<immediate> params: Params;

struct WarpCounters {
    hole_pixels: atomic<u32>,
    offscreen_pixels: atomic<u32>,
}

@group(0) @binding(0) var source_shading: texture_2d<f32>;
@group(0) @binding(1) var source_geometry: texture_2d<f32>;
@group(0) @binding(2) var source_normal_id: texture_2d<f32>;
@group(0) @binding(3) var target_geometry: texture_2d<f32>;
@group(0) @binding(4) var target_normal_id: texture_2d<f32>;
@group(0) @binding(5) var motion: texture_2d<f32>;
@group(0) @binding(6) var warped: texture_storage_2d<rgba32float, write>;
@group(0) @binding(7) var<storage, read_write> counters: WarpCounters;

var<workgroup> group_holes: atomic<u32>;
var<workgroup> group_offscreen: atomic<u32>;

fn geometry_weight(target_geo: vec4f, target_nid: vec4f, source_geo: vec4f, source_nid: vec4f) -> f32 {
    if (target_nid.w != source_nid.w) {
        return 0.0;
    }
    if (is_sky(target_geo.w) || is_sky(source_geo.w)) {
        return select(0.0, 1.0, is_sky(target_geo.w) && is_sky(source_geo.w));
    }
    var weight = exp(-(1.0 - dot(target_nid.xyz, source_nid.xyz)) * params.inv_sigma_normal);
    if (target_nid.w == 0.0) {
        let e = distance(target_geo.xyz, source_geo.xyz) / target_geo.w * params.inv_sigma_position;
        weight *= exp(-e * e);
    } else {
        let e = abs(target_geo.w - source_geo.w) / max(target_geo.w, source_geo.w) * params.inv_sigma_depth;
        weight *= exp(-e * e);
    }
    return weight;
}

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u, @builtin(local_invocation_index) lane: u32) {
    if (lane == 0u) {
        atomicStore(&group_holes, 0u);
        atomicStore(&group_offscreen, 0u);
    }
    workgroupBarrier();

    let p = id.xy;
    if (all(p < params.extent)) {
        let extent = vec2i(params.extent);
        let q = vec2f(p) + 0.5 + textureLoad(motion, p, 0).xy * params.motion_scale + params.jitter_delta;
        // Written so that a NaN motion vector counts as off-screen.
        let offscreen = !(all(q >= vec2f(0.0)) && all(q < vec2f(params.extent)));
        let target_geo = textureLoad(target_geometry, p, 0);
        let target_nid = textureLoad(target_normal_id, p, 0);

        // Bilinear footprint of q, each texel weighted by its agreement with the target.
        let corner = vec2i(floor(q - 0.5));
        let f = q - 0.5 - floor(q - 0.5);
        var shading_sum = vec3f(0.0);
        var weight_sum = 0.0;
        var best_agreement = 0.0;
        for (var i = 0; i < 4; i++) {
            let offset = vec2i(i & 1, i >> 1u);
            let s = clamp(corner + offset, vec2i(0), extent - 1);
            let agreement = geometry_weight(target_geo, target_nid,
                textureLoad(source_geometry, s, 0), textureLoad(source_normal_id, s, 0));
            let bilinear = select(1.0 - f, f, vec2<bool>(offset == vec2i(1)));
            let footprint = bilinear.x * bilinear.y;
            shading_sum += footprint * agreement * textureLoad(source_shading, s, 0).rgb;
            weight_sum += footprint * agreement;
            if (footprint > 0.0) {
                best_agreement = max(best_agreement, agreement);
            }
        }

        if (weight_sum < BILINEAR_ACCEPT) {
            // Joint bilateral gather around q.
            shading_sum = vec3f(0.0);
            weight_sum = 0.0;
            let centre = clamp(vec2i(floor(q)), vec2i(0), extent - 1);
            let r = params.kernel_radius;
            for (var dy = -r; dy <= r; dy++) {
                for (var dx = -r; dx <= r; dx++) {
                    let s = clamp(centre + vec2i(dx, dy), vec2i(0), extent - 1);
                    let agreement = geometry_weight(target_geo, target_nid,
                        textureLoad(source_geometry, s, 0), textureLoad(source_normal_id, s, 0));
                    let d = vec2f(s) + 0.5 - q;
                    let weight = exp(-dot(d, d) * params.inv_two_sigma_spatial_sq) * agreement;
                    shading_sum += weight * textureLoad(source_shading, s, 0).rgb;
                    weight_sum += weight;
                    best_agreement = max(best_agreement, agreement);
                }
            }
        }
        var shading = textureLoad(source_shading, clamp(vec2i(floor(q)), vec2i(0), extent - 1), 0).rgb;
        if (weight_sum > MIN_TOTAL_WEIGHT) {
            shading = shading_sum / weight_sum;
        }
        let hole = offscreen || best_agreement < AGREEMENT_THRESHOLD;
        textureStore(warped, p, vec4f(shading, select(1.0, 0.0, hole)));
        if (hole) {
            atomicAdd(&group_holes, 1u);
        }
        if (offscreen) {
            atomicAdd(&group_offscreen, 1u);
        }
    }

    workgroupBarrier();
    if (lane == 0u) {
        atomicAdd(&counters.hole_pixels, atomicLoad(&group_holes));
        atomicAdd(&counters.offscreen_pixels, atomicLoad(&group_offscreen));
    }
}
