// With a PatchexTranslucencyInput on frame t: blends frame t's translucency layer
// (separate_translucency.wgsl) over the extrapolated frame, moved to the target instant:
//   c' = max(layer.rgb + (1 - layer.a) * c, 0)
// The layer is read where its content at the target was in frame t: with its own motion, around
// the point x with x = p + alpha * motion(x) (constant velocity), found by two steps from where
// the surface behind p was; without, where the target's motion vectors say that surface was.
// Each step reads the motion of the most covered texel around x, so that the edge of a puff
// moving ahead of its texels still finds them; with none around, x stays where the surface was.
// With its own motion, the 3x3 texels around x are splatted forward: each moves by its own
// motion and adds itself to the pixels its centre lands between, with bilinear weights, so that
// a puff keeps its light where its motion stretches or squeezes it, and particles moving apart
// stay apart. Where splats pile up beyond full cover, they are scaled back to it. Where they
// leave a static surface partly uncovered, the rest comes with the surface: inside the layer,
// the layer carried with it, since one motion per pixel cannot say how layers drawn over one
// another move (a pane of glass with smoke drifting behind it takes their mean) and the parts of
// one layer moving apart would open a seam of bare surface between them; where a moving object
// covered the surface in frame t, hiding what lay over it, the layer spread there as the fill
// spreads the shading. Without its own motion, the layer is read bilinear at x, and where frame
// t did not see the target's surface (a disocclusion, which the warp fills from the uncovered
// side), what lay over it was hidden too: the layer is spread there as the fill spreads the
// shading, from the texels whose surface matches.
// Either way, a dynamic object takes the layer where frame t's layer lay over the texel it showed,
// or where frame t showed the object itself under the layer around that texel: there the layer
// lay in front of it, and covers its edges as they move. Elsewhere the layer beside the object
// lay behind it (no input gives the layer's depth), and must not cover it.
// #import gbuffer
// #import cameras
// #import surface
// #import surface_match
// #import fill
// #import tallies

struct Params {
    extent: vec2u,
    // Turns the engine's target motion vectors into backward motion in pixels.
    motion_scale: vec2f,
    // Target jitter minus frame t's jitter, in pixels.
    jitter_delta: vec2f,
    // The target's place between frame t and frame t+1.
    alpha: f32,
    has_motion: u32,
    // The call's warp settings, for its agreement test (include/surface.wgsl).
    inv_sigma_depth: f32,
    inv_sigma_normal: f32,
    inv_sigma_position: f32,
    in_plane_weight: f32,
    pixel_angle: f32,
}
var<immediate> params: Params;

@group(0) @binding(0) var frame: texture_storage_2d<rgba16float, read_write>;
@group(0) @binding(1) var target_motion: texture_2d<f32>;
@group(0) @binding(2) var layer: texture_2d<f32>;
@group(0) @binding(3) var layer_motion: texture_2d<f32>;
@group(0) @binding(4) var<storage, read_write> counters: SanitizeCounters;
@group(0) @binding(5) var target_depth: texture_2d<f32>;
@group(0) @binding(6) var target_normal: texture_2d<f32>;
@group(0) @binding(7) var target_stencil: texture_2d<u32>;
// Frame t's packed G-buffer (pack_gbuffer.wgsl), which says which texels show the target's
// surface.
@group(0) @binding(8) var source_depth: texture_2d<f32>;
@group(0) @binding(9) var source_normal_id: texture_2d<u32>;
@group(0) @binding(10) var<uniform> cameras: Cameras;

// Texels apart of the 3x3 taps the motion is looked for in.
const MOTION_SEARCH_STEP: i32 = 2;

fn unspecialised(setting: u32) -> u32 {
    return select(0u, setting, textureDimensions(layer).x != 0u);
}

fn clamped(s: vec2i) -> vec2i {
    return clamp(s, vec2i(0), vec2i(params.extent) - 1);
}

// The next guess after x: where the motion of the most covered of the 3x3 texels around x
// leads from p, or x itself where none is covered.
fn step_from(x: vec2f, centre: vec2f) -> vec2f {
    let around = vec2i(floor(clamp(x, vec2f(0.0), vec2f(params.extent))));
    var best = 0.0;
    var found = x;
    for (var i = 0; i < 9; i++) {
        let s = clamped(around + MOTION_SEARCH_STEP * vec2i(i % 3 - 1, i / 3 - 1));
        let a = textureLoad(layer, s, 0).a;
        if (a > best) {
            best = a;
            found = centre + params.alpha * textureLoad(layer_motion, s, 0).xy;
        }
    }
    return found;
}

// What the fill spreads (fill.wgsl): the layer.
alias FillValue = vec4f;

fn fill_value(s: vec2i) -> vec4f {
    return textureLoad(layer, s, 0);
}

// Whether frame t saw target surface `t` at one of the 3x3 texels around q.
fn seen_around(t: Surface, q: vec2f) -> bool {
    let centre = clamped(vec2i(floor(q)));
    var seen = false;
    for (var i = 0; i < 9; i++) {
        let s = clamped(centre + vec2i(i % 3 - 1, i / 3 - 1));
        seen = seen || agreement_at(t, s) >= AGREEMENT_THRESHOLD;
    }
    return seen;
}

