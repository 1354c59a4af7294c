//! Mirror of `shaders/warp_gbuffer.wgsl`.

use glam::{IVec2, Vec2, Vec3, Vec4};

use super::gbuffer::is_sky;
use super::Image;
use crate::shaders::warp_gbuffer::Params;

pub const AGREEMENT_THRESHOLD: f32 = 0.5;
pub const BILINEAR_ACCEPT: f32 = 0.5;
const MIN_TOTAL_WEIGHT: f32 = 1e-6;

pub struct Warped {
    /// (shading, 1 for valid or 0 for hole).
    pub warped: Image,
    /// The best geometry agreement each pixel found: how close it came to the hole threshold.
    pub best_agreement: Vec<f32>,
    /// The agreeing share of each pixel's bilinear footprint: how close it came to switching to
    /// the bilateral gather.
    pub bilinear_weight: Vec<f32>,
    pub hole_pixels: u32,
    pub offscreen_pixels: u32,
}

pub struct WarpSources<'a> {
    pub shading: &'a Image,
    pub geometry: &'a Image,
    pub normal_id: &'a Image,
}

fn geometry_weight(
    params: &Params,
    target_geo: Vec4,
    target_nid: Vec4,
    source_geo: Vec4,
    source_nid: Vec4,
) -> f32 {
    if target_nid.w != source_nid.w {
        return 0.0;
    }
    if is_sky(target_geo.w) || is_sky(source_geo.w) {
        return if is_sky(target_geo.w) && is_sky(source_geo.w) {
            1.0
        } else {
            0.0
        };
    }
    let mut weight =
        (-(1.0 - target_nid.truncate().dot(source_nid.truncate())) * params.inv_sigma_normal).exp();
    let e = if target_nid.w == 0.0 {
        target_geo.truncate().distance(source_geo.truncate()) / target_geo.w
            * params.inv_sigma_position
    } else {
        (target_geo.w - source_geo.w).abs() / target_geo.w.max(source_geo.w)
            * params.inv_sigma_depth
    };
    weight *= (-e * e).exp();
    weight
}

pub fn warp_gbuffer(
    source: &WarpSources,
    target_geometry: &Image,
    target_normal_id: &Image,
    motion: &Image,
    params: &Params,
) -> Warped {
    let (width, height) = (params.extent[0] as usize, params.extent[1] as usize);
    let extent = IVec2::new(width as i32, height as i32);
    let texel = |image: &Image, s: IVec2| Vec4::from_slice(image.clamped(s.x, s.y));
    let mut best_agreements = Vec::with_capacity(width * height);
    let mut bilinear_weights = Vec::with_capacity(width * height);
    let (mut hole_pixels, mut offscreen_pixels) = (0, 0);
    let warped = Image::from_fn(width, height, 4, |x, y| {
        let q = Vec2::new(x as f32, y as f32)
            + 0.5
            + Vec2::from_slice(motion.at(x, y)) * Vec2::from(params.motion_scale)
            + Vec2::from(params.jitter_delta);
        let offscreen = !(q.x >= 0.0 && q.y >= 0.0 && q.x < width as f32 && q.y < height as f32);
        let target_geo = Vec4::from_slice(target_geometry.at(x, y));
        let target_nid = Vec4::from_slice(target_normal_id.at(x, y));
        let agreement_at = |s: IVec2| {
            geometry_weight(
                params,
                target_geo,
                target_nid,
                texel(source.geometry, s),
                texel(source.normal_id, s),
            )
        };

        let corner = (q - 0.5).floor().as_ivec2();
        let f = q - 0.5 - (q - 0.5).floor();
        let mut shading_sum = Vec3::ZERO;
        let mut weight_sum = 0.0;
        let mut best_agreement: f32 = 0.0;
        for i in 0..4 {
            let offset = IVec2::new(i & 1, i >> 1);
            let s = (corner + offset).clamp(IVec2::ZERO, extent - 1);
            let agreement = agreement_at(s);
            let bx = if offset.x == 1 { f.x } else { 1.0 - f.x };
            let by = if offset.y == 1 { f.y } else { 1.0 - f.y };
            let footprint = bx * by;
            shading_sum += footprint * agreement * texel(source.shading, s).truncate();
            weight_sum += footprint * agreement;
            if footprint > 0.0 {
                best_agreement = best_agreement.max(agreement);
            }
        }

        bilinear_weights.push(weight_sum);
        if weight_sum < BILINEAR_ACCEPT {
            shading_sum = Vec3::ZERO;
            weight_sum = 0.0;
            let centre = q.floor().as_ivec2().clamp(IVec2::ZERO, extent - 1);
            let r = params.kernel_radius;
            for dy in -r..=r {
                for dx in -r..=r {
                    let s = (centre + IVec2::new(dx, dy)).clamp(IVec2::ZERO, extent - 1);
                    let agreement = agreement_at(s);
                    let d = s.as_vec2() + 0.5 - q;
                    let weight = (-d.dot(d) * params.inv_two_sigma_spatial_sq).exp() * agreement;
                    shading_sum += weight * texel(source.shading, s).truncate();
                    weight_sum += weight;
                    best_agreement = best_agreement.max(agreement);
                }
            }
        }
        let nearest = q.floor().as_ivec2().clamp(IVec2::ZERO, extent - 1);
        let shading = if weight_sum > MIN_TOTAL_WEIGHT {
            shading_sum / weight_sum
        } else {
            texel(source.shading, nearest).truncate()
        };
        let hole = offscreen || best_agreement < AGREEMENT_THRESHOLD;
        hole_pixels += hole as u32;
        offscreen_pixels += offscreen as u32;
        best_agreements.push(best_agreement);
        vec![
            shading.x,
            shading.y,
            shading.z,
            if hole { 0.0 } else { 1.0 },
        ]
    });
    Warped {
        warped,
        best_agreement: best_agreements,
        bilinear_weight: bilinear_weights,
        hole_pixels,
        offscreen_pixels,
    }
}
