// With a PatchexSunLight or a PatchexSkyLight on frame t: adds the sun's highlights and the
// sky's reflection to the extrapolated colour, as the target's view sees them on the target's
// surfaces, in place of frame t's, which remove_highlights.wgsl took out of the shading the warp
// carried:
//   c' = c + visibility * dynamic * (sun specular + sun diffuse change) + sky specular.
// The sun's diffuse change is what a moving object's Lambert reflection of the sun gains or loses
// by turning: the warp carries it as frame t lit it, at frame t's normal.
// The sun's visibility is frame t's where it saw the target's surface: from the texels around
// where the motion vectors lead that pass the G-buffer warp's agreement test. `dynamic` is 1
// without a shadow input; with one, the dynamic casters' visibility at the target where a target
// shadow input gives it, else the share of light the shadows leave there (remodulate.wgsl).
// #import gbuffer
// #import cameras
// #import surface
// #import surface_match
// #import fill
// #import sun_specular
// #import sky_specular
// #import tallies

struct Params {
    extent: vec2u,
    // Turns the engine's motion vectors into backward motion in pixels.
    motion_scale: vec2f,
    // Target jitter minus frame t's jitter, in pixels.
    jitter_delta: vec2f,
    has_material: u32,
    has_shadow_share: u32,
    // With a target shadow input: the dynamic casters' visibility at the target, which static
    // pixels' highlights take in place of the share.
    has_target_mask: u32,
    // The call's warp settings, for its agreement test (include/warp.wgsl).
    inv_sigma_depth: f32,
    inv_sigma_normal: f32,
    inv_sigma_position: f32,
    in_plane_weight: f32,
    pixel_angle: f32,
    // With a sky: its map's mips (0 without one) and side, as remove_highlights.wgsl kept them
    // side by side.
    sky_levels: u32,
    sky_side: u32,
    sun_direction: vec3f,
    sun_illuminance: vec3f,
}
var<immediate> params: Params;

@group(0) @binding(0) var frame: texture_storage_2d<rgba16float, read_write>;
@group(0) @binding(1) var target_depth: texture_2d<f32>;
@group(0) @binding(2) var target_normal: texture_2d<f32>;
@group(0) @binding(3) var base_color: texture_2d<f32>;
@group(0) @binding(4) var material: texture_2d<f32>;
@group(0) @binding(5) var motion: texture_2d<f32>;
// Frame t's visibility of the sun, as remove_highlights.wgsl kept it.
@group(0) @binding(6) var kept_visibility: texture_2d<f32>;
// With `has_shadow_share`: the share of light the dynamic shadows take away at the target.
@group(0) @binding(7) var shadow_share: texture_2d<f32>;
@group(0) @binding(8) var<uniform> cameras: Cameras;
@group(0) @binding(9) var<storage, read_write> counters: SanitizeCounters;
// Frame t's packed G-buffer (pack_gbuffer.wgsl), which says which texels show the target's
// surface.
@group(0) @binding(10) var source_depth: texture_2d<f32>;
@group(0) @binding(11) var source_normal_id: texture_2d<u32>;
@group(0) @binding(12) var target_stencil: texture_2d<u32>;
@group(0) @binding(13) var target_mask: texture_2d<f32>;
@group(0) @binding(14) var kept_sky: texture_2d<f32>;

// The share of q's bilinear footprint agreeing texels must hold, as the warp's (BILINEAR_ACCEPT).
const BILINEAR_ACCEPT: f32 = 0.5;

// A setting as this pass branches on it: tied to an image's size, which the driver cannot inline,
// so that lavapipe does not compile the shader again for every value at every dispatch
// (include/warp.wgsl `unspecialised`). Always `setting`.
fn unspecialised(setting: u32) -> u32 {
    return select(0u, setting, textureDimensions(kept_visibility).x != 0u);
}

// Whether frame t's texel `s` shows surface `t`, as the G-buffer warp decides it.
fn agrees(t: Surface, s: vec2i) -> bool {
    return agreement_at(t, s) >= AGREEMENT_THRESHOLD;
}

// What the fill spreads (fill.wgsl): frame t's visibility, and its normal.
alias FillValue = vec4f;

fn fill_value(s: vec2i) -> vec4f {
    return vec4f(textureLoad(kept_visibility, s, 0).r, source_normal(s));
}

// What frame t saw of surface `t` around `q`: the sun's visibility, and the normal its
// shading was lit with.
struct SeenFromSource {
    visibility: f32,
    normal: vec3f,
}