// The layer at x, bilinear (it is premultiplied); nothing off screen.
fn layer_at(x: vec2f) -> vec4f {
    if (any(x < vec2f(0.0)) || any(x > vec2f(params.extent))) {
        return vec4f(0.0);
    }
    let corner = vec2i(floor(x - 0.5));
    let f = x - 0.5 - floor(x - 0.5);
    let l00 = textureLoad(layer, clamped(corner), 0);
    let l10 = textureLoad(layer, clamped(corner + vec2i(1, 0)), 0);
    let l01 = textureLoad(layer, clamped(corner + vec2i(0, 1)), 0);
    let l11 = textureLoad(layer, clamped(corner + vec2i(1, 1)), 0);
    return mix(mix(l00, l10, f.x), mix(l01, l11, f.x), f.y);
}

// A point is inside the layer where the layer covers it and the texels this many pixels away in
// the 8 directions (chosen on validation among 2, 4 and 8; 2 and 4 tie): a spark or a puff's
// edge moving away leaves its place bare.
const GAP_REACH: i32 = 4;

// Whether q lies inside frame t's layer, not at an edge of it.
fn inside_layer(q: vec2f) -> bool {
    let centre = vec2i(floor(q));
    for (var i = 0; i < 9; i++) {
        let s = centre + GAP_REACH * vec2i(i % 3 - 1, i / 3 - 1);
        if (any(s < vec2i(0)) || any(s >= vec2i(params.extent)) || textureLoad(layer, s, 0).a <= 0.0) {
            return false;
        }
    }
    return true;
}

// The layer that comes with the target's static surface `t`, which lay at `q` in frame t, where
// the splat leaves it partly uncovered: spread from around where a moving object covered it in
// frame t, read at q inside the layer, none at the layer's edges.
fn layer_with_surface(q: vec2f, t: Surface) -> vec4f {
    let under = clamped(vec2i(floor(q)));
    if (object_id(textureLoad(source_normal_id, under, 0).r) != 0u) {
        return fill_hole(q, t);
    }
    return select(vec4f(0.0), layer_at(q), inside_layer(q));
}

// Whether the dynamic object `id`, which frame t showed at x, takes the layer (see the top).
// Its own texels are looked for among the 3x3 around x (5x5 and 9x9 tie on validation).
fn object_takes_layer(x: vec2f, id: u32) -> bool {
    let under = clamped(vec2i(floor(x)));
    if (textureLoad(layer, under, 0).a > 0.0) {
        return true;
    }
    if (layer_at(x).a <= 0.0) {
        return false;
    }
    var behind_layer = false;
    for (var i = 0; i < 9; i++) {
        let s = clamped(under + vec2i(i % 3 - 1, i / 3 - 1));
        let own = object_id(textureLoad(source_normal_id, s, 0).r) == id;
        behind_layer = behind_layer || (own && textureLoad(layer, s, 0).a > 0.0);
    }
    return behind_layer;
}

// A splat's premultiplied sum, and the share of the pixel the covered texels landing on it fill.
struct Splat {
    sum: vec4f,
    weight: f32,
}

// The layer's texels around x, moved to the target instant by their own motion, splatted onto
// the pixel centred at `centre`.
fn layer_splatted(x: vec2f, centre: vec2f) -> Splat {
    let around = vec2i(floor(clamp(x, vec2f(-1.0), vec2f(params.extent) + 1.0)));
    var sum = vec4f(0.0);
    var weight = 0.0;
    for (var i = 0; i < 9; i++) {
        let s = around + vec2i(i % 3 - 1, i / 3 - 1);
        if (any(s < vec2i(0)) || any(s >= vec2i(params.extent))) {
            continue;
        }
        let moved = vec2f(s) + 0.5 - params.alpha * textureLoad(layer_motion, s, 0).xy;
        let w = max(vec2f(1.0) - abs(moved - centre), vec2f(0.0));
        let l = textureLoad(layer, s, 0);
        sum += (w.x * w.y) * l;
        weight += select(0.0, w.x * w.y, l.a > 0.0);
    }
    return Splat(sum, weight);
}

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u, @builtin(local_invocation_index) lane: u32) {
    open_tallies(lane);
    let p = id.xy;
    if (all(p < params.extent)) {
        let centre = vec2f(p) + 0.5 + params.jitter_delta;
        var x = centre + textureLoad(target_motion, p, 0).xy * params.motion_scale;
        // Non-finite target motion reads no layer (the warp counts it).
        let finite = all(abs(x) <= vec2f(MAX_FINITE));
        var over = vec4f(0.0);
        let t = target_surface(p);
        let takes_layer = finite && (t.id == 0u || object_takes_layer(x, t.id));
        if (takes_layer && unspecialised(params.has_motion) != ABSENT) {
            let surface_point = x;
            for (var step = 0; step < 2; step++) {
                x = step_from(x, centre);
            }
            let splat = layer_splatted(x, centre);
            over = splat.sum;
            if (splat.weight < 1.0 && t.id == 0u) {
                over += (1.0 - splat.weight) * layer_with_surface(surface_point, t);
            }
            over /= max(1.0, over.a);
        } else if (finite && t.valid && !seen_around(t, clamp(x, vec2f(0.0), vec2f(params.extent)))) {
            over = fill_hole(x, t);
        } else if (takes_layer) {
            over = layer_at(x);
        }
        if (over.a > 0.0) {
            let c = textureLoad(frame, p);
            let blended = sanitize_color(max(over.rgb + (1.0 - over.a) * c.rgb, vec3f(0.0)));
            textureStore(frame, p, vec4f(to_half(blended.value), c.a));
            if (blended.changed) {
                atomicAdd(&group_tallies[0u], 1u);
            }
        }
    }
    if (close_tallies(lane)) {
        atomicAdd(&counters.sanitized_pixels, atomicLoad(&group_tallies[0u]));
    }
}
