//! How the harness turns f32 values into the bytes of an image format and back. Every colour
//! format exchanges four values per texel (a format without alpha reads back alpha 1), so a test
//! can hand any of them the same RGBA image.

use ash::vk;
use half::f16;

/// Values per texel exchanged with the harness, and bytes per texel in the image.
pub fn texel_layout(format: vk::Format) -> (usize, usize) {
    use vk::Format as F;
    match format {
        F::R32G32B32A32_SFLOAT => (4, 16),
        F::R16G16B16A16_SFLOAT => (4, 8),
        F::R32G32_SFLOAT => (2, 8),
        F::R16G16_SFLOAT => (2, 4),
        F::R32_SFLOAT | F::D32_SFLOAT => (1, 4),
        F::R8_UINT => (1, 1),
        F::R8G8B8A8_UNORM
        | F::R8G8B8A8_SRGB
        | F::B8G8R8A8_UNORM
        | F::B8G8R8A8_SRGB
        | F::A2B10G10R10_UNORM_PACK32
        | F::B10G11R11_UFLOAT_PACK32 => (4, 4),
        other => panic!("the harness does not handle {other:?}"),
    }
}

/// The sRGB transfer function, as a GPU applies it when it writes an SRGB format.
pub fn srgb_encode(linear: f32) -> f32 {
    let l = linear.clamp(0.0, 1.0);
    if l <= 0.003_130_8 {
        12.92 * l
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    }
}

/// The inverse of [`srgb_encode`], as a GPU applies it when it samples an SRGB format.
pub fn srgb_decode(encoded: f32) -> f32 {
    if encoded <= 0.040_45 {
        encoded / 12.92
    } else {
        ((encoded + 0.055) / 1.055).powf(2.4)
    }
}

fn unorm(value: f32, bits: u32) -> u32 {
    let max = ((1u32 << bits) - 1) as f32;
    (value.clamp(0.0, 1.0) * max).round() as u32
}

fn from_unorm(value: u32, bits: u32) -> f32 {
    value as f32 / ((1u32 << bits) - 1) as f32
}

/// An unsigned float of 5 exponent bits and `mantissa_bits` (6 or 5): a half float with its
/// sign dropped and its mantissa rounded to fewer bits.
fn small_float(value: f32, mantissa_bits: u32) -> u32 {
    let shift = 10 - mantissa_bits;
    let half = f16::from_f32(value.max(0.0)).to_bits() as u32;
    let rounded = (half + (1 << (shift - 1))) >> shift;
    let max = (0x1e << mantissa_bits) | ((1 << mantissa_bits) - 1);
    rounded.min(max)
}

fn from_small_float(bits: u32, mantissa_bits: u32) -> f32 {
    f16::from_bits((bits << (10 - mantissa_bits)) as u16).to_f32()
}

/// `values` (as many per texel as [`texel_layout`] says) as the bytes of `format`.
pub fn encode(format: vk::Format, values: &[f32]) -> Vec<u8> {
    use vk::Format as F;
    let rgba8 = |texel: &[f32], order: [usize; 4], srgb: bool| -> [u8; 4] {
        order.map(|c| {
            let v = if srgb && c < 3 {
                srgb_encode(texel[c])
            } else {
                texel[c]
            };
            unorm(v, 8) as u8
        })
    };
    let per_texel = |pack: &dyn Fn(&[f32]) -> u32| -> Vec<u8> {
        values
            .chunks_exact(4)
            .flat_map(|t| pack(t).to_le_bytes())
            .collect()
    };
    match format {
        F::R8G8B8A8_UNORM | F::R8G8B8A8_SRGB | F::B8G8R8A8_UNORM | F::B8G8R8A8_SRGB => {
            let srgb = matches!(format, F::R8G8B8A8_SRGB | F::B8G8R8A8_SRGB);
            let order = if matches!(format, F::B8G8R8A8_UNORM | F::B8G8R8A8_SRGB) {
                [2, 1, 0, 3]
            } else {
                [0, 1, 2, 3]
            };
            values
                .chunks_exact(4)
                .flat_map(|t| rgba8(t, order, srgb))
                .collect()
        }
        F::A2B10G10R10_UNORM_PACK32 => per_texel(&|t| {
            unorm(t[0], 10) | unorm(t[1], 10) << 10 | unorm(t[2], 10) << 20 | unorm(t[3], 2) << 30
        }),
        F::B10G11R11_UFLOAT_PACK32 => per_texel(&|t| {
            small_float(t[0], 6) | small_float(t[1], 6) << 11 | small_float(t[2], 5) << 22
        }),
        F::R8_UINT => values.iter().map(|v| *v as u8).collect(),
        _ => match texel_layout(format) {
            (channels, bytes) if bytes / channels == 4 => {
                values.iter().flat_map(|v| v.to_ne_bytes()).collect()
            }
            _ => values
                .iter()
                .flat_map(|v| f16::from_f32(*v).to_ne_bytes())
                .collect(),
        },
    }
}

