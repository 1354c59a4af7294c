// With a PatchexSunLight or a PatchexSkyLight: takes the sun's highlights and the sky's
// reflection out of frame t's shading, which the warps then carry without them, and keeps the
// sun's visibility and the sky's map for the target (place_highlights.wgsl adds them back as
// the target's view sees them). In place of shading s, of colour c over modulation factor f
// (gbuffer.wgsl `demodulated`, which may have scaled f up):
//   s' = s - (visibility * sun specular + sky specular) / f.
// The result may be negative where the engine's reflection differs from the model: the warp
// carries it as it is, and the target's highlight adds back what was taken. With the shadows
// separated (separate_shadows.wgsl), the shadow layer is the share of the light without the
// highlight that the shadows take away: from F' = F - mask * h and U' = U - h, for highlight h
// through static casters, so that it takes from the warped shading only what the shadows took
// from it. (The sky's reflection is in both colours: no shadow takes it.)
// #import gbuffer
// #import sun_specular
// #import sky_specular
// #import tallies

struct Params {
    extent: vec2u,
    has_material: u32,
    // With a shadow input: the visibility given is the static casters'. Where the shading
    // holds the dynamic casters' shadows too (dynamic objects, or every pixel when the shadows
    // are not separated), the term it holds is that times the mask.
    has_shadow_input: u32,
    // With the shadows separated: static pixels hold the colour without the dynamic shadows,
    // and the shadow layer is made again without the highlight.
    separated: u32,
    // With a sky: its octahedral map's mips (0 without one) and side; this pass also copies
    // the mips side by side into `kept_sky`.
    sky_levels: u32,
    sky_side: u32,
    // Without a sun (a sky alone), `visibility` is not read: nothing is lit by a sun.
    has_sun: u32,
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
// PatchexShadowInput's mask, with `has_shadow_input` (its sanitising is the separation's to
// count), and with `separated` its colours and the layer made from them.
@group(0) @binding(8) var dynamic_mask: texture_2d<f32>;
@group(0) @binding(9) var color: texture_2d<f32>;
@group(0) @binding(10) var color_without_dynamic_shadows: texture_2d<f32>;
@group(0) @binding(11) var shadow_layer: texture_storage_2d<rgba16float, read_write>;
// PatchexSkyLight's map, and the copy of it the target's reflection reads.
@group(0) @binding(12) var sky: texture_2d<f32>;
@group(0) @binding(13) var kept_sky: texture_storage_2d<rgba16float, write>;

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
    let sky_map = SkyMap(params.sky_side, unspecialised(params.sky_levels), false);
    let has_sky = sky_map.levels != 0u;
    // The dispatch covers the frame and the sky's mips side by side, whichever is larger.
    if (has_sky) {
        var level = 0u;
        var offset = 0u;
        while (level + 1u < sky_map.levels && p.x >= offset + mip_side(sky_map, level)) {
            offset += mip_side(sky_map, level);
            level++;
        }
        let texel = vec2u(p.x - offset, p.y);
        if (all(texel < vec2u(mip_side(sky_map, level)))) {
            let radiance = sanitize_input_color(textureLoad(sky, texel, i32(level)).rgb);
            textureStore(kept_sky, p, vec4f(to_half(radiance.value), 1.0));
            if (radiance.changed) {
                atomicAdd(&group_tallies[0u], 1u);
            }
        }
    }
    if (all(p < params.extent)) {
        var seen = Sanitized(vec3f(0.0), false);
        if (unspecialised(params.has_sun) != ABSENT) {
            seen = sanitize_unit(vec3f(textureLoad(visibility, p, 0).r, 0.0, 0.0));
        }
        let packed = textureLoad(source_normal_id, p, 0).r;
        // Static pixels of separated shadows hold the colour without them.
        let separated = unspecialised(params.separated) != ABSENT && object_id(packed) == 0u;
        var lit = seen.value.x;
        if (unspecialised(params.has_shadow_input) != ABSENT && !separated) {
            lit *= sanitize_unit(vec3f(textureLoad(dynamic_mask, p, 0).r, 0.0, 0.0)).value.x;
        }
        textureStore(kept_visibility, p, vec4f(lit, 0.0, 0.0, 1.0));
        let normal = unpack_normal(packed);
        let depth = textureLoad(source_depth, p, 0).r;
        var changed = seen.changed;
        if ((lit > 0.0 || has_sky) && !is_sky(depth) && any(normal != vec3f(0.0))) {
            let has_material = unspecialised(params.has_material);
            let glossy = glossy_material(base_color, material, p, has_material);
            changed = changed || glossy.roughness_changed;
            let ray = params.ray_at_origin + f32(p.x) * params.ray_per_x + f32(p.y) * params.ray_per_y;
            let view = -normalize(ray);
            let sun = Sun(params.sun_direction, params.sun_illuminance);
            var highlight = vec3f(0.0);
            if (lit > 0.0) {
                highlight = lit * sun_specular(sun, normal, view, glossy);
            }
            var reflection = vec3f(0.0);
            if (has_sky) {
                reflection = sky_specular(sky, sky_map, normal, view, glossy);
            }
            let s = textureLoad(shading, p);
            // The factor the colour was divided by: the pixel's modulation, scaled as the
            // divisor in alpha says.
            let factor = pixel_modulation(base_color, material, p, has_material).factor;
            let scale = max(1.0, s.a / largest(factor));
            textureStore(shading, p, vec4f(to_half(s.rgb - (highlight + reflection) / (factor * scale)), s.a));
            if (separated) {
                let mask = sanitize_unit(vec3f(textureLoad(dynamic_mask, p, 0).r, 0.0, 0.0)).value.x;
                let lit_color = sanitize_input_color(textureLoad(color, p, 0).rgb).value;
                let unshadowed = sanitize_input_color(textureLoad(color_without_dynamic_shadows, p, 0).rgb).value;
                let layer = textureLoad(shadow_layer, p);
                let share = share_lost_to_shadows(max(lit_color - mask * highlight - reflection, vec3f(0.0)),
                    max(unshadowed - highlight - reflection, vec3f(0.0)));
                textureStore(shadow_layer, p, vec4f(to_half(share), layer.a));
            }
        }
        if (changed) {
            atomicAdd(&group_tallies[0u], 1u);
        }
    }
    if (close_tallies(lane)) {
        atomicAdd(&counters.sanitized_pixels, atomicLoad(&group_tallies[0u]));
    }
}
