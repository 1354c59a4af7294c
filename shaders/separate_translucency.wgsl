// With a PatchexTranslucencyInput on frame t: takes what is drawn over the opaque surface apart
// from it, where the mask covers a pixel:
//   colour = layer + (1 - a) * surface
// Given frame t's colour from before its translucency pass, the surface is that colour, and the
// layer is taken apart exactly. Without it, the surface is estimated from the nearby texels the
// mask leaves uncovered that show the same surface (same object, depth and normal), weighted as
// the hole fill weights its texels (surface_match.wgsl) over a wider, sparser window, since a
// puff of smoke covers more than a hole. The surface's shading replaces the covered texel's, so
// the warp carries the surface alone. The layer is what remains of the colour, premultiplied by
// a (held to [0, colour]), kept with a and with the translucency's own motion for
// place_translucency.wgsl. A covered texel with no uncovered one of its surface in reach keeps
// its shading, and its layer is a times its colour.
// Without the colour before the pass, a layer is left in the colour, carried with the surface
// behind it, where that is right already and taking it apart would only add the estimate's
// errors: where it is the same all around a texel (inside a pane of glass or a fog card), since
// nothing in it moves that could show, where its own motion is the surface's to within half a
// pixel a frame, and where it is thin (under a fifth), fainter than the estimate's error. Only
// where the mask changes (smoke, sparks, a pane's edges) and moves otherwise than the surface
// behind it is the layer taken apart.
// Given that colour, only a layer lying on its surface (glass set in a wall, a decal), whose
// motion is the surface's to within a tenth of a pixel, is left: the warp follows its surface's
// geometry, while a separated layer one or two aliased pixels wide would be smeared by the splat.
// #import gbuffer
// #import surface_match
// #import tallies

struct Params {
    extent: vec2u,
    has_material: u32,
    has_motion: u32,
    // Turns the engine's translucency motion vectors into backward motion in pixels.
    motion_scale: vec2f,
    // The same for frame t's geometry motion vectors, when it came with them.
    surface_motion_scale: vec2f,
    has_surface_motion: u32,
    has_opaque: u32,
}
var<immediate> params: Params;

@group(0) @binding(0) var color: texture_2d<f32>;
@group(0) @binding(1) var base_color: texture_2d<f32>;
@group(0) @binding(2) var material: texture_2d<f32>;
@group(0) @binding(3) var mask: texture_2d<f32>;
@group(0) @binding(4) var motion: texture_2d<f32>;
// Frame t's demodulated shading: read at uncovered texels, written at covered ones only.
@group(0) @binding(5) var shading: texture_storage_2d<rgba16float, read_write>;
// The layer over the surface: premultiplied colour, and a.
@group(0) @binding(6) var layer: texture_storage_2d<rgba16float, write>;
// Its own motion in pixels, zero where it has none.
@group(0) @binding(7) var layer_motion: texture_storage_2d<rg16float, write>;
// Frame t's packed G-buffer (pack_gbuffer.wgsl).
@group(0) @binding(8) var source_depth: texture_2d<f32>;
@group(0) @binding(9) var source_normal_id: texture_2d<u32>;
@group(0) @binding(10) var<storage, read_write> counters: SanitizeCounters;
// Frame t's geometry motion vectors: where the surfaces behind the layer move.
@group(0) @binding(11) var surface_motion: texture_2d<f32>;
// Frame t's colour before its translucency pass, when the engine gave it.
@group(0) @binding(12) var opaque_color: texture_2d<f32>;

// The window's radius and tap spacing, in pixels.
const BEHIND_RADIUS: i32 = 48;
const BEHIND_STEP: i32 = 8;
// A texel this far off (surface_match.wgsl) shows another surface, and is not taken: the layer
// keeps every error of the surface behind, so no surface is better than a wrong one.
const BEHIND_MAX_COST: f32 = 9.0;
// Coverage below this is left in the surface's shading: so faint a layer is not worth an
// estimate of the surface that may be off by more than it.
const MIN_COVERAGE: f32 = 0.05;
// ...and below this without the colour before the pass: thin smoke spread wide leaves the
// estimate few uncovered texels, and its error, carried with the layer, lands where the smoke
// goes (chosen on validation among 0.05, 0.2 and 0.5).
const MIN_ESTIMATED_COVERAGE: f32 = 0.2;
// A layer is uniform at a texel where the coverage FLAT_REACH pixels away, in the 8 directions,
// is within FLAT_TOLERANCE of its own (about two steps of an 8-bit mask).
const FLAT_REACH: i32 = 8;
const FLAT_TOLERANCE: f32 = 0.01;
// A layer moving with the surface behind it to within this many pixels a frame is left in the
// colour (chosen on validation among 0.1, 0.25, 0.5 and 1)...
const SAME_MOTION: f32 = 0.5;
// ...and within this many given the colour before the pass (chosen on validation among 0.02,
// 0.1, 0.25 and 0.5; the two smallest tie, and this one is above half floats' rounding of
// motions up to 100 pixels).
const SAME_MOTION_EXACT: f32 = 0.1;

// A setting as this pass branches on it, tied to an image's size so that lavapipe does not
// compile the shader again for each value (include/warp.wgsl `unspecialised`).
fn unspecialised(setting: u32) -> u32 {
    return select(0u, setting, textureDimensions(mask).x != 0u);
}

