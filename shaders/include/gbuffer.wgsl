// G-buffer conventions shared by every pass. src/reference/gbuffer.rs mirrors this file.

// Floor of the modulation factor, by which remodulation multiplies.
const MIN_MODULATION: f32 = 0.01;

// Below this modulation factor in its largest channel a surface is too dark to trust its colour
// as albedo times light (black and emissive materials): remodulation never makes what was
// warped from it brighter than its colour (`remodulation`).
const DARK_MODULATION: f32 = 0.05;

// Linear depth stored for pixels that hit no geometry (sky, far plane, infinite far).
const SKY_DEPTH: f32 = 1e30;

// Largest value of the RGBA16F output, and so the largest colour worth keeping.
const MAX_HALF: f32 = 65504.0;
// Below this a value rounds to at most MAX_HALF when stored as a half float (to nearest), so it
// is representable, not out of range.
const HALF_ROUNDS_TO_MAX: f32 = 65519.0;

// An instant's packed G-buffer is two R32 images: linear depth (R32F), and the unit normal with
// the object id (R32UI): the normal octahedral in two 12-bit codes, the id in the low 8 bits
// (ids come from 8-bit stencils). World positions are rebuilt from depth and the camera
// (`Cameras` in warp.wgsl). Code 0 on both axes means no normal (a zero or unusable one).
const OCTAHEDRAL_SCALE: f32 = 2047.0;
const OCTAHEDRAL_CENTRE: f32 = 2048.0;

fn sign_not_zero(v: vec2f) -> vec2f {
    return select(vec2f(-1.0), vec2f(1.0), v >= vec2f(0.0));
}

fn pack_normal_id(n: vec3f, object_id: u32) -> u32 {
    if (all(n == vec3f(0.0))) {
        return object_id & 0xffu;
    }
    var e = n.xy / (abs(n.x) + abs(n.y) + abs(n.z));
    if (n.z < 0.0) {
        e = (1.0 - abs(e.yx)) * sign_not_zero(e);
    }
    let code = vec2u(round(clamp(e, vec2f(-1.0), vec2f(1.0)) * OCTAHEDRAL_SCALE + OCTAHEDRAL_CENTRE));
    return (code.x << 20u) | (code.y << 8u) | (object_id & 0xffu);
}

fn unpack_normal(packed: u32) -> vec3f {
    let code = vec2u(packed >> 20u, (packed >> 8u) & 0xfffu);
    if (all(code == vec2u(0u))) {
        return vec3f(0.0);
    }
    let e = (vec2f(code) - OCTAHEDRAL_CENTRE) / OCTAHEDRAL_SCALE;
    var n = vec3f(e, 1.0 - abs(e.x) - abs(e.y));
    if (n.z < 0.0) {
        n = vec3f((1.0 - abs(n.yx)) * sign_not_zero(n.xy), n.z);
    }
    return normalize(n);
}

fn object_id(packed: u32) -> u32 {
    return packed & 0xffu;
}

// The object id at `p` of an engine's stencil, as `pack_normal_id` keeps it; 0 (static geometry)
// without a stencil, when a placeholder is bound. The passes that read frame t's ids alone read
// them here, without waiting for pack_gbuffer.wgsl. A select, not a branch on the setting.
fn stencil_object_id(stencil: texture_2d<u32>, p: vec2u, has_stencil: u32) -> u32 {
    return select(0u, textureLoad(stencil, p, 0).r & 0xffu, has_stencil != ABSENT);
}

// Values of `depth_convention` (PATCHEX_DEPTH_*) and `normal_encoding` (PATCHEX_NORMAL_*).
const DEPTH_LINEAR_VIEW_Z: u32 = 0u;
const DEPTH_HARDWARE_REVERSED: u32 = 2u;
const NORMAL_UNORM: u32 = 1u;

// Linear depth of an engine's stored depth at pixel `p`: a linear view z as it is, hardware depth
// z through the projection: 1 / dot(curve, (z, 1, x, y)) (`Camera::depth_curve`), exact for any
// perspective projection. Beyond the far plane, or at an infinite one, it is sky.
fn linear_depth(stored: f32, p: vec2u, curve: vec4f, far: f32, convention: u32) -> f32 {
    if (convention == DEPTH_LINEAR_VIEW_Z) {
        return select(stored, SKY_DEPTH, stored >= far);
    }
    let at_far = select(stored >= 1.0, stored <= 0.0, convention == DEPTH_HARDWARE_REVERSED);
    let inverse = dot(curve, vec4f(stored, 1.0, vec2f(p)));
    if (at_far || inverse == 0.0) {
        return SKY_DEPTH;
    }
    return 1.0 / inverse;
}

