//! Mirror of `shaders/estimate_sun_share.wgsl` and `shaders/place_target_shadows.wgsl`.

use glam::Vec3;

use super::gbuffer::{round_vec3_to_f16, sanitize};
use super::warp::Warped;
use super::{round_to_f16, Image};

/// Fixed-point units per unit of share and darkness in the sums.
const SUN_SHARE_SCALE: f32 = 64.0;
/// Below this darkness a carried texel says too little about the sun's share.
const LOCAL_DARKNESS: f32 = 0.1;

/// The fixed-point sums over frame t's shadow layer, as stored (RGBA16F): share of light lost
/// per channel, then darkness.
pub fn sun_share_sums(shadow_layer: &Image) -> [u32; 4] {
    let fixed =
        |v: f32| (round_to_f16(v).clamp(0.0, 1.0) * SUN_SHARE_SCALE).round_ties_even() as u32;
    let mut sums = [0; 4];
    for texel in shadow_layer.data.chunks_exact(4) {
        for c in 0..3 {
            sums[c] += fixed(-texel[c]);
        }
        sums[3] += fixed(texel[3]);
    }
    sums
}

/// The darkness-weighted mean of the sun's share; zero without any shadow.
fn mean_sun_share(sums: [u32; 4]) -> Vec3 {
    let darkness = sums[3] as f32;
    if darkness < 1.0 {
        return Vec3::ZERO;
    }
    (Vec3::new(sums[0] as f32, sums[1] as f32, sums[2] as f32) / darkness).min(Vec3::ONE)
}

/// The share of light the target's shadows take away, from `carried` (frame t's shadow layer
/// through the frame's warp: its darkness in `divisor`), the engine's `mask` at the target and
/// its object ids (`stencil`), with the pixels whose mask was sanitised.
pub fn place(
    carried: &Warped,
    mask: &Image,
    stencil: Option<&Image>,
    sums: [u32; 4],
) -> (Image, u32) {
    let mean = mean_sun_share(sums);
    let mut sanitized = 0;
    let width = mask.width;
    let share = Image::from_fn(mask.width, mask.height, 4, |x, y| {
        let texel = carried.warped.at(x, y);
        let hole = texel[3] == 0.0;
        let darkness = carried.divisor[x + y * width];
        let sun = if !hole && darkness >= LOCAL_DARKNESS {
            (-Vec3::from_slice(texel) / darkness).clamp(Vec3::ZERO, Vec3::ONE)
        } else {
            mean
        };
        let (visibility, changed) = sanitize(Vec3::new(mask.at(x, y)[0], 0.0, 0.0), 0.0, 1.0);
        sanitized += changed as u32;
        let dynamic = stencil.is_some_and(|ids| ids.at(x, y)[0] != 0.0);
        let lost = if dynamic {
            Vec3::ZERO
        } else {
            -(1.0 - visibility.x) * sun
        };
        round_vec3_to_f16(lost).extend(1.0).to_array().to_vec()
    });
    (share, sanitized)
}
