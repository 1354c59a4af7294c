//! Mirror of `shaders/remodulate.wgsl`, including the rounding of the RGBA16F output.

use glam::Vec3;

use super::gbuffer::{pixel_modulation, sanitize_color};
use super::{round_to_f16, Image};

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
        vec![
            round_to_f16(color.x),
            round_to_f16(color.y),
            round_to_f16(color.z),
            1.0,
        ]
    });
    (output, sanitized)
}
