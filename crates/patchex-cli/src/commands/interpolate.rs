//! The reference for what the future frame adds: bidirectional interpolation, which also uses
//! the future frame t+1 and so costs a frame of latency (what DLSS-G and FSR3 frame generation
//! do). Plain CPU code for the evaluation only; it is not part of the plugin. It fills no
//! holes, so it bounds extrapolation only where a frame has the surface.
//!
//! It works in the plugin's demodulated space and remodulates with the target's own G-buffer,
//! so it differs from the extrapolating warps only in what it knows. Each target pixel takes
//! frame t's shading where its backward motion vector lands on the same surface (same object
//! id, linear depth within 5%, normals within 25 degrees; bilinear over the agreeing texels),
//! and frame t+1's shading the same way along the opposite vector (motion assumed steady over
//! the two half-frames), or where that fails, splatted forward along t+1's own motion vectors
//! (which point at the target instant) with a depth test. It averages the two where both agree,
//! takes the one that does otherwise (the future frame fills what frame t hid), and keeps frame
//! t's reprojection where neither does.

use glam::Vec3;
use patchex::reference::gbuffer::modulation;
use patchex_scene::dataset::{
    BASE_COLOR, CUSTOM_STENCIL, FINAL_IMAGE, METALLIC, MOTION_VECTOR, SCENE_DEPTH, SPECULAR,
    WORLD_NORMAL,
};
use patchex_scene::FrameLayers;

const DEPTH_TOLERANCE: f32 = 0.05;
/// Smallest cosine between normals of one surface (about 25 degrees).
const MIN_NORMAL_COSINE: f32 = 0.9;

/// What a target pixel shows, to test source texels against.
#[derive(Clone, Copy)]
struct Surface {
    depth: f32,
    id: f32,
    normal: Vec3,
}

impl Surface {
    fn at(layers: &FrameLayers, x: usize, y: usize) -> Self {
        Self {
            depth: layers.layer(SCENE_DEPTH).value(x, y, 0),
            id: layers.layer(CUSTOM_STENCIL).value(x, y, 0),
            normal: Vec3::from_slice(layers.layer(WORLD_NORMAL).pixel(x, y)),
        }
    }

    fn agrees(&self, other: &Surface) -> bool {
        self.id == other.id
            && (self.depth - other.depth).abs() <= DEPTH_TOLERANCE * self.depth.max(other.depth)
            && self.normal.dot(other.normal) >= MIN_NORMAL_COSINE
    }
}

/// One frame's demodulated shading and the geometry to test agreement against.
struct Shading<'a> {
    width: usize,
    height: usize,
    shading: Vec<Vec3>,
    layers: &'a FrameLayers,
}

fn modulation_at(layers: &FrameLayers, x: usize, y: usize) -> Vec3 {
    modulation(
        Vec3::from_slice(layers.layer(BASE_COLOR).pixel(x, y)),
        layers.layer(METALLIC).value(x, y, 0),
        layers.layer(SPECULAR).value(x, y, 0),
    )
}

impl<'a> Shading<'a> {
    fn demodulate(layers: &'a FrameLayers) -> Self {
        let (width, height) = (layers.width, layers.height);
        let color = layers.layer(FINAL_IMAGE);
        let shading = (0..width * height)
            .map(|p| {
                let (x, y) = (p % width, p / width);
                Vec3::from_slice(color.pixel(x, y)) / modulation_at(layers, x, y)
            })
            .collect();
        Self {
            width,
            height,
            shading,
            layers,
        }
    }

    fn index(&self, x: i64, y: i64) -> Option<usize> {
        (x >= 0 && y >= 0 && (x as usize) < self.width && (y as usize) < self.height)
            .then(|| y as usize * self.width + x as usize)
    }

    /// Whether texel `s` shows `surface`.
    fn agrees(&self, s: usize, surface: &Surface) -> bool {
        Surface::at(self.layers, s % self.width, s / self.width).agrees(surface)
    }

    /// Bilinear shading at continuous point (x, y) over the texels that agree, if any does.
    fn sample(&self, x: f32, y: f32, surface: &Surface) -> Option<Vec3> {
        let (fx, fy) = (x - 0.5, y - 0.5);
        let (x0, y0) = (fx.floor(), fy.floor());
        let (tx, ty) = (fx - x0, fy - y0);
        let mut sum = Vec3::ZERO;
        let mut total = 0.0;
        for (dx, dy, weight) in [
            (0, 0, (1.0 - tx) * (1.0 - ty)),
            (1, 0, tx * (1.0 - ty)),
            (0, 1, (1.0 - tx) * ty),
            (1, 1, tx * ty),
        ] {
            if let Some(s) = self.index(x0 as i64 + dx, y0 as i64 + dy) {
                if weight > 0.0 && self.agrees(s, surface) {
                    sum += weight * self.shading[s];
                    total += weight;
                }
            }
        }
        (total > 0.0).then(|| sum / total)
    }
}

/// RGB, linear HDR, of the target instant between `previous` (t) and `next` (t+1).
pub fn interpolate(previous: &FrameLayers, target: &FrameLayers, next: &FrameLayers) -> Vec<f32> {
    let (width, height) = (target.width, target.height);
    let previous = Shading::demodulate(previous);
    let next = Shading::demodulate(next);

    // Frame t+1 splatted onto the target: the nearest surface wins each pixel.
    let next_depth = next.layers.layer(SCENE_DEPTH);
    let next_motion = next.layers.layer(MOTION_VECTOR);
    let mut splat: Vec<Option<(f32, usize)>> = vec![None; width * height];
    for y in 0..height {
        for x in 0..width {
            let v = next_motion.pixel(x, y);
            let to_x = (x as f32 + 0.5 + v[0]).floor() as i64;
            let to_y = (y as f32 + 0.5 + v[1]).floor() as i64;
            let Some(to) = next.index(to_x, to_y) else {
                continue;
            };
            let d = next_depth.value(x, y, 0);
            if splat[to].is_none_or(|(nearest, _)| d < nearest) {
                splat[to] = Some((d, y * width + x));
            }
        }
    }

    let motion = target.layer(MOTION_VECTOR);
    let mut out = Vec::with_capacity(width * height * 3);
    for y in 0..height {
        for x in 0..width {
            let surface = Surface::at(target, x, y);
            let v = motion.pixel(x, y);
            let (qx, qy) = (x as f32 + 0.5 + v[0], y as f32 + 0.5 + v[1]);
            let backward = previous.sample(qx, qy, &surface);
            let forward = next
                .sample(x as f32 + 0.5 - v[0], y as f32 + 0.5 - v[1], &surface)
                .or_else(|| {
                    splat[y * width + x]
                        .filter(|(_, s)| next.agrees(*s, &surface))
                        .map(|(_, s)| next.shading[s])
                });
            let shading = match (backward, forward) {
                (Some(b), Some(f)) => 0.5 * (b + f),
                (Some(only), None) | (None, Some(only)) => only,
                (None, None) => {
                    let s = previous.index(qx.floor() as i64, qy.floor() as i64);
                    previous.shading[s.unwrap_or(y * width + x)]
                }
            };
            out.extend_from_slice(&(shading * modulation_at(target, x, y)).to_array());
        }
    }
    out
}
