//! The particles' forward pass, drawn after lighting as an engine draws its translucency: each
//! particle a camera-facing soft disc, blended back to front over the lit colour, faded where it
//! nears the opaque surface behind it. It writes what an engine hands a frame generator beside
//! the colour: the mask of how much of each pixel the particles cover, and their own motion.
//! Drawn on the CPU from the frame's read-back layers: particles cast no shadow and write no
//! G-buffer, so nothing on the GPU needs them.

use glam::{Vec3, Vec4Swizzles};

use crate::dataset::{
    FrameLayers, LayerImage, FINAL_IMAGE, FINAL_IMAGE_NO_DYNAMIC_SHADOWS, SCENE_DEPTH,
    SPECULAR_LIGHT, TRANSLUCENCY_MASK, TRANSLUCENCY_MOTION,
};
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

/// Blends `particles` over the frame's lit layers, back to front, and adds the translucency
/// mask and motion layers.
pub fn draw_particles(
    layers: &mut FrameLayers,
    particles: &[Particle],
    camera: &CameraState,
    previous_camera: &CameraState,
) {
    let (width, height) = (layers.width, layers.height);
    let size = [width as f32, height as f32];
    let mut sprites: Vec<Sprite> = particles
        .iter()
        .filter_map(|p| sprite(p, camera, previous_camera, size))
        .filter(|s| s.opacity > 0.0 && s.radius > 0.0)
        .collect();
    sprites.sort_by(|a, b| b.depth.total_cmp(&a.depth));

    let scene_depth = layers.layer(SCENE_DEPTH).plane(0);
    let mut coverage = vec![0f32; width * height];
    // Each particle's motion weighted by what it shows of itself in the final pixel.
    let mut weighted_motion = vec![[0f32; 2]; width * height];
    let mut colors: Vec<&mut LayerImage> = layers
        .layers
        .iter_mut()
        .filter(|l| l.name == FINAL_IMAGE || l.name == FINAL_IMAGE_NO_DYNAMIC_SHADOWS)
        .collect();
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
                for layer in colors.iter_mut() {
                    let c = &mut layer.data[pixel * 3..pixel * 3 + 3];
                    for (channel, own) in c.iter_mut().zip(s.color.to_array()) {
                        *channel = a * own + (1.0 - a) * *channel;
                    }
                }
                coverage[pixel] = a + (1.0 - a) * coverage[pixel];
                let m = &mut weighted_motion[pixel];
                m[0] = a * s.motion[0] + (1.0 - a) * m[0];
                m[1] = a * s.motion[1] + (1.0 - a) * m[1];
            }
        }
    }
    // The view-dependent part of the colour is hidden as much as the rest of it.
    if let Some(specular) = layers.get_mut(SPECULAR_LIGHT) {
        for (pixel, c) in specular.data.chunks_mut(3).enumerate() {
            c.iter_mut().for_each(|v| *v *= 1.0 - coverage[pixel]);
        }
    }
    let motion = weighted_motion
        .iter()
        .zip(&coverage)
        .flat_map(|(m, &a)| {
            if a > 0.0 {
                [m[0] / a, m[1] / a]
            } else {
                [0.0; 2]
            }
        })
        .collect();
    let layer = |name: &str, channels: &[&str], data| LayerImage {
        name: name.to_owned(),
        channels: channels.iter().map(|c| (*c).to_owned()).collect(),
        width,
        height,
        data,
    };
    layers
        .layers
        .push(layer(TRANSLUCENCY_MASK, &["R"], coverage));
    layers
        .layers
        .push(layer(TRANSLUCENCY_MOTION, &["R", "G"], motion));
}