// Whether a stored depth lies in its convention's range: a positive linear depth (+infinity is
// sky), or hardware depth in [0, 1]. NaN fails both.
fn depth_in_range(stored: f32, convention: u32) -> bool {
    if (convention == DEPTH_LINEAR_VIEW_Z) {
        return stored > 0.0;
    }
    return stored >= 0.0 && stored <= 1.0;
}

// Whether an engine pixel's geometry can be used: its depth in range and its normal finite.
fn valid_geometry(stored_depth: f32, stored_normal: vec3f, convention: u32) -> bool {
    return depth_in_range(stored_depth, convention) && is_finite(vec4f(stored_normal, 0.0));
}

// An engine's stored normal as a unit vector; zero, NaN and infinite ones become no normal.
fn unit_normal(stored: vec3f, encoding: u32) -> vec3f {
    var n = stored;
    if (encoding == NORMAL_UNORM) {
        n = n * 2.0 - 1.0;
    }
    let n_length = length(n);
    return select(vec3f(0.0), n / n_length, n_length > 1e-6 && n_length <= MAX_FINITE);
}

// Values of `has_material` and `has_stencil`.
const ABSENT: u32 = 0u;

// Unreal's split of base colour into diffuse and specular colour, summed:
// BaseColor * (1 - Metallic) + lerp(0.08 * Specular, BaseColor, Metallic)
//   = BaseColor + 0.08 * Specular * (1 - Metallic).
fn modulation(base_color: vec3f, metallic: f32, specular: f32) -> vec3f {
    return max(base_color + vec3f(0.08 * specular * (1.0 - metallic)), vec3f(MIN_MODULATION));
}

// Metallic and specular of pixel `p` from the material image (R metallic, G specular, as in
// Unreal's GBufferB), or Unreal's defaults (0, 0.5) when the engine gave no material image.
fn metallic_specular(material: texture_2d<f32>, p: vec2u, has_material: u32) -> vec2f {
    if (has_material == ABSENT) {
        return vec2f(0.0, 0.5);
    }
    return textureLoad(material, p, 0).rg;
}

// Metallic and roughness (B, as in Unreal's GBufferB) of pixel `p` for the networks, in [0, 1],
// or (0, 0.5) without a material image. Counting what was sanitised is remodulation's job.
fn metallic_roughness(material: texture_2d<f32>, p: vec2u, has_material: u32) -> vec2f {
    if (has_material == ABSENT) {
        return vec2f(0.0, 0.5);
    }
    return sanitize_unit(vec3f(textureLoad(material, p, 0).rb, 0.0)).value.xy;
}

// The largest finite f32.
const MAX_FINITE: f32 = 3.40282347e38;

// False for NaN (which fails every comparison) and for infinities.
fn is_finite(v: vec4f) -> bool {
    return all(abs(v) <= vec4f(MAX_FINITE));
}

fn is_sky(linear_depth: f32) -> bool {
    return linear_depth >= 0.5 * SKY_DEPTH;
}

// Inputs an engine may get wrong: NaN, infinities, negative colours, colours beyond what the
// output can hold, material values outside [0, 1]. Each is replaced by the nearest usable value
// (NaN by 0) and the pixel counted, so the output stays finite and the statistics say what was
// changed. src/reference/gbuffer.rs mirrors these rules.
struct Sanitized {
    value: vec3f,
    changed: bool,
}

// Written so that NaN fails every comparison and takes 0.
fn sanitize(v: vec3f, low: f32, high: f32) -> Sanitized {
    let usable = v >= vec3f(low) & v <= vec3f(high);
    let clamped = select(vec3f(0.0), clamp(v, vec3f(low), vec3f(high)), v == v);
    return Sanitized(select(clamped, v, usable), !all(usable));
}

// A colour the pipeline computed, held to what the RGBA16F output can store.
fn sanitize_color(v: vec3f) -> Sanitized {
    return sanitize(v, -HALF_ROUNDS_TO_MAX, HALF_ROUNDS_TO_MAX);
}

// An engine's colour input: light, so never negative, and within the half-float range.
fn sanitize_input_color(v: vec3f) -> Sanitized {
    return sanitize(v, 0.0, MAX_HALF);
}

fn sanitize_unit(v: vec3f) -> Sanitized {
    return sanitize(v, 0.0, 1.0);
}

