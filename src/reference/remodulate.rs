//! Mirror of `shaders/remodulate.wgsl`, including the rounding of the RGBA16F output.

use glam::Vec3;

use super::gbuffer::{pixel_modulation, remodulation, round_vec3_to_f16, sanitize_color};
use super::Image;

/// The output image, and the number of pixels whose inputs or result were sanitised.
/// `divisor` is each pixel's divisor (`Warped::divisor`), which `remodulation` reads.
/// `shadow_share` is, for a frame with a shadow input, the share of light its shadows take away
/// at the target (`Shadows::change`).
pub fn remodulate(
    shading: &Image,
    divisor: &[f32],
    shadow_share: Option<&Image>,
    base_color: &Image,
    material: Option<&Image>,
) -> (Image, u32) {
    let mut sanitized = 0;
    let width = shading.width;
    let output = Image::from_fn(shading.width, shading.height, 4, |x, y| {
        let (factor, material_changed) = pixel_modulation(base_color, material, x, y);
        let warped = Vec3::from_slice(shading.at(x, y));
        let factor = remodulation(factor, warped, divisor[x + y * width]);
        let lit = match shadow_share {
            Some(share) => warped * (Vec3::ONE + Vec3::from_slice(share.at(x, y))),
            None => warped,
        };
        let (color, color_changed) = sanitize_color(lit * factor);
        sanitized += (material_changed || color_changed) as u32;
        round_vec3_to_f16(color).extend(1.0).to_array().to_vec()
    });
    (output, sanitized)
}