// The mask, sanitised, and 0 below MIN_COVERAGE.
fn coverage(s: vec2i) -> Sanitized {
    let a = sanitize_unit(vec3f(textureLoad(mask, s, 0).r, 0.0, 0.0));
    return Sanitized(select(vec3f(0.0), a.value, a.value.x >= MIN_COVERAGE), a.changed);
}

// Whether the layer at `p`, of coverage `a`, is the same all around it.
fn uniform_layer(p: vec2i, a: f32) -> bool {
    let last = vec2i(params.extent) - 1;
    for (var i = 0; i < 9; i++) {
        let s = p + FLAT_REACH * vec2i(i % 3 - 1, i / 3 - 1);
        if (any(s < vec2i(0)) || any(s > last)) {
            continue;
        }
        if (abs(coverage(s).value.x - a) > FLAT_TOLERANCE) {
            return false;
        }
    }
    return true;
}

// The shading of the surface behind covered texel `p`: a weighted mean over the uncovered texels
// of its object around it, or vec4(-1) where there is none.
fn shading_behind(p: vec2i) -> vec4f {
    let last = vec2i(params.extent) - 1;
    let depth = textureLoad(source_depth, p, 0).r;
    let packed = textureLoad(source_normal_id, p, 0).r;
    let normal = unpack_normal(packed);
    let id = object_id(packed);
    // The weights are exp(least - cost), rescaled as a cheaper texel appears (fill.wgsl).
    var least = 3.4e38;
    var sum = vec3f(0.0);
    var total = 0.0;
    for (var dy = -BEHIND_RADIUS; dy <= BEHIND_RADIUS; dy += BEHIND_STEP) {
        for (var dx = -BEHIND_RADIUS; dx <= BEHIND_RADIUS; dx += BEHIND_STEP) {
            let offset = vec2i(dx, dy);
            let s = p + offset;
            if (any(s < vec2i(0)) || any(s > last) || coverage(s).value.x > 0.0) {
                continue;
            }
            let s_packed = textureLoad(source_normal_id, s, 0).r;
            if (object_id(s_packed) != id) {
                continue;
            }
            let cost = surface_cost(depth, normal, s, s_packed, offset, BEHIND_RADIUS);
            if (cost > BEHIND_MAX_COST) {
                continue;
            }
            if (cost < least) {
                let rescale = exp(cost - least);
                sum *= rescale;
                total *= rescale;
                least = cost;
            }
            let w = exp(least - cost);
            sum += w * textureLoad(shading, s).rgb;
            total += w;
        }
    }
    if (total == 0.0) {
        return vec4f(-1.0);
    }
    return vec4f(sum / total, 1.0);
}

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u, @builtin(local_invocation_index) lane: u32) {
    open_tallies(lane);
    let p = id.xy;
    if (all(p < params.extent)) {
        // Given frame t's colour before its translucency, the layer is taken apart exactly, so
        // only a layer lying on its surface is left in the colour.
        let exact = unspecialised(params.has_opaque) != ABSENT;
        var a = coverage(vec2i(p));
        if (!exact && (a.value.x < MIN_ESTIMATED_COVERAGE || uniform_layer(vec2i(p), a.value.x))) {
            a.value = vec3f(0.0);
        }
        var changed = a.changed;
        var own = vec2f(0.0);
        if (unspecialised(params.has_motion) != ABSENT) {
            // Kept in half floats, as motion vectors come: what a half cannot hold is no motion.
            let stored = textureLoad(motion, p, 0).xy * params.motion_scale;
            let usable = all(abs(stored) <= vec2f(MAX_HALF));
            own = select(vec2f(0.0), to_half(vec3f(stored, 0.0)).xy, usable);
            changed = changed || (a.value.x > 0.0 && !usable);
            if (unspecialised(params.has_surface_motion) != ABSENT) {
                let surface = textureLoad(surface_motion, p, 0).xy * params.surface_motion_scale;
                if (usable && length(own - surface) <= select(SAME_MOTION, SAME_MOTION_EXACT, exact)) {
                    a.value = vec3f(0.0);
                }
            }
        }
        var over = vec4f(0.0);
        if (a.value.x > 0.0) {
            let c = sanitize_input_color(textureLoad(color, p, 0).rgb);
            changed = changed || c.changed;
            var surface = c.value;
            let m = pixel_modulation(base_color, material, p, unspecialised(params.has_material));
            if (exact) {
                let opaque = sanitize_input_color(textureLoad(opaque_color, p, 0).rgb);
                changed = changed || opaque.changed;
                surface = opaque.value;
                textureStore(shading, p, demodulated(surface, m.factor));
            } else {
                let behind = shading_behind(vec2i(p));
                if (behind.a > 0.0) {
                    surface = min(behind.rgb * m.factor, vec3f(MAX_HALF));
                    textureStore(shading, p, demodulated(surface, m.factor));
                }
            }
            // Light the layer adds, so never below 0, nor above the colour it is part of: an
            // estimate of the surface off by more than that is not carried with the layer.
            let added = clamp(c.value - (1.0 - a.value.x) * surface, vec3f(0.0), c.value);
            over = vec4f(to_half(added), to_half(a.value).x);
        }
        textureStore(layer, p, over);
        textureStore(layer_motion, p, vec4f(select(vec2f(0.0), own, a.value.x > 0.0), 0.0, 0.0));
        if (changed) {
            atomicAdd(&group_tallies[0u], 1u);
        }
    }
    if (close_tallies(lane)) {
        atomicAdd(&counters.sanitized_pixels, atomicLoad(&group_tallies[0u]));
    }
}
