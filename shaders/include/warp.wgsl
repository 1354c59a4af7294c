// What every backward warp shares: its parameters, bindings and hole counters, the target's
// G-buffer read straight from the engine's images, the geometry agreement test, what it fetches
// from frame t (its shading and, with a shadow input, its shadow layer, blended with one set of
// weights), and how a pixel is stored, remodulated when nothing else runs between the warp and
// the output. The entry point is warp_entry.wgsl; fill_holes.wgsl shares the rest. Needs
// gbuffer.wgsl, cameras.wgsl, surface.wgsl, atlas.wgsl and tallies.wgsl.
// src/reference/warp.rs mirrors it.

// Below this total weight a weighted fetch found nothing usable.
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
    occlusion_search_radius: i32,
    // How much of the world-position distance along the target's surface counts: 1 for surface
    // points, which must land on themselves; 0 for shadows, which slide across their receiver
    // and need only land on the same plane.
    in_plane_weight: f32,
    // Radians one pixel spans at the image centre.
    pixel_angle: f32,
    // G-buffer-guided warp: PATCHEX_HOLE_FILL_* (0 uncovered side, 1 nearest texel).
    hole_fill: u32,
    // Not 0: multiply by the target's modulation and write the output (remodulate.wgsl's
    // work, without shadow layers), counting what was sanitised.
    remodulate: u32,
    has_material: u32,
    // Not 0: the shadow layer rides along, warped with the shading's weights into the shadows'
    // share at the target (`store_pixel`).
    carries_layer: u32,
    // Not 0 when that share already holds the layer as its flow moved it, which the carried
    // layer only completes.
    shadow_share: u32,
    // Occlusion-motion-vector warp: not 0 to weigh each texel of the bilinear fetch by its
    // agreement, as the G-buffer warp does. For the shadow layer, which is zero on dynamic
    // objects: a plain blend beside one would thin the shadow on the ground at its feet.
    agreeing_bilinear: u32,
    // G-buffer-guided warp: PATCHEX_RESAMPLE_* (0 Catmull-Rom, 1 bilinear).
    resample: u32,
    // The shadow layer's warp: `motion` is the shadow flow's atlas, and the motion its finest
    // level here, scaled up to the frame (`motion_at`); 0 x 0 for the engine's motion vectors.
    motion_level_offset: vec2u,
    motion_level_size: vec2u,
}
var<immediate> params: Params;

struct WarpCounters {
    hole_pixels: atomic<u32>,
    offscreen_pixels: atomic<u32>,
    // The largest |motion| of a target pixel, in pixels, as f32 bits: non-negative floats
    // order as their bits, so atomicMax finds it.
    largest_motion_bits: atomic<u32>,
    // Target pixels whose depth, normal or motion vector is NaN or infinite.
    invalid_geometry_pixels: atomic<u32>,
    // With `remodulate`: pixels whose material or result was sanitised.
    sanitized_pixels: atomic<u32>,
}

@group(0) @binding(0) var source_shading: texture_2d<f32>;
@group(0) @binding(1) var source_depth: texture_2d<f32>;
@group(0) @binding(2) var source_normal_id: texture_2d<u32>;
// The target's G-buffer, the engine's images.
@group(0) @binding(3) var target_depth: texture_2d<f32>;
@group(0) @binding(4) var target_normal: texture_2d<f32>;
@group(0) @binding(9) var target_stencil: texture_2d<u32>;
// With `remodulate`: the target's material.
@group(0) @binding(10) var base_color: texture_2d<f32>;
@group(0) @binding(11) var material: texture_2d<f32>;
@group(0) @binding(5) var motion: texture_2d<f32>;
@group(0) @binding(6) var warped: texture_storage_2d<rgba16float, write>;
@group(0) @binding(7) var<storage, read_write> counters: WarpCounters;
@group(0) @binding(8) var<uniform> cameras: Cameras;
// With `carries_layer`: frame t's shadow layer, and the shadows' share it is stored into; with
// `shadow_share`, that share as the layer's flow moved it, read back in place.
@group(0) @binding(16) var source_layer: texture_2d<f32>;
@group(0) @binding(17) var warped_layer: texture_storage_2d<rgba16float, write>;
@group(0) @binding(15) var moved_layer: texture_2d<f32>;

