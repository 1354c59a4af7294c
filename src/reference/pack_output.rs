//! Mirror of `shaders/pack_output.wgsl`: the extrapolated frame as the 32-bit texels of an
//! output format a shader cannot store.

use super::Image;
use crate::passes::pack_output::Encoding;

fn srgb_encode(linear: f32) -> f32 {
    let l = linear.clamp(0.0, 1.0);
    if l <= 0.003_130_8 {
        12.92 * l
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    }
}

fn unsigned_float(value: f32, bits: u32) -> u32 {
    let mantissa_bits = bits - 5;
    let v = value.max(0.0);
    let largest = (1 << bits) - 1 - (1 << mantissa_bits);
    if v < 2f32.powi(-14) {
        return (v * 2f32.powi((14 + mantissa_bits) as i32) + 0.5).floor() as u32;
    }
    let shift = 23 - mantissa_bits;
    let rounded = (v.to_bits() + (1 << (shift - 1))) >> shift;
    (rounded - ((127 - 15) << mantissa_bits)).min(largest)
}

fn unorm(value: f32, bits: u32) -> u32 {
    let levels = ((1u32 << bits) - 1) as f32;
    (value.clamp(0.0, 1.0) * levels + 0.5).floor() as u32
}

/// Every pixel of `frame` (RGBA, values already rounded to RGBA16F) packed per `encoding`.
pub fn pack_output(frame: &Image, encoding: &Encoding) -> Vec<u32> {
    frame
        .data
        .chunks_exact(4)
        .map(|colour| {
            (0..4)
                .filter(|&c| encoding.bits[c] > 0)
                .map(|c| {
                    let bits = encoding.bits[c];
                    let value = if encoding.srgb && c < 3 {
                        srgb_encode(colour[c])
                    } else {
                        colour[c]
                    };
                    let code = if encoding.unsigned_float {
                        unsigned_float(value, bits)
                    } else {
                        unorm(value, bits)
                    };
                    code << encoding.shifts[c]
                })
                .fold(0, |texel, bits| texel | bits)
        })
        .collect()
}
