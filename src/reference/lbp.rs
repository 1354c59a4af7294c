//! Mirror of `shaders/include/lbp.wgsl` and `shaders/lbp.wgsl`.

use glam::Vec3;

use super::{round_to_f16, Image};

pub const LUMINANCE: Vec3 = Vec3::new(0.2126, 0.7152, 0.0722);
/// Clockwise from the top-left; neighbour k sets bit k.
pub const NEIGHBOURS: [(i32, i32); 8] = [
    (-1, -1),
    (0, -1),
    (1, -1),
    (1, 0),
    (1, 1),
    (0, 1),
    (-1, 1),
    (-1, 0),
];

pub fn luminance(image: &Image, x: i32, y: i32) -> f32 {
    Vec3::from_slice(image.clamped(x, y)).dot(LUMINANCE)
}

/// The LBP code of `warped`'s luminance at (x, y), 0 to 255 (`include/lbp.wgsl`).
pub fn code(warped: &Image, x: i32, y: i32) -> u32 {
    let centre = luminance(warped, x, y);
    NEIGHBOURS
        .iter()
        .enumerate()
        .filter(|(_, (dx, dy))| luminance(warped, x + dx, y + dy) >= centre)
        .fold(0, |code, (k, _)| code | 1 << k)
}

/// LBP codes of `warped`, as code / 255 in one channel, rounded to f16 as stored.
pub fn lbp(warped: &Image) -> Image {
    Image::from_fn(warped.width, warped.height, 1, |x, y| {
        vec![round_to_f16(
            code(warped, x as i32, y as i32) as f32 / 255.0,
        )]
    })
}