// A setting as the warps branch on it. lavapipe (Mesa 22.3) specialises a shader on the push
// constants and uniforms that a branch or loop bound depends on alone and, keeping no cache of
// its specialisations, compiles it again at every dispatch: about 380 ms of LLVM a frame for the
// G-buffer warp at 640x360, hidden only where Mesa's disk cache has seen those exact frames. Tied
// to the source image's size, which the driver cannot inline, a setting no longer qualifies and
// each warp compiles once. For any driver the select always yields `setting`.
fn unspecialised(setting: u32) -> u32 {
    return select(0u, setting, textureDimensions(source_shading).x != 0u);
}

// The motion at target pixel p: the engine's vector, or the shadow flow's.
fn motion_at(p: vec2u) -> vec2f {
    if (unspecialised(params.motion_level_size.x) == 0u) {
        return textureLoad(motion, p, 0).xy;
    }
    return frame_flow(motion, params.motion_level_offset, params.motion_level_size, params.extent, p);
}

// The workgroup's tallies (tallies.wgsl).
const TALLY_HOLES: u32 = 0u;
const TALLY_OFFSCREEN: u32 = 1u;
const TALLY_LARGEST_MOTION: u32 = 2u;
const TALLY_INVALID_GEOMETRY: u32 = 3u;
const TALLY_SANITIZED: u32 = 4u;

// Frame t's geometry is read four texels at a time: a gather fetches as much as a load does.
// The sampler (src/vk/pipeline.rs `gather_sampler`) neither filters nor wraps, so a gather
// returns what four loads clamped to the image would.
@group(0) @binding(18) var geometry_sampler: sampler;

// Frame t's normals and ids (`packed`) and depths at the 2x2 texels from `corner`, each clamped
// to the image, in a gather's order: (0, 1), (1, 1), (1, 0), (0, 0) from the corner.
struct GeometryQuad {
    packed: vec4u,
    depth: vec4f,
}

// Index into a GeometryQuad of the texel at `corner + offset`, offset in {0, 1}^2.
fn quad_index(offset: vec2i) -> i32 {
    return select(3 - offset.x, offset.x, offset.y == 1);
}

fn geometry_quad(corner: vec2i) -> GeometryQuad {
    // The point between the four texels' centres picks them whatever the rounding.
    let at = (vec2f(corner) + 1.0) / vec2f(textureDimensions(source_depth));
    return GeometryQuad(textureGather(0, source_normal_id, geometry_sampler, at),
        textureGather(0, source_depth, geometry_sampler, at));
}

// Whether frame t's texel `s` (normal and id `packed`, depth `depth`) shows the static target
// surface `t` wherever on it: its object, its normal and its plane, as `agreement_of` measures
// them without the distance along it.
fn on_static_surface(t: Surface, s: vec2i, packed: u32, depth: f32) -> bool {
    if (object_id(packed) != t.id) {
        return false;
    }
    if (is_sky(t.depth) || is_sky(depth)) {
        return false;
    }
    let normal_term = (1.0 - dot(t.normal, unpack_normal(packed))) * params.inv_sigma_normal;
    let across = dot(t.normal, source_position(s, depth) - t.position) / t.footprint * params.inv_sigma_position;
    // exp(-x) >= AGREEMENT_THRESHOLD, without the exp.
    return normal_term + across * across <= LN_AGREEMENT_THRESHOLD;
}

// Where target pixel `p` lands in frame t when it follows `motion` (raw engine units).
fn source_point(p: vec2u, motion: vec2f) -> vec2f {
    return vec2f(p) + 0.5 + motion * params.motion_scale + params.jitter_delta;
}

// Written so that a NaN motion vector counts as off-screen.
fn is_offscreen(q: vec2f) -> bool {
    return !(all(q >= vec2f(0.0)) && all(q < vec2f(params.extent)));
}

fn texel(q: vec2f) -> vec2i {
    return clamp(vec2i(floor(q)), vec2i(0), vec2i(params.extent) - 1);
}


// What a warp fetches from frame t and blends with one set of weights, as a matrix's columns:
// the shading (its alpha the divisor, gbuffer.wgsl `demodulated`) and, with `carries_layer`, the
// shadow layer (zero without). Both move with the surfaces, so one warp's weights serve both.
alias Fetched = mat2x4f;

fn carries_layer() -> bool {
    return unspecialised(params.carries_layer) != 0u;
}

