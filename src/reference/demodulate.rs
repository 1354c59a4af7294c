//! Mirror of `shaders/demodulate.wgsl`.

use glam::Vec3;

use super::gbuffer::{metallic_specular, modulation};
use super::Image;

pub fn demodulate(color: &Image, base_color: &Image, material: Option<&Image>) -> Image {
    Image::from_fn(color.width, color.height, 4, |x, y| {
        let (metallic, specular) = metallic_specular(material, x, y);
        let factor = modulation(Vec3::from_slice(base_color.at(x, y)), metallic, specular);
        let shading = Vec3::from_slice(color.at(x, y)) / factor;
        vec![shading.x, shading.y, shading.z, 1.0]
    })
}
