//! Mirror of `shaders/remodulate.wgsl`, including the rounding of the RGBA16F output.

use glam::Vec3;

use super::gbuffer::{metallic_specular, modulation};
use super::{round_to_f16, Image};

pub fn remodulate(shading: &Image, base_color: &Image, material: Option<&Image>) -> Image {
    Image::from_fn(shading.width, shading.height, 4, |x, y| {
        let (metallic, specular) = metallic_specular(material, x, y);
        let factor = modulation(Vec3::from_slice(base_color.at(x, y)), metallic, specular);
        let color = Vec3::from_slice(shading.at(x, y)) * factor;
        vec![
            round_to_f16(color.x),
            round_to_f16(color.y),
            round_to_f16(color.z),
            1.0,
        ]
    })
}
