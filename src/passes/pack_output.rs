//! Packs the extrapolated frame into an output format that a shader cannot store
//! (`shaders/pack_output.wgsl`) and copies the packed texels into the engine's image.

use ash::vk;

use crate::shaders::pack_output::{binding, Params};
use crate::vk::image::{ImportedImage, OwnedImage};
use crate::vk::recorder::{Pass, Recorder};

/// How one 32-bit output format lays out a texel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Encoding {
    /// Bits of R, G, B, A (0: dropped).
    pub bits: [u32; 4],
    /// Where each channel's bits start.
    pub shifts: [u32; 4],
    pub srgb: bool,
    /// Unsigned floats with 5 exponent bits instead of UNORM.
    pub unsigned_float: bool,
}

const fn unorm8(shifts: [u32; 4], srgb: bool) -> Encoding {
    Encoding {
        bits: [8; 4],
        shifts,
        srgb,
        unsigned_float: false,
    }
}

const RGBA8: [u32; 4] = [0, 8, 16, 24];
const BGRA8: [u32; 4] = [16, 8, 0, 24];

/// The encoding of each packed output format (`vk::image::PACKED_OUTPUT_FORMATS`).
pub fn encoding(format: vk::Format) -> Option<Encoding> {
    use vk::Format as F;
    Some(match format {
        F::R8G8B8A8_UNORM => unorm8(RGBA8, false),
        F::R8G8B8A8_SRGB => unorm8(RGBA8, true),
        F::B8G8R8A8_UNORM => unorm8(BGRA8, false),
        F::B8G8R8A8_SRGB => unorm8(BGRA8, true),
        F::A2B10G10R10_UNORM_PACK32 => Encoding {
            bits: [10, 10, 10, 2],
            shifts: [0, 10, 20, 30],
            srgb: false,
            unsigned_float: false,
        },
        F::B10G11R11_UFLOAT_PACK32 => Encoding {
            bits: [11, 11, 10, 0],
            shifts: [0, 11, 22, 0],
            srgb: false,
            unsigned_float: true,
        },
        _ => return None,
    })
}

/// The frame to pack, how, the working image its texels go to, and the engine's output they are
/// copied into (in TRANSFER_DST_OPTIMAL while the call's commands run).
pub struct Packing<'a> {
    pub encoding: Encoding,
    pub frame: &'a OwnedImage,
    pub packed: &'a OwnedImage,
    pub output: &'a ImportedImage,
}

pub fn record(rec: &mut Recorder, pass: Pass, extent: vk::Extent2D, packing: &Packing) {
    let Packing {
        encoding,
        frame,
        packed,
        output,
    } = packing;
    let bound = rec.bind(pass, |writes| {
        writes
            .image(binding::FRAME, *frame)
            .image(binding::PACKED, *packed)
    });
    let params = Params {
        bits: encoding.bits,
        shifts: encoding.shifts,
        extent: [extent.width, extent.height],
        srgb: encoding.srgb as u32,
        unsigned_float: encoding.unsigned_float as u32,
    };
    rec.dispatch(&bound, &params, extent);
    rec.copy(packed, output, extent);
}