// Frame t's visibility of the sun and normal where it saw surface `t` around `q`: the bilinear
// blend of the texels that agree with it when they hold enough of the blend, else the mean of
// the 3x3 texels around q that agree. Where none does (a hole, off screen or uncovered), frame
// t's visibility and normal spread as the G-buffer warp's fill spreads its shading there: from
// the texels whose surface matches, which the fill's shading came from.
fn seen_from_source(t: Surface, q: vec2f) -> SeenFromSource {
    let corner = vec2i(floor(q - 0.5));
    let f = q - 0.5 - floor(q - 0.5);
    let last = vec2i(params.extent) - 1;
    // Unrolled: lavapipe runs a loop of divergent loads lane by lane.
    let s00 = clamp(corner, vec2i(0), last);
    let s10 = clamp(corner + vec2i(1, 0), vec2i(0), last);
    let s01 = clamp(corner + vec2i(0, 1), vec2i(0), last);
    let s11 = clamp(corner + vec2i(1, 1), vec2i(0), last);
    let v = vec4f(textureLoad(kept_visibility, s00, 0).r, textureLoad(kept_visibility, s10, 0).r,
        textureLoad(kept_visibility, s01, 0).r, textureLoad(kept_visibility, s11, 0).r);
    let w = vec4f((1.0 - f.x) * (1.0 - f.y), f.x * (1.0 - f.y), (1.0 - f.x) * f.y, f.x * f.y);
    let agreeing = w * vec4f(select(0.0, 1.0, agrees(t, s00)), select(0.0, 1.0, agrees(t, s10)),
        select(0.0, 1.0, agrees(t, s01)), select(0.0, 1.0, agrees(t, s11)));
    let weight = agreeing.x + agreeing.y + agreeing.z + agreeing.w;
    if (weight >= BILINEAR_ACCEPT) {
        let normal = agreeing.x * source_normal(s00) + agreeing.y * source_normal(s10)
            + agreeing.z * source_normal(s01) + agreeing.w * source_normal(s11);
        return SeenFromSource(dot(agreeing, v) / weight, unit_or_zero(normal));
    }
    let centre = clamp(vec2i(floor(q)), vec2i(0), last);
    var count = 0.0;
    var sum = 0.0;
    var normal = vec3f(0.0);
    for (var i = 0; i < 9; i++) {
        let s = clamp(centre + vec2i(i % 3 - 1, i / 3 - 1), vec2i(0), last);
        if (agrees(t, s)) {
            count += 1.0;
            sum += textureLoad(kept_visibility, s, 0).r;
            normal += source_normal(s);
        }
    }
    if (count > 0.0) {
        return SeenFromSource(sum / count, unit_or_zero(normal));
    }
    let filled = fill_hole(q, t);
    return SeenFromSource(filled.x, unit_or_zero(filled.yzw));
}

// Frame t's normal at texel `s` (zero where it has none).
fn source_normal(s: vec2i) -> vec3f {
    return unpack_normal(textureLoad(source_normal_id, s, 0).r);
}

// `v` made unit, or zero where it has no direction (normals that cancel out).
fn unit_or_zero(v: vec3f) -> vec3f {
    let length2 = dot(v, v);
    return select(vec3f(0.0), v * inverseSqrt(length2), length2 > 1e-12);
}

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u, @builtin(local_invocation_index) lane: u32) {
    open_tallies(lane);
    let p = id.xy;
    if (all(p < params.extent)) {
        let t = target_surface(p);
        let q = vec2f(p) + 0.5 + textureLoad(motion, p, 0).xy * params.motion_scale + params.jitter_delta;
        // Invalid geometry (the warp counts it) and NaN motion get no highlight.
        let usable = t.valid && !is_sky(t.depth) && any(t.normal != vec3f(0.0)) && all(q == q);
        var changed = false;
        if (usable) {
            let ray = cameras.target_at_origin + f32(p.x) * cameras.target_per_x
                + f32(p.y) * cameras.target_per_y;
            let view = -normalize(ray);
            let seen = seen_from_source(t, q);
            let glossy = glossy_material(base_color, material, p, unspecialised(params.has_material));
            let sun = Sun(params.sun_direction, params.sun_illuminance);
            var sun_light = sun_specular(sun, t.normal, view, glossy);
            // A moving object may have turned towards or away from the sun; a static surface
            // has not, and its normals differ only by resampling.
            if (t.id != 0u) {
                sun_light += sun_diffuse_change(sun, seen.normal, t.normal, glossy);
            }
            var highlight = seen.visibility * sun_light;
            // The dynamic shadows at the target: a highlight is the sun's alone, so the mask
            // takes it where there is one; the share, the part of all light they take, elsewhere.
            if (unspecialised(params.has_target_mask) != ABSENT && t.id == 0u) {
                let mask = sanitize_unit(vec3f(textureLoad(target_mask, p, 0).r, 0.0, 0.0));
                highlight *= mask.value.x;
            } else if (unspecialised(params.has_shadow_share) != ABSENT) {
                highlight *= 1.0 + textureLoad(shadow_share, p, 0).rgb;
            }
            let sky_map = SkyMap(params.sky_side, unspecialised(params.sky_levels), true);
            if (sky_map.levels != 0u) {
                highlight += sky_specular(kept_sky, sky_map, t.normal, view, glossy);
            }
            let color = sanitize_color(textureLoad(frame, p).rgb + highlight);
            textureStore(frame, p, vec4f(to_half(color.value), 1.0));
            changed = glossy.roughness_changed || color.changed;
        }
        if (changed) {
            atomicAdd(&group_tallies[0u], 1u);
        }
    }
    if (close_tallies(lane)) {
        atomicAdd(&counters.sanitized_pixels, atomicLoad(&group_tallies[0u]));
    }
}
