//! Mirror of `shaders/include/gbuffer.wgsl`.

use glam::{Vec3, Vec4};

use super::{round_to_f16, Image};
use crate::abi::{PatchexDepthConvention, PATCHEX_DEPTH_LINEAR_VIEW_Z};

pub const MIN_MODULATION: f32 = 0.01;
pub const DARK_MODULATION: f32 = 0.05;
pub const FITTED_SHADING: f32 = 64000.0;
pub const SATURATED_SHADING: f32 = 63968.0;
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
/// Below this a value rounds to at most MAX_HALF as a half float (`HALF_ROUNDS_TO_MAX`).
pub const HALF_ROUNDS_TO_MAX: f32 = 65519.0;

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
    sanitize(v, -HALF_ROUNDS_TO_MAX, HALF_ROUNDS_TO_MAX)
}

pub fn sanitize_input_color(v: Vec3) -> (Vec3, bool) {
    sanitize(v, 0.0, MAX_HALF)
}

pub fn round_vec3_to_f16(v: Vec3) -> Vec3 {
    v.to_array().map(round_to_f16).into()
}

/// `demodulated` in gbuffer.wgsl: the shading, rounded to f16, and in alpha the largest channel
/// of its divisor, the modulation factor scaled up where the shading would pass
/// `FITTED_SHADING`.
pub fn demodulated(color: Vec3, factor: Vec3) -> Vec4 {
    let shading = color / factor;
    let scale = (shading.max_element() / FITTED_SHADING).max(1.0);
    round_vec3_to_f16((shading / scale).min(Vec3::splat(FITTED_SHADING)))
        .extend(factor.max_element() * scale)
}

/// `remodulation` in gbuffer.wgsl: the factor warped shading is multiplied by, from the target's
/// modulation factor, the shading and its divisor.
pub fn remodulation(target: Vec3, shading: Vec3, divisor: f32) -> Vec3 {
    let mut factor = target;
    if divisor < DARK_MODULATION {
        factor = factor.min(Vec3::splat(divisor));
    }
    let brightest = shading.max_element();
    if brightest >= SATURATED_SHADING {
        let target_max = target.max_element();
        let scale = (divisor / target_max).min(MAX_HALF / (brightest * target_max));
        factor = target * scale.max(1.0);
    }
    factor
}

/// `valid_geometry` in gbuffer.wgsl: the depth in its convention's range (a positive linear
/// depth, +infinity included; hardware depth in [0, 1]) and the normal finite.
pub fn valid_geometry(depth: f32, normal: Vec3, convention: PatchexDepthConvention) -> bool {
    let depth_in_range = if convention == PATCHEX_DEPTH_LINEAR_VIEW_Z {
        depth > 0.0
    } else {
        (0.0..=1.0).contains(&depth)
    };
    depth_in_range && normal.is_finite()
}

/// `pixel_modulation`: the modulation factor from sanitised base colour and material, and
/// whether either was sanitised.
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
