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

/// Largest value of the RGBA16F output.
pub const MAX_HALF: f32 = 65504.0;

/// `sanitize` of `include/gbuffer.wgsl`: components outside [low, high] take the nearest bound,
/// NaN takes 0; returns whether any changed.
pub fn sanitize(v: Vec3, low: f32, high: f32) -> (Vec3, bool) {
    let fix = |c: f32| {
        if (low..=high).contains(&c) {
            c
        } else if c.is_nan() {
            0.0
        } else {
            c.clamp(low, high)
        }
    };
    let fixed = Vec3::new(fix(v.x), fix(v.y), fix(v.z));
    let changed = !v.cmpge(Vec3::splat(low)).all() || !v.cmple(Vec3::splat(high)).all();
    (fixed, changed)
}

pub fn sanitize_color(v: Vec3) -> (Vec3, bool) {
    sanitize(v, -MAX_HALF, MAX_HALF)
}

/// `pixel_modulation`: the modulation factor from sanitised base colour and material, and
/// whether either was sanitised.
/// Shading as the RGBA16F working images hold it (`demodulated` in gbuffer.wgsl): held to the
/// half-float range (whether it was is returned) and rounded to f16.
pub fn demodulated(color: Vec3, factor: Vec3) -> (Vec3, bool) {
    let (shading, changed) = sanitize_color(color / factor);
    (shading.to_array().map(super::round_to_f16).into(), changed)
}

pub fn pixel_modulation(
    base_color: &Image,
    material: Option<&Image>,
    x: usize,
    y: usize,
) -> (Vec3, bool) {
    let (base, base_changed) = sanitize(Vec3::from_slice(base_color.at(x, y)), 0.0, 1.0);
    let (metallic, specular) = metallic_specular(material, x, y);
    let (ms, ms_changed) = sanitize(Vec3::new(metallic, specular, 0.0), 0.0, 1.0);
    (modulation(base, ms.x, ms.y), base_changed || ms_changed)
}
