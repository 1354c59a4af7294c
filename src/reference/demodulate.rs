//! Mirror of `shaders/demodulate.wgsl`.

use glam::Vec3;

use super::gbuffer::{demodulated, pixel_modulation, sanitize_input_color};
use super::Image;

/// Frame t's shading, and the number of pixels whose inputs were sanitised.
pub fn demodulate(color: &Image, base_color: &Image, material: Option<&Image>) -> (Image, u32) {
    let mut sanitized = 0;
    let shading = Image::from_fn(color.width, color.height, 4, |x, y| {
        let (factor, material_changed) = pixel_modulation(base_color, material, x, y);
        let (color, color_changed) = sanitize_input_color(Vec3::from_slice(color.at(x, y)));
        sanitized += (material_changed || color_changed) as u32;
        demodulated(color, factor).to_array().to_vec()
    });
    (shading, sanitized)
}
