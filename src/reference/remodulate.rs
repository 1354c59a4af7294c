//! Mirror of `shaders/remodulate.wgsl`, including the rounding of the RGBA16F output.

use glam::Vec3;

use super::gbuffer::{pixel_modulation, round_vec3_to_f16, sanitize_color};
use super::Image;

/// The output image, and the number of pixels whose inputs or result were sanitised.
/// `shadow_share` is, for a frame with a shadow input, the share of light its shadows take
/// away at the target (`Shadows::change`).
pub fn remodulate(
    shading: &Image,
    shadow_share: Option<&Image>,
    base_color: &Image,
    material: Option<&Image>,
) -> (Image, u32) {
    let mut sanitized = 0;
    let output = Image::from_fn(shading.width, shading.height, 4, |x, y| {
        let (factor, material_changed) = pixel_modulation(base_color, material, x, y);
        let mut shading = Vec3::from_slice(shading.at(x, y));
        if let Some(share) = shadow_share {
            shading *= Vec3::ONE + Vec3::from_slice(share.at(x, y));
        }
        let (color, color_changed) = sanitize_color(shading * factor);
        sanitized += (material_changed || color_changed) as u32;
        round_vec3_to_f16(color).extend(1.0).to_array().to_vec()
    });
    (output, sanitized)
}

/// The warp's own remodulation (`store_pixel` with `remodulate` in warp.wgsl), when nothing runs
/// between the warp and the output: what each pixel fetched (`Warped::fetched`), its share of
/// shading multiplied by the target's modulation (`gbuffer::modulation_image`). Returns the
/// output and the pixels whose material or result was sanitised.
pub fn remodulate_fetched(fetched: &Image, modulation: &Image) -> (Image, u32) {
    let mut sanitized = 0;
    let output = Image::from_fn(fetched.width, fetched.height, 4, |x, y| {
        let (value, share) = (Vec3::from_slice(fetched.at(x, y)), fetched.at(x, y)[3]);
        let (factor, material_changed) = (
            Vec3::from_slice(modulation.at(x, y)),
            modulation.at(x, y)[3] != 0.0,
        );
        let (color, color_changed) = sanitize_color(value * Vec3::ONE.lerp(factor, share));
        sanitized += (material_changed || color_changed) as u32;
        round_vec3_to_f16(color).extend(1.0).to_array().to_vec()
    });
    (output, sanitized)
}