// The nearest half float to `v` (ties to even; `v` within the half range), so that storing it
// into an RGBA16F image is exact whatever rounding the driver's conversion uses, and the
// reference (`round_to_f16`) gets the same value. Drops the 13 mantissa bits a half lacks.
fn to_half(v: vec3f) -> vec3f {
    let bits = bitcast<vec3u>(v);
    let rounded = bits + vec3u(0xfffu) + ((bits >> vec3u(13u)) & vec3u(1u));
    return bitcast<vec3f>(rounded & vec3u(0xffffe000u));
}

// A source pixel as the RGBA16F shading image holds it: its colour over its modulation factor
// (the shading), and in alpha the largest channel of what it was divided by (its divisor).
// Where the shading would pass FITTED_SHADING (bright HDR over a dark albedo), the factor is
// scaled up until it fits, and the divisor with it. The warps carry alpha along with the
// shading, and remodulation reads it (`remodulation`). `color` is a sanitised input, in
// [0, MAX_HALF].
fn demodulated(color: vec3f, factor: vec3f) -> vec4f {
    let shading = color / factor;
    let scale = max(1.0, largest(shading) / FITTED_SHADING);
    return vec4f(to_half(min(shading / scale, vec3f(FITTED_SHADING))), largest(factor) * scale);
}

// Below this unshadowed colour a receiver has no light to lose.
const BLACK: f32 = 1e-6;

// The shadow layer (separate_shadows.wgsl): the share of the unshadowed light U that the
// dynamic shadows take away from F, per channel, in [-1, 0].
fn share_lost_to_shadows(lit: vec3f, unshadowed: vec3f) -> vec3f {
    let lost = min(lit, unshadowed) - unshadowed;
    return select(vec3f(0.0), lost / unshadowed, unshadowed > vec3f(BLACK));
}

// The largest of the three channels.
fn largest(v: vec3f) -> f32 {
    return max(v.r, max(v.g, v.b));
}

// The largest shading stored: below the half-float limit by more than a half-float rounding of
// the divisor can add back, so that remodulating scaled shading gives back at most 65504.
const FITTED_SHADING: f32 = 64000.0;

// What remodulation multiplies warped shading by: the target's modulation factor `target_factor`, so
// that texture detail comes from the target's G-buffer, except where the warped value's divisor
// (`divisor`, what frame t's colour was divided by, gathered as the shading was) says the
// shading cannot be trusted to carry light:
// - from a source too dark (DARK_MODULATION), the result is never brighter than the colour
//   that source had: a black pixel in frame t under a lit one at the target is not brightened;
// - from shading at FITTED_SHADING, whose divisor was scaled up to fit (see `demodulated`),
//   the factor is scaled up as the divisor was, so bright HDR colour comes back unchanged. The
//   scaling stops at the half-float limit: it rebuilds a colour that was within it, so what
//   passes the limit is the divisor's own rounding, not light.
fn remodulation(target_factor: vec3f, shading: vec3f, divisor: f32) -> vec3f {
    var factor = target_factor;
    if (divisor < DARK_MODULATION) {
        factor = min(factor, vec3f(divisor));
    }
    let brightest = largest(shading);
    if (brightest >= SATURATED_SHADING) {
        let target_max = largest(target_factor);
        let scale = min(divisor / target_max, MAX_HALF / (brightest * target_max));
        factor = target_factor * max(1.0, scale);
    }
    return factor;
}

// Shading within a half-float step of FITTED_SHADING was scaled to fit (`demodulated`).
const SATURATED_SHADING: f32 = 63968.0;

// Between the warp and remodulation, the frame's alpha says whether a pixel is a hole and what
// its value's divisor is (`demodulated`): the divisor (at least MIN_MODULATION) where the warp
// found the pixel's source, and -1 - divisor in a hole.
fn frame_alpha(divisor: f32, hole: bool) -> f32 {
    return select(divisor, -1.0 - divisor, hole);
}

fn is_hole(frame_alpha: f32) -> bool {
    return frame_alpha < -0.5;
}

fn frame_divisor(frame_alpha: f32) -> f32 {
    return select(frame_alpha, -1.0 - frame_alpha, is_hole(frame_alpha));
}

// A pixel's modulation factor from its (sanitised) base colour and material.
struct Modulation {
    factor: vec3f,
    changed: bool,
}

fn pixel_modulation(base_color: texture_2d<f32>, material: texture_2d<f32>, p: vec2u, has_material: u32) -> Modulation {
    let base = sanitize_unit(textureLoad(base_color, p, 0).rgb);
    let ms = sanitize_unit(vec3f(metallic_specular(material, p, has_material), 0.0));
    return Modulation(modulation(base.value, ms.value.x, ms.value.y), base.changed || ms.changed);
}

struct SanitizeCounters {
    sanitized_pixels: atomic<u32>,
}