/// The bytes of `format` as values, as many per texel as [`texel_layout`] says.
pub fn decode(format: vk::Format, bytes: &[u8]) -> Vec<f32> {
    use vk::Format as F;
    let words = || {
        bytes
            .chunks_exact(4)
            .map(|b| u32::from_le_bytes(b.try_into().unwrap()))
    };
    match format {
        F::R8G8B8A8_UNORM | F::R8G8B8A8_SRGB | F::B8G8R8A8_UNORM | F::B8G8R8A8_SRGB => {
            let srgb = matches!(format, F::R8G8B8A8_SRGB | F::B8G8R8A8_SRGB);
            let bgra = matches!(format, F::B8G8R8A8_UNORM | F::B8G8R8A8_SRGB);
            bytes
                .chunks_exact(4)
                .flat_map(|texel| {
                    let mut rgba: [f32; 4] =
                        std::array::from_fn(|c| from_unorm(texel[c] as u32, 8));
                    if bgra {
                        rgba.swap(0, 2);
                    }
                    if srgb {
                        for c in &mut rgba[..3] {
                            *c = srgb_decode(*c);
                        }
                    }
                    rgba
                })
                .collect()
        }
        F::A2B10G10R10_UNORM_PACK32 => words()
            .flat_map(|w| {
                [0, 10, 20]
                    .map(|shift| from_unorm(w >> shift & 0x3ff, 10))
                    .into_iter()
                    .chain([from_unorm(w >> 30, 2)])
            })
            .collect(),
        F::B10G11R11_UFLOAT_PACK32 => words()
            .flat_map(|w| {
                [
                    from_small_float(w & 0x7ff, 6),
                    from_small_float(w >> 11 & 0x7ff, 6),
                    from_small_float(w >> 22, 5),
                    1.0,
                ]
            })
            .collect(),
        F::R8_UINT => bytes.iter().map(|b| *b as f32).collect(),
        _ => match texel_layout(format) {
            (channels, bytes_per_texel) if bytes_per_texel / channels == 4 => bytes
                .chunks_exact(4)
                .map(|b| f32::from_ne_bytes(b.try_into().unwrap()))
                .collect(),
            _ => bytes
                .chunks_exact(2)
                .map(|b| f16::from_ne_bytes(b.try_into().unwrap()).to_f32())
                .collect(),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_colour_format_round_trips_within_its_precision() {
        use vk::Format as F;
        let values = [0.0, 0.25, 0.5, 1.0, 0.001, 0.7, 0.33, 0.0];
        for (format, tolerance) in [
            (F::R8G8B8A8_UNORM, 1.0 / 255.0),
            (F::B8G8R8A8_UNORM, 1.0 / 255.0),
            (F::R8G8B8A8_SRGB, 0.01),
            (F::B8G8R8A8_SRGB, 0.01),
            (F::A2B10G10R10_UNORM_PACK32, 1.0 / 1023.0),
            (F::B10G11R11_UFLOAT_PACK32, 0.5f32.powi(6)),
        ] {
            let back = decode(format, &encode(format, &values));
            for (i, (a, b)) in values.iter().zip(&back).enumerate() {
                let alpha = i % 4 == 3;
                if alpha && format == F::B10G11R11_UFLOAT_PACK32 {
                    assert_eq!(*b, 1.0);
                    continue;
                }
                let tolerance = if alpha && format == F::A2B10G10R10_UNORM_PACK32 {
                    1.0 / 6.0
                } else {
                    tolerance
                };
                assert!(
                    (a - b).abs() <= tolerance.max(a * tolerance),
                    "{format:?}: {a} -> {b}"
                );
            }
        }
    }
}