fn source_texel(s: vec2i) -> Fetched {
    var layer = vec4f(0.0);
    if (carries_layer()) {
        layer = textureLoad(source_layer, s, 0);
    }
    return Fetched(textureLoad(source_shading, s, 0), layer);
}

// A weighted sum over its total weight. WGSL divides no matrix, and a multiplication by the
// reciprocal would round otherwise than the reference.
fn divided(sum: Fetched, total: f32) -> Fetched {
    return Fetched(sum[0] / total, sum[1] / total);
}

// Frame t's `image` (its shading or its shadow layer) at `q`, bilinear over the texels around it.
fn bilinear(image: texture_2d<f32>, q: vec2f) -> vec4f {
    let corner = vec2i(floor(q - 0.5));
    let f = q - 0.5 - floor(q - 0.5);
    let last = vec2i(params.extent) - 1;
    let s00 = textureLoad(image, clamp(corner, vec2i(0), last), 0);
    let s10 = textureLoad(image, clamp(corner + vec2i(1, 0), vec2i(0), last), 0);
    let s01 = textureLoad(image, clamp(corner + vec2i(0, 1), vec2i(0), last), 0);
    let s11 = textureLoad(image, clamp(corner + vec2i(1, 1), vec2i(0), last), 0);
    return mix(mix(s00, s10, f.x), mix(s01, s11, f.x), f.y);
}

// The fetches whose weights need no G-buffer run once per image, so that a warp without the
// layer pays nothing for it (each is inlined with its image).
fn bilinear_fetch(q: vec2f) -> Fetched {
    var layer = vec4f(0.0);
    if (carries_layer()) {
        layer = bilinear(source_layer, q);
    }
    return Fetched(bilinear(source_shading, q), layer);
}

// q's bilinear footprint in frame t with each texel weighted by its agreement with the target:
// the weighted shading and weight sums, and the best agreement of a texel with a share of it.
struct AgreeingFootprint {
    shading_sum: Fetched,
    weight_sum: f32,
    best_agreement: f32,
    // The least agreement among the four texels: all of them show the target's surface when it
    // reaches AGREEMENT_THRESHOLD.
    least_agreement: f32,
}

fn agreeing_footprint(t: Surface, q: vec2f) -> AgreeingFootprint {
    let corner = vec2i(floor(q - 0.5));
    let f = q - 0.5 - floor(q - 0.5);
    let quad = geometry_quad(corner);
    var sums = AgreeingFootprint(Fetched(), 0.0, 0.0, 1.0);
    for (var i = 0; i < 4; i++) {
        let offset = vec2i(i & 1, i >> 1u);
        let s = clamp(corner + offset, vec2i(0), vec2i(params.extent) - 1);
        let k = quad_index(offset);
        let agreement = agreement_of(t, s, quad.packed[k], quad.depth[k]);
        let bilinear = select(1.0 - f, f, vec2<bool>(offset == vec2i(1)));
        let footprint = bilinear.x * bilinear.y;
        sums.shading_sum += footprint * agreement * source_texel(s);
        sums.weight_sum += footprint * agreement;
        if (footprint > 0.0) {
            sums.best_agreement = max(sums.best_agreement, agreement);
        }
        sums.least_agreement = min(sums.least_agreement, agreement);
    }
    return sums;
}

// The Catmull-Rom weights of four texels in a row, for a point at `f` between the middle two.
fn catmull_rom_weights(f: f32) -> vec4f {
    let f2 = f * f;
    let f3 = f2 * f;
    return vec4f(
        -0.5 * f3 + f2 - 0.5 * f,
        1.5 * f3 - 2.5 * f2 + 1.0,
        -1.5 * f3 + 2.0 * f2 + 0.5 * f,
        0.5 * f3 - 0.5 * f2);
}

