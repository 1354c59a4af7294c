//! Mirror of `shaders/pack_gbuffer.wgsl`, including the rounding of the RGBA16F normal_id image.

use glam::{Mat4, Vec2, Vec3, Vec4};

use super::gbuffer::SKY_DEPTH;
use super::{round_to_f16, Image};
use crate::abi::{
    PATCHEX_DEPTH_HARDWARE_REVERSED, PATCHEX_DEPTH_LINEAR_VIEW_Z, PATCHEX_NORMAL_UNORM,
};
use crate::shaders::pack_gbuffer::Params;

pub struct Packed {
    /// (world position, linear depth).
    pub geometry: Image,
    /// (unit world normal, object id).
    pub normal_id: Image,
    /// Pixels whose depth, normal or motion vector has a NaN or infinite component.
    pub invalid_pixels: u32,
}

fn surface(params: &Params, ndc: Vec2, stored_depth: f32) -> Vec4 {
    let inv_view_proj = Mat4::from_cols_array_2d(&params.inv_view_proj);
    let camera_position = Vec3::from(params.camera_position);
    let unproject = |depth: f32| inv_view_proj * Vec4::new(ndc.x, ndc.y, depth, 1.0);
    if params.depth_convention == PATCHEX_DEPTH_LINEAR_VIEW_Z {
        if stored_depth >= params.far {
            return Vec4::new(0.0, 0.0, 0.0, SKY_DEPTH);
        }
        let on_ray = unproject(0.5);
        let ray = on_ray.truncate() / on_ray.w - camera_position;
        let position =
            camera_position + ray * (stored_depth / ray.dot(Vec3::from(params.camera_forward)));
        return position.extend(stored_depth);
    }
    let at_far = if params.depth_convention == PATCHEX_DEPTH_HARDWARE_REVERSED {
        stored_depth <= 0.0
    } else {
        stored_depth >= 1.0
    };
    let clip = unproject(stored_depth);
    if at_far || clip.w.abs() < 1e-20 {
        return Vec4::new(0.0, 0.0, 0.0, SKY_DEPTH);
    }
    let position = clip.truncate() / clip.w;
    position.extend((position - camera_position).dot(Vec3::from(params.camera_forward)))
}

/// `stencil` holds object ids as floats; `None` means all static. `motion` is only checked.
pub fn pack_gbuffer(
    depth: &Image,
    normal: &Image,
    stencil: Option<&Image>,
    motion: Option<&Image>,
    params: &Params,
) -> Packed {
    let (width, height) = (params.extent[0] as usize, params.extent[1] as usize);
    let extent = Vec2::new(width as f32, height as f32);
    let geometry = Image::from_fn(width, height, 4, |x, y| {
        let ndc = (Vec2::new(x as f32, y as f32) + 0.5) / extent * 2.0 - 1.0;
        surface(params, ndc, depth.at(x, y)[0]).to_array().to_vec()
    });
    let normal_id = Image::from_fn(width, height, 4, |x, y| {
        let mut n = Vec3::from_slice(normal.at(x, y));
        if params.normal_encoding == PATCHEX_NORMAL_UNORM {
            n = n * 2.0 - 1.0;
        }
        let length = n.length();
        let n = if length > 1e-6 {
            n / length
        } else {
            Vec3::ZERO
        };
        let id = stencil.map_or(0.0, |s| s.at(x, y)[0]);
        vec![
            round_to_f16(n.x),
            round_to_f16(n.y),
            round_to_f16(n.z),
            round_to_f16(id),
        ]
    });
    let finite = |image: &Image, x, y, channels: usize| {
        image.at(x, y)[..channels].iter().all(|v| v.is_finite())
    };
    let invalid_pixels = (0..height)
        .flat_map(|y| (0..width).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            !(finite(depth, x, y, 1)
                && finite(normal, x, y, 3)
                && motion.is_none_or(|motion| finite(motion, x, y, 2)))
        })
        .count() as u32;
    Packed {
        geometry,
        normal_id,
        invalid_pixels,
    }
}
