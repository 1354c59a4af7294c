// Packs the extrapolated frame (RGBA16F) into the 32-bit texel of an output format that a shader
// cannot store: B10G11R11 floats, A2B10G10R10, RGBA8/BGRA8 UNORM or SRGB. The texels are copied
// into the engine's image with vkCmdCopyImage, which moves bits unchanged between formats of one
// size, so this pass alone decides every rounding. Mirrored by src/reference/pack_output.rs.

struct Params {
    // Bits of R, G, B, A in the texel (0: the channel is dropped).
    bits: vec4u,
    // Where each channel's bits start.
    shifts: vec4u,
    extent: vec2u,
    // 1: R, G and B are sRGB-encoded before quantising.
    srgb: u32,
    // 1: the channels are unsigned floats with 5 exponent bits (B10G11R11), not UNORM.
    unsigned_float: u32,
}
var<immediate> params: Params;

@group(0) @binding(0) var frame: texture_2d<f32>;
@group(0) @binding(1) var packed: texture_storage_2d<r32uint, write>;

fn srgb_encode(linear: f32) -> f32 {
    let l = clamp(linear, 0.0, 1.0);
    if (l <= 0.0031308) {
        return 12.92 * l;
    }
    return 1.055 * pow(l, 1.0 / 2.4) - 0.055;
}

// An unsigned float of 5 exponent bits (bias 15) and bits - 5 mantissa bits, rounded to nearest
// (halves up) and clamped to the largest finite value; negatives become 0.
fn to_unsigned_float(value: f32, bits: u32) -> u32 {
    let mantissa_bits = bits - 5u;
    let v = max(value, 0.0);
    let largest = (1u << bits) - 1u - (1u << mantissa_bits);
    if (v < exp2(-14.0)) {
        // Denormal: mantissa / 2^mantissa_bits * 2^-14.
        return u32(floor(v * exp2(f32(14u + mantissa_bits)) + 0.5));
    }
    // The f32's exponent and mantissa, rounded to mantissa_bits (a carry moves the exponent),
    // then rebiased from 127 to 15.
    let shift = 23u - mantissa_bits;
    let rounded = (bitcast<u32>(v) + (1u << (shift - 1u))) >> shift;
    return min(rounded - ((127u - 15u) << mantissa_bits), largest);
}

fn to_unorm(value: f32, bits: u32) -> u32 {
    let levels = f32((1u << bits) - 1u);
    return u32(floor(clamp(value, 0.0, 1.0) * levels + 0.5));
}

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    let p = id.xy;
    if (any(p >= params.extent)) {
        return;
    }
    let colour = textureLoad(frame, p, 0);
    var texel = 0u;
    for (var c = 0u; c < 4u; c++) {
        let bits = params.bits[c];
        if (bits == 0u) {
            continue;
        }
        var value = colour[c];
        if (params.srgb == 1u && c < 3u) {
            value = srgb_encode(value);
        }
        var code: u32;
        if (params.unsigned_float == 1u) {
            code = to_unsigned_float(value, bits);
        } else {
            code = to_unorm(value, bits);
        }
        texel |= code << params.shifts[c];
    }
    textureStore(packed, p, vec4u(texel, 0u, 0u, 0u));
}
