//! The particles, drawn after lighting as an engine draws its translucency: each particle a
//! camera-facing soft disc, blended back to front into the translucent layer (under its blended
//! surfaces where it lies beyond them), faded where it nears the opaque surface behind it. Drawn
//! on the CPU: particles cast no shadow and write no G-buffer, so nothing on the GPU needs them.

use glam::{Vec3, Vec4Swizzles};

use super::translucent_layer::{Texel, TranslucentLayer};
use crate::scene::{CameraState, Particle};

/// A particle as the screen sees it.
struct Sprite {
    centre: [f32; 2],
    radius: f32,
    depth: f32,
    /// Backward motion to the earlier instant, in pixels.
    motion: [f32; 2],
    opacity: f32,
    color: Vec3,
    /// The distance over which it fades into the surface behind it.
    soft_depth: f32,
}

fn pixel_of(camera: &CameraState, position: Vec3, size: [f32; 2]) -> Option<([f32; 2], f32)> {
    let clip = camera.view_proj() * position.extend(1.0);
    if clip.w <= camera.near {
        return None;
    }
    let ndc = clip.xy() / clip.w;
    Some((
        [(ndc.x * 0.5 + 0.5) * size[0], (ndc.y * 0.5 + 0.5) * size[1]],
        clip.w,
    ))
}

fn sprite(
    particle: &Particle,
    camera: &CameraState,
    previous_camera: &CameraState,
    size: [f32; 2],
) -> Option<Sprite> {
    let (centre, depth) = pixel_of(camera, particle.position, size)?;
    let (previous, _) = pixel_of(previous_camera, particle.previous_position, size)?;
    // |proj[1][1]| is the focal length over half the image's height (negative: y points down).
    let radius = particle.radius * camera.proj.y_axis.y.abs() * 0.5 * size[1] / depth;
    Some(Sprite {
        centre,
        radius,
        depth,
        motion: [previous[0] - centre[0], previous[1] - centre[1]],
        opacity: particle.opacity,
        color: particle.color,
        soft_depth: particle.radius,
    })
}

/// Draws `particles` into `layer`, back to front, where they lie in front of the opaque surface
/// at `scene_depth`.
pub(crate) fn draw_particles(
    layer: &mut TranslucentLayer,
    scene_depth: &[f32],
    particles: &[Particle],
    camera: &CameraState,
    previous_camera: &CameraState,
) {
    let (width, height) = (layer.width(), layer.height());
    let size = [width as f32, height as f32];
    let mut sprites: Vec<Sprite> = particles
        .iter()
        .filter_map(|p| sprite(p, camera, previous_camera, size))
        .filter(|s| s.opacity > 0.0 && s.radius > 0.0)
        .collect();
    sprites.sort_by(|a, b| b.depth.total_cmp(&a.depth));

    for s in &sprites {
        let x0 = (s.centre[0] - s.radius).floor().max(0.0) as usize;
        let y0 = (s.centre[1] - s.radius).floor().max(0.0) as usize;
        let x1 = ((s.centre[0] + s.radius).ceil().max(0.0) as usize).min(width);
        let y1 = ((s.centre[1] + s.radius).ceil().max(0.0) as usize).min(height);
        for y in y0..y1 {
            for x in x0..x1 {
                let dx = (x as f32 + 0.5 - s.centre[0]) / s.radius;
                let dy = (y as f32 + 0.5 - s.centre[1]) / s.radius;
                let r2 = dx * dx + dy * dy;
                if r2 >= 1.0 {
                    continue;
                }
                let pixel = y * width + x;
                let behind = scene_depth[pixel] - s.depth;
                let soft = (behind / s.soft_depth).clamp(0.0, 1.0);
                let a = s.opacity * (1.0 - r2) * (1.0 - r2) * soft;
                if a <= 0.0 {
                    continue;
                }
                layer.draw(pixel, Texel::new(s.color, s.motion, a), s.depth);
            }
        }
    }
}
