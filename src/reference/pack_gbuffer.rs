//! Mirror of `shaders/pack_gbuffer.wgsl`, and of how the warps unpack what it stores: linear
//! depth, the normal through its octahedral code, and world positions rebuilt from depth and the
//! camera's pixel rays.

use glam::{Vec2, Vec3, Vec4};

use super::gbuffer::{valid_geometry, SKY_DEPTH};
use super::Image;
use crate::abi::{
    PATCHEX_DEPTH_HARDWARE_REVERSED, PATCHEX_DEPTH_LINEAR_VIEW_Z, PATCHEX_NORMAL_UNORM,
};
use crate::camera::PixelRays;
use crate::shaders::pack_gbuffer::Params;

pub struct Packed {
    /// (world position, linear depth), the position as the warps rebuild it.
    pub geometry: Image,
    /// (unit world normal, object id), as the warps unpack them.
    pub normal_id: Image,
    /// Per pixel, row by row: whether its depth and normal are usable (`valid_geometry`).
    pub valid: Vec<bool>,
    /// Pixels whose depth is NaN or out of range, or whose normal or motion vector has a NaN
    /// or infinite component.
    pub invalid_pixels: u32,
    /// The camera the positions are rebuilt around, as the warps have it.
    pub camera_position: Vec3,
}

/// Linear depth of a stored depth at pixel (x, y) (`linear_depth` in gbuffer.wgsl).
pub fn linear_depth(params: &Params, x: usize, y: usize, stored: f32) -> f32 {
    if params.depth_convention == PATCHEX_DEPTH_LINEAR_VIEW_Z {
        return if stored >= params.far {
            SKY_DEPTH
        } else {
            stored
        };
    }
    let at_far = if params.depth_convention == PATCHEX_DEPTH_HARDWARE_REVERSED {
        stored <= 0.0
    } else {
        stored >= 1.0
    };
    let inverse = Vec4::from(params.depth_curve).dot(Vec4::new(stored, 1.0, x as f32, y as f32));
    if at_far || inverse == 0.0 {
        return SKY_DEPTH;
    }
    1.0 / inverse
}

/// A stored normal as a unit vector, or zero (`unit_normal`).
pub fn unit_normal(stored: Vec3, encoding: u32) -> Vec3 {
    let n = if encoding == PATCHEX_NORMAL_UNORM {
        stored * 2.0 - 1.0
    } else {
        stored
    };
    let length = n.length();
    if length > 1e-6 && length <= f32::MAX {
        n / length
    } else {
        Vec3::ZERO
    }
}

/// Which instant a G-buffer belongs to, which decides how it is read.
#[derive(Clone, Copy, PartialEq)]
pub enum Instant {
    /// Frame t: normals through the packed octahedral code, as the warps unpack them.
    Source,
    /// The target: normals as the engine stored them, which the warps read straight.
    Target,
}

/// `stencil` holds object ids as floats; `None` means all static. `motion` is only checked.
pub fn pack_gbuffer(
    depth: &Image,
    normal: &Image,
    stencil: Option<&Image>,
    motion: Option<&Image>,
    params: &Params,
    rays: &PixelRays,
    instant: Instant,
) -> Packed {
    let (width, height) = (params.extent[0] as usize, params.extent[1] as usize);
    let geometry = Image::from_fn(width, height, 4, |x, y| {
        let linear = linear_depth(params, x, y, depth.at(x, y)[0]);
        rays.surface(x as f32, y as f32, linear)
            .extend(linear)
            .to_array()
            .to_vec()
    });
    let valid = |x: usize, y: usize| {
        valid_geometry(
            depth.at(x, y)[0],
            Vec3::from_slice(normal.at(x, y)),
            params.depth_convention,
        )
    };
    let normal_id = Image::from_fn(width, height, 4, |x, y| {
        let n = unit_normal(Vec3::from_slice(normal.at(x, y)), params.normal_encoding);
        let id = stencil.map_or(0.0, |s| s.at(x, y)[0]);
        let n = match instant {
            Instant::Source => unpack_normal(pack_normal(n)),
            Instant::Target => n,
        };
        vec![n.x, n.y, n.z, id]
    });
    let valid: Vec<bool> = (0..height)
        .flat_map(|y| (0..width).map(move |x| (x, y)))
        .map(|(x, y)| valid(x, y))
        .collect();
    let finite_motion =
        |x: usize, y: usize| motion.is_none_or(|m| m.at(x, y)[..2].iter().all(|v| v.is_finite()));
    let invalid_pixels = (0..height)
        .flat_map(|y| (0..width).map(move |x| (x, y)))
        .filter(|&(x, y)| !(valid[x + y * width] && finite_motion(x, y)))
        .count() as u32;
    Packed {
        geometry,
        normal_id,
        valid,
        invalid_pixels,
        camera_position: rays.position,
    }
}

const OCTAHEDRAL_SCALE: f32 = 2047.0;
const OCTAHEDRAL_CENTRE: f32 = 2048.0;

fn sign_not_zero(v: Vec2) -> Vec2 {
    Vec2::new(
        if v.x >= 0.0 { 1.0 } else { -1.0 },
        if v.y >= 0.0 { 1.0 } else { -1.0 },
    )
}

/// The unit normal's two 12-bit octahedral codes (`pack_normal_id` in gbuffer.wgsl); (0, 0) for
/// no normal.
pub fn pack_normal(n: Vec3) -> [u32; 2] {
    if n == Vec3::ZERO {
        return [0, 0];
    }
    let mut e = Vec2::new(n.x, n.y) / (n.x.abs() + n.y.abs() + n.z.abs());
    if n.z < 0.0 {
        e = (1.0 - Vec2::new(e.y, e.x).abs()) * sign_not_zero(e);
    }
    let code = e.clamp(Vec2::splat(-1.0), Vec2::ONE) * OCTAHEDRAL_SCALE + OCTAHEDRAL_CENTRE;
    [code.x, code.y].map(|c| c.round_ties_even() as u32)
}

/// The normal the warps read back from its codes (`unpack_normal`).
pub fn unpack_normal(code: [u32; 2]) -> Vec3 {
    if code == [0, 0] {
        return Vec3::ZERO;
    }
    let e = (Vec2::new(code[0] as f32, code[1] as f32) - OCTAHEDRAL_CENTRE) / OCTAHEDRAL_SCALE;
    let mut n = Vec3::new(e.x, e.y, 1.0 - e.x.abs() - e.y.abs());
    if n.z < 0.0 {
        let folded = (1.0 - Vec2::new(n.y, n.x).abs()) * sign_not_zero(Vec2::new(n.x, n.y));
        n = Vec3::new(folded.x, folded.y, n.z);
    }
    n.normalize()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn octahedral_codes_keep_normals_within_a_sixteenth_of_a_degree() {
        let mut worst = 0.0f32;
        for i in 0..2000 {
            // A spiral over the sphere, poles and axes included.
            let z = 1.0 - 2.0 * i as f32 / 1999.0;
            let angle = i as f32 * 2.399_963;
            let r = (1.0 - z * z).max(0.0).sqrt();
            for n in [
                Vec3::new(r * angle.cos(), r * angle.sin(), z),
                Vec3::X,
                -Vec3::Y,
                -Vec3::Z,
            ] {
                let back = unpack_normal(pack_normal(n));
                worst = worst.max(n.dot(back).clamp(-1.0, 1.0).acos().to_degrees());
            }
        }
        assert!(worst < 0.0625, "{worst} degrees");
        assert_eq!(unpack_normal(pack_normal(Vec3::ZERO)), Vec3::ZERO);
    }
}