// Whether the texels around `q` beyond its four nearest, the 12 that Catmull-Rom adds, show the
// static target surface `t` somewhere on it: same object, normal and plane. They are read as the
// four quads at the 4x4 block's corners, each holding one of the nearest four.
fn surface_around(t: Surface, q: vec2f) -> bool {
    let corner = vec2i(floor(q - 0.5));
    let last = vec2i(params.extent) - 1;
    for (var j = 0; j < 4; j++) {
        // Quads from (-1, -1), (1, -1), (-1, 1) and (1, 1) off the corner.
        let start = corner + 2 * vec2i(j & 1, j >> 1u) - 1;
        let quad = geometry_quad(start);
        for (var i = 0; i < 4; i++) {
            let offset = vec2i(i & 1, i >> 1u);
            let s = start + offset;
            let nearest = all((s == corner) | (s == corner + 1));
            let k = quad_index(offset);
            if (!nearest && !on_static_surface(t, clamp(s, vec2i(0), last), quad.packed[k], quad.depth[k])) {
                return false;
            }
        }
    }
    return true;
}

// Frame t's `image` at `q`, Catmull-Rom over the 4x4 texels around it, held within the range of
// the four nearest so that it cannot ring. Bilinear blurs: a half-texel shift halves detail at
// the finest scale, and a moving camera shifts every frame.
fn catmull_rom(image: texture_2d<f32>, q: vec2f) -> vec4f {
    let corner = vec2i(floor(q - 0.5));
    let f = q - 0.5 - floor(q - 0.5);
    let wx = catmull_rom_weights(f.x);
    let wy = catmull_rom_weights(f.y);
    let last = vec2i(params.extent) - 1;
    var sum = vec4f(0.0);
    var low = vec4f(3.4e38);
    var high = vec4f(-3.4e38);
    for (var j = 0; j < 4; j++) {
        for (var i = 0; i < 4; i++) {
            let s = textureLoad(image, clamp(corner + vec2i(i - 1, j - 1), vec2i(0), last), 0);
            sum += wx[i] * wy[j] * s;
            if ((i == 1 || i == 2) && (j == 1 || j == 2)) {
                low = min(low, s);
                high = max(high, s);
            }
        }
    }
    return clamp(sum, low, high);
}

fn catmull_rom_fetch(q: vec2f) -> Fetched {
    var layer = vec4f(0.0);
    if (carries_layer()) {
        layer = catmull_rom(source_layer, q);
    }
    return Fetched(catmull_rom(source_shading, q), layer);
}

struct WarpedPixel {
    fetched: Fetched,
    hole: bool,
    offscreen: bool,
    // Left to the hole fill (fill_holes.wgsl), which writes the pixel.
    deferred: bool,
}

// The holes a G-buffer warp leaves to the fill: their count, and the fill's indirect dispatch
// (one 64-wide workgroup per 64 holes; y and z are 1, written by the host before the warp).
struct DeferredHoles {
    count: atomic<u32>,
    groups: atomic<u32>,
    groups_y: u32,
    groups_z: u32,
}

// `value` with the hole flag in its alpha (`frame_alpha`), rounded to half floats here, as the
// colour is, whatever the driver's conversion does.
fn with_hole_flag(value: vec4f, hole: bool) -> vec4f {
    return vec4f(to_half(value.rgb), to_half(vec3f(frame_alpha(value.a, hole))).x);
}

// Writes pixel p's warped shading with its hole flag and divisor (`frame_alpha`), remodulated
// when the warp remodulates; and with `carries_layer` the shadows' share at the target.
fn store_pixel(p: vec2u, fetched: Fetched, hole: bool) {
    let shading = fetched[0];
    var color = with_hole_flag(shading, hole);
    if (unspecialised(params.remodulate) != 0u) {
        let m = pixel_modulation(base_color, material, p, unspecialised(params.has_material));
        let factor = remodulation(m.factor, shading.rgb, shading.a);
        let remodulated = sanitize_color(shading.rgb * factor);
        color = vec4f(to_half(remodulated.value), 1.0);
        if (m.changed || remodulated.changed) {
            atomicAdd(&group_tallies[TALLY_SANITIZED], 1u);
        }
    }
    textureStore(warped, p, color);
    if (carries_layer()) {
        // The layer's alpha is its darkness, flagged as the shading's divisor is.
        var share = with_hole_flag(fetched[1], hole);
        if (unspecialised(params.shadow_share) != 0u) {
            // The layer as its flow moved it where that found a receiver (not a hole), as this
            // warp carried it with the surfaces elsewhere.
            let moved = textureLoad(moved_layer, p, 0);
            let found = select(1.0, 0.0, is_hole(moved.a));
            share = vec4f(to_half(mix(share.rgb, moved.rgb, found)), found);
        }
        textureStore(warped_layer, p, share);
    }
}
