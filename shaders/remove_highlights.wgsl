// With a PatchexSunLight: takes the sun's highlights out of frame t's shading, which the warps
// then carry without them, and keeps the sun's visibility for the target (place_highlights.wgsl
// adds the highlights back as the target's view sees them). In place of shading s, of colour c
// over modulation factor f (gbuffer.wgsl `demodulated`, which may have scaled f up):
//   s' = s - visibility * specular / f.
// The result may be negative where the engine's reflection differs from the model: the warp
// carries it as it is, and the target's highlight adds back what was taken.
// #import gbuffer
// #import sun_specular
// #import tallies

struct Params {
    extent: vec2u,
    has_material: u32,
    // With a shadow input whose shadows stay in the shading (not separated): its visibility
    // (static casters) times the dynamic casters' mask is the term the shading holds.
    times_dynamic_mask: u32,
    // Frame t's camera as rays through its pixel centres (`Cameras`, without the position).
    ray_at_origin: vec3f,
    ray_per_x: vec3f,
    ray_per_y: vec3f,
    sun_direction: vec3f,
    sun_illuminance: vec3f,
}
var<immediate> params: Params;

@group(0) @binding(0) var shading: texture_storage_2d<rgba16float, read_write>;
@group(0) @binding(1) var visibility: texture_2d<f32>;
@group(0) @binding(2) var base_color: texture_2d<f32>;
@group(0) @binding(3) var material: texture_2d<f32>;
// Frame t's packed G-buffer (pack_gbuffer.wgsl).
@group(0) @binding(4) var source_depth: texture_2d<f32>;
@group(0) @binding(5) var source_normal_id: texture_2d<u32>;
@group(0) @binding(6) var kept_visibility: texture_storage_2d<r16float, write>;
@group(0) @binding(7) var<storage, read_write> counters: SanitizeCounters;
// PatchexShadowInput.mask, with `times_dynamic_mask` (its sanitising is the separation's to count).
@group(0) @binding(8) var dynamic_mask: texture_2d<f32>;

// A setting as this pass branches on it: tied to an image's size, which the driver cannot inline,
// so that lavapipe does not compile the shader again for every value at every dispatch
// (include/warp.wgsl `unspecialised`). Always `setting`.
fn unspecialised(setting: u32) -> u32 {
    return select(0u, setting, textureDimensions(visibility).x != 0u);
}

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u, @builtin(local_invocation_index) lane: u32) {
    open_tallies(lane);
    let p = id.xy;
    if (all(p < params.extent)) {
        let seen = sanitize_unit(vec3f(textureLoad(visibility, p, 0).r, 0.0, 0.0));
        var lit = seen.value.x;
        if (unspecialised(params.times_dynamic_mask) != ABSENT) {
            lit *= sanitize_unit(vec3f(textureLoad(dynamic_mask, p, 0).r, 0.0, 0.0)).value.x;
        }
        textureStore(kept_visibility, p, vec4f(lit, 0.0, 0.0, 1.0));
        let normal = unpack_normal(textureLoad(source_normal_id, p, 0).r);
        let depth = textureLoad(source_depth, p, 0).r;
        var changed = seen.changed;
        if (lit > 0.0 && !is_sky(depth) && any(normal != vec3f(0.0))) {
            let has_material = unspecialised(params.has_material);
            let glossy = glossy_material(base_color, material, p, has_material);
            changed = changed || glossy.roughness_changed;
            let ray = params.ray_at_origin + f32(p.x) * params.ray_per_x + f32(p.y) * params.ray_per_y;
            let sun = Sun(params.sun_direction, params.sun_illuminance);
            let highlight = lit * sun_specular(sun, normal, -normalize(ray), glossy);
            let s = textureLoad(shading, p);
            // The factor the colour was divided by: the pixel's modulation, scaled as the
            // divisor in alpha says.
            let factor = pixel_modulation(base_color, material, p, has_material).factor;
            let scale = max(1.0, s.a / largest(factor));
            textureStore(shading, p, vec4f(to_half(s.rgb - highlight / (factor * scale)), s.a));
        }
        if (changed) {
            atomicAdd(&group_tallies[0u], 1u);
        }
    }
    if (close_tallies(lane)) {
        atomicAdd(&counters.sanitized_pixels, atomicLoad(&group_tallies[0u]));
    }
}
