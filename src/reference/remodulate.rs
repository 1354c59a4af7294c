//! Mirror of `shaders/remodulate.wgsl`, including the rounding of the RGBA16F output.

use glam::Vec3;

use super::gbuffer::{pixel_modulation, round_vec3_to_f16, sanitize_color};
use super::Image;

/// The output image, and the number of pixels whose inputs or result were sanitised.
/// `shading_share` is each pixel's share of shading (`Warped::shading_share`); the rest, colour
/// frame t kept as colour, is not multiplied. `shadow_share` is, for a frame with a shadow
/// input, the share of light its shadows take away at the target (`Shadows::change`).
pub fn remodulate(
    shading: &Image,
    shading_share: &[f32],
    shadow_share: Option<&Image>,
    base_color: &Image,
    material: Option<&Image>,
) -> (Image, u32) {
    let mut sanitized = 0;
    let width = shading.width;
    let output = Image::from_fn(shading.width, shading.height, 4, |x, y| {
        let (factor, material_changed) = pixel_modulation(base_color, material, x, y);
        let mut shading = Vec3::from_slice(shading.at(x, y));
        if let Some(share) = shadow_share {
            shading *= Vec3::ONE + Vec3::from_slice(share.at(x, y));
        }
        let share = shading_share[x + y * width];
        let (color, color_changed) = sanitize_color(shading * Vec3::ONE.lerp(factor, share));
        sanitized += (material_changed || color_changed) as u32;
        round_vec3_to_f16(color).extend(1.0).to_array().to_vec()
    });
    (output, sanitized)
}
