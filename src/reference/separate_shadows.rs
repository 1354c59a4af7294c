//! Mirror of `shaders/separate_shadows.wgsl`.

use glam::{Vec3, Vec4};

use super::gbuffer::{demodulated, pixel_modulation, sanitize, sanitize_input_color};
use super::Image;

pub struct Separated {
    /// The demodulated frame, which the warps carry: without the dynamic casters' shadows on
    /// static receivers when tracked.
    pub shading: Image,
    /// The share of light those shadows take away, in [-1, 0], and in alpha their darkness
    /// (1 - mask); zero untracked.
    pub shadow_layer: Image,
    /// Level 0 of the flow's pyramid.
    pub mask: Image,
    pub sanitized: u32,
}

/// `normal_id` is frame t's packed G-buffer, whose alpha is the object id; `tracked`: frame
/// t-1's shadows were tracked.
pub fn separate(
    color: &Image,
    color_without_dynamic_shadows: &Image,
    mask: &Image,
    base_color: &Image,
    material: Option<&Image>,
    normal_id: &Image,
    tracked: bool,
) -> Separated {
    let (w, h) = (color.width, color.height);
    let mut separated = Separated {
        shading: Image::new(w, h, 4),
        shadow_layer: Image::new(w, h, 4),
        mask: Image::new(w, h, 1),
        sanitized: 0,
    };
    for y in 0..h {
        for x in 0..w {
            let (factor, material_changed) = pixel_modulation(base_color, material, x, y);
            let (lit, lit_changed) = sanitize_input_color(Vec3::from_slice(color.at(x, y)));
            let (unshadowed, unshadowed_changed) =
                sanitize_input_color(Vec3::from_slice(color_without_dynamic_shadows.at(x, y)));
            let (visibility, mask_changed) =
                sanitize(Vec3::new(mask.at(x, y)[0], 0.0, 0.0), 0.0, 1.0);
            let dynamic = normal_id.at(x, y)[3] != 0.0;
            let separates = tracked && !dynamic;
            let shading = demodulated(if separates { unshadowed } else { lit }, factor);
            let layer = if separates {
                share_lost_to_shadows(lit, unshadowed).extend(1.0 - visibility.x)
            } else {
                Vec4::ZERO
            };
            let visibility = if dynamic { 1.0 } else { visibility.x };
            separated.shading.set(x, y, &shading.to_array());
            separated.shadow_layer.set(x, y, &layer.to_array());
            separated.mask.set(x, y, &[visibility]);
            separated.sanitized +=
                (material_changed || lit_changed || unshadowed_changed || mask_changed) as u32;
        }
    }
    separated
}

/// The share of the unshadowed light that the dynamic shadows take away, per channel
/// (`share_lost_to_shadows` in gbuffer.wgsl).
pub fn share_lost_to_shadows(lit: Vec3, unshadowed: Vec3) -> Vec3 {
    let lost = lit.min(unshadowed) - unshadowed;
    Vec3::select(
        unshadowed.cmpgt(Vec3::splat(BLACK)),
        lost / unshadowed,
        Vec3::ZERO,
    )
}

/// Below this unshadowed colour a receiver has no light to lose.
const BLACK: f32 = 1e-6;

/// The mask as the flow sees it, from an engine's mask and object ids (the stencil): sanitised,
/// and lit on dynamic objects, as `separate` leaves it for the next frame.
pub fn flow_mask(mask: &Image, object_ids: &Image) -> Image {
    Image::from_fn(mask.width, mask.height, 1, |x, y| {
        if object_ids.at(x, y)[0] != 0.0 {
            return vec![1.0];
        }
        vec![
            sanitize(Vec3::new(mask.at(x, y)[0], 0.0, 0.0), 0.0, 1.0)
                .0
                .x,
        ]
    })
}
