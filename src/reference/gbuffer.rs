//! Mirror of `shaders/include/gbuffer.wgsl`.

use glam::Vec3;

use super::Image;

pub const MIN_MODULATION: f32 = 0.01;
pub const SKY_DEPTH: f32 = 1e30;

pub fn modulation(base_color: Vec3, metallic: f32, specular: f32) -> Vec3 {
    (base_color + Vec3::splat(0.08 * specular * (1.0 - metallic))).max(Vec3::splat(MIN_MODULATION))
}

/// (metallic, specular) of a pixel, or Unreal's defaults without a material image.
pub fn metallic_specular(material: Option<&Image>, x: usize, y: usize) -> (f32, f32) {
    match material {
        Some(material) => (material.at(x, y)[0], material.at(x, y)[1]),
        None => (0.0, 0.5),
    }
}

pub fn is_sky(linear_depth: f32) -> bool {
    linear_depth >= 0.5 * SKY_DEPTH
}
