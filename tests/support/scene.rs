//! A small analytic scene ray-cast on the CPU: a textured sphere (a dynamic object, stencil 1)
//! moving over a checkered ground plane and casting a soft sun shadow on it, under a moving
//! camera. It produces every G-buffer the
//! plugin reads, mutually consistent by construction, at any instant and any size, so tests can
//! run real two-frame cases without a renderer.

use glam::camera::rh::proj::vulkan;
use glam::camera::rh::view::look_at_mat4;
use glam::{Mat4, Vec2, Vec3, Vec4, Vec4Swizzles};
use patchex::abi::*;
use patchex::reference::Image;

pub struct Scene {
    pub width: usize,
    pub height: usize,
    pub depth_convention: PatchexDepthConvention,
    /// Metres per second of the sphere along +x.
    pub sphere_speed: f32,
    /// Metres per second of the camera along +x.
    pub camera_speed: f32,
    /// Radians the camera's look direction is turned about the vertical (a cut when large).
    pub camera_turn: f32,
    /// Direction towards the sun.
    pub sun: Vec3,
    /// Whether the sphere casts a shadow on the ground (off: the mask is 1 everywhere).
    pub casts_shadow: bool,
}

/// One instant's G-buffers, as an engine would hand them over.
#[derive(Clone)]
pub struct Frame {
    pub color: Image,
    pub base_color: Image,
    /// R metallic, G specular, B roughness, A unused.
    pub material: Image,
    pub depth: Image,
    /// Unit world normals in RGB (signed), A unused.
    pub normal: Image,
    pub stencil: Image,
    /// Backward motion to the `previous` instant, in pixels, excluding jitter.
    pub motion: Image,
    pub camera: PatchexCamera,
    /// The sun's visibility through the sphere (the dynamic caster), 1 channel.
    pub shadow_mask: Image,
    pub color_without_dynamic_shadows: Image,
    /// The sun's visibility through every caster (`PatchexSunLight.visibility`), 1 channel.
    pub sun_visibility: Image,
    /// Through static casters alone (`PatchexSunLight.visibility` with a shadow input).
    pub static_visibility: Image,
    /// Where known, the true motion of the sphere's shadow to the `previous` instant, in pixels:
    /// on the ground, whose shadow moves with the sphere (NaN elsewhere).
    pub shadow_motion: Option<Image>,
}

const NEAR: f32 = 0.1;
const FAR: f32 = 100.0;
const SPHERE_RADIUS: f32 = 0.7;
const SUN: Vec3 = Vec3::new(0.4, 0.8, 0.45);
/// Width of the shadow's penumbra, as a fraction of the sphere's radius.
const PENUMBRA: f32 = 0.2;

struct Hit {
    position: Vec3,
    normal: Vec3,
    object: u32,
}

impl Scene {
    pub fn new(width: usize, height: usize) -> Self {
        Self {
            width,
            height,
            depth_convention: PATCHEX_DEPTH_HARDWARE,
            sphere_speed: 6.0,
            camera_speed: 1.5,
            camera_turn: 0.0,
            sun: SUN.normalize(),
            casts_shadow: false,
        }
    }

    /// Visibility of the sun from `point` through the sphere: 0 in the umbra, 1 outside, a
    /// smooth penumbra in between.
    fn sun_visibility(&self, time: f32, point: Vec3) -> f32 {
        let to_centre = self.sphere_centre(time) - point;
        let along = to_centre.dot(self.sun);
        if !self.casts_shadow || along <= 0.0 {
            return 1.0;
        }
        let distance = (to_centre - along * self.sun).length() / SPHERE_RADIUS;
        let t = ((distance - (1.0 - PENUMBRA)) / PENUMBRA).clamp(0.0, 1.0);
        t * t * (3.0 - 2.0 * t)
    }

    fn sphere_centre(&self, time: f32) -> Vec3 {
        Vec3::new(-0.6 + self.sphere_speed * time, SPHERE_RADIUS, 0.0)
    }

    fn view(&self, time: f32) -> Mat4 {
        let eye = Vec3::new(self.camera_speed * time, 1.6, 4.0);
        let look = Vec3::new(self.camera_speed * time * 0.5, 0.4, 0.0) - eye;
        let look = glam::Quat::from_rotation_y(self.camera_turn) * look;
        look_at_mat4(eye, eye + look, Vec3::Y)
    }

    /// Vulkan clip space (y down); `jitter` moves the sample positions by that many pixels.
    fn projection(&self, jitter: Vec2) -> Mat4 {
        let aspect = self.width as f32 / self.height as f32;
        let fov = 60f32.to_radians();
        let projection = match self.depth_convention {
            PATCHEX_DEPTH_HARDWARE_REVERSED => {
                vulkan::perspective_infinite_reverse(fov, aspect, NEAR)
            }
            _ => vulkan::perspective(fov, aspect, NEAR, FAR),
        };
        let shift = -2.0 * jitter / Vec2::new(self.width as f32, self.height as f32);
        Mat4::from_translation(shift.extend(0.0)) * projection
    }

    fn camera(&self, time: f32, jitter: Vec2) -> PatchexCamera {
        PatchexCamera {
            view: self.view(time).to_cols_array(),
            projection: self.projection(jitter).to_cols_array(),
            jitter: jitter.into(),
            near_plane: NEAR,
            far_plane: if self.depth_convention == PATCHEX_DEPTH_HARDWARE_REVERSED {
                f32::INFINITY
            } else {
                FAR
            },
            depth_convention: self.depth_convention,
        }
    }

    fn trace(&self, time: f32, origin: Vec3, direction: Vec3) -> Option<Hit> {
        let mut best: Option<(f32, Hit)> = None;
        if direction.y < -1e-6 {
            let t = -origin.y / direction.y;
            let position = origin + t * direction;
            if position.x.abs() < 20.0 && position.z.abs() < 20.0 {
                best = Some((
                    t,
                    Hit {
                        position,
                        normal: Vec3::Y,
                        object: 0,
                    },
                ));
            }
        }
        let oc = origin - self.sphere_centre(time);
        let b = oc.dot(direction);
        let discriminant = b * b - (oc.length_squared() - SPHERE_RADIUS * SPHERE_RADIUS);
        if discriminant > 0.0 {
            let t = -b - discriminant.sqrt();
            if t > 0.0 && best.as_ref().is_none_or(|(best_t, _)| t < *best_t) {
                let position = origin + t * direction;
                let normal = (position - self.sphere_centre(time)).normalize();
                best = Some((
                    t,
                    Hit {
                        position,
                        normal,
                        object: 1,
                    },
                ));
            }
        }
        best.map(|(_, hit)| hit)
    }

    /// Base colour, metallic, specular, roughness of a surface point.
    fn material(&self, time: f32, hit: &Hit) -> (Vec3, f32, f32, f32) {
        if hit.object == 1 {
            // Stripes fixed to the moving sphere.
            let local = hit.position - self.sphere_centre(time);
            let band = ((local.y * 6.0).floor() as i32
                + (local.x.atan2(local.z) * 3.0).floor() as i32)
                .rem_euclid(2);
            let base = if band == 0 {
                Vec3::new(0.85, 0.2, 0.15)
            } else {
                Vec3::new(0.95, 0.85, 0.3)
            };
            (base, 0.2, 0.5, 0.4)
        } else {
            let cell = ((hit.position.x * 2.0).floor() as i32
                + (hit.position.z * 2.0).floor() as i32)
                .rem_euclid(2);
            let grain = 0.05 * (hit.position.x * 17.0).sin() * (hit.position.z * 13.0).cos();
            let base = if cell == 0 {
                Vec3::splat(0.7 + grain)
            } else {
                Vec3::new(0.15, 0.3, 0.2) + grain
            };
            (base, 0.0, 0.5, 0.8)
        }
    }

    /// Renders the instant `time` with sample jitter `jitter`; motion vectors point to `previous`.
    pub fn render(&self, time: f32, jitter: Vec2, previous: f32) -> Frame {
        let (w, h) = (self.width, self.height);
        let view = self.view(time);
        let projection = self.projection(jitter);
        let inverse = (projection * view).inverse();
        let eye = view.inverse().w_axis.xyz();
        let unjittered = self.projection(Vec2::ZERO) * view;
        let previous_unjittered = self.projection(Vec2::ZERO) * self.view(previous);
        let size = Vec2::new(w as f32, h as f32);
        let to_pixels = |clip: Vec4| (clip.xy() / clip.w + 1.0) * 0.5 * size;

        let mut frame = Frame {
            color: Image::new(w, h, 4),
            base_color: Image::new(w, h, 4),
            material: Image::new(w, h, 4),
            depth: Image::new(w, h, 1),
            normal: Image::new(w, h, 4),
            stencil: Image::new(w, h, 1),
            motion: Image::new(w, h, 2),
            camera: self.camera(time, jitter),
            shadow_mask: Image::new(w, h, 1),
            color_without_dynamic_shadows: Image::new(w, h, 4),
            sun_visibility: Image::new(w, h, 1),
            static_visibility: Image::from_fn(w, h, 1, |_, _| vec![1.0]),
            shadow_motion: Some(Image::from_fn(w, h, 2, |_, _| vec![f32::NAN; 2])),
        };
        for y in 0..h {
            for x in 0..w {
                let ndc = (Vec2::new(x as f32, y as f32) + 0.5) / size * 2.0 - 1.0;
                let far_point = inverse * Vec4::new(ndc.x, ndc.y, 0.5, 1.0);
                let direction = (far_point.xyz() / far_point.w - eye).normalize();
                let Some(hit) = self.trace(time, eye, direction) else {
                    let sky = Vec3::new(0.45, 0.6, 0.9);
                    frame.color.set(x, y, &[sky.x, sky.y, sky.z, 1.0]);
                    frame
                        .color_without_dynamic_shadows
                        .set(x, y, &[sky.x, sky.y, sky.z, 1.0]);
                    frame.shadow_mask.set(x, y, &[1.0]);
                    frame.base_color.set(x, y, &[1.0, 1.0, 1.0, 1.0]);
                    frame.material.set(x, y, &[0.0, 0.0, 1.0, 0.0]);
                    let sky_depth = match self.depth_convention {
                        PATCHEX_DEPTH_LINEAR_VIEW_Z => FAR,
                        PATCHEX_DEPTH_HARDWARE_REVERSED => 0.0,
                        _ => 1.0,
                    };
                    frame.depth.set(x, y, &[sky_depth]);
                    // The sky moves with the camera's rotation only; here the view barely turns.
                    frame.motion.set(x, y, &[0.0, 0.0]);
                    continue;
                };
                let (base, metallic, specular, roughness) = self.material(time, &hit);
                let sun = 0.9 * hit.normal.dot(self.sun).max(0.0);
                let visibility = if hit.object == 0 {
                    self.sun_visibility(time, hit.position)
                } else {
                    1.0
                };
                let modulation = base + Vec3::splat(0.08 * specular * (1.0 - metallic));
                let color = modulation * (0.25 + sun * visibility);
                let unshadowed = modulation * (0.25 + sun);
                frame.color.set(x, y, &[color.x, color.y, color.z, 1.0]);
                frame.color_without_dynamic_shadows.set(
                    x,
                    y,
                    &[unshadowed.x, unshadowed.y, unshadowed.z, 1.0],
                );
                frame.shadow_mask.set(x, y, &[visibility]);
                frame.base_color.set(x, y, &[base.x, base.y, base.z, 1.0]);
                frame
                    .material
                    .set(x, y, &[metallic, specular, roughness, 0.0]);
                frame
                    .normal
                    .set(x, y, &[hit.normal.x, hit.normal.y, hit.normal.z, 0.0]);
                frame.stencil.set(x, y, &[hit.object as f32]);
                let clip = projection * view * hit.position.extend(1.0);
                let depth = match self.depth_convention {
                    PATCHEX_DEPTH_LINEAR_VIEW_Z => -(view * hit.position.extend(1.0)).z,
                    _ => clip.z / clip.w,
                };
                frame.depth.set(x, y, &[depth]);
                // The sphere moves along x; on the ground, so does its shadow.
                let sphere_shift = Vec3::X * self.sphere_speed * (time - previous);
                let here = to_pixels(unjittered * hit.position.extend(1.0));
                let earlier = if hit.object == 1 {
                    hit.position - sphere_shift
                } else {
                    hit.position
                };
                let motion = to_pixels(previous_unjittered * earlier.extend(1.0)) - here;
                frame.motion.set(x, y, &[motion.x, motion.y]);
                if hit.object == 0 {
                    let shadow_earlier = hit.position - sphere_shift;
                    let shadow_motion =
                        to_pixels(previous_unjittered * shadow_earlier.extend(1.0)) - here;
                    if let Some(truth) = &mut frame.shadow_motion {
                        truth.set(x, y, &[shadow_motion.x, shadow_motion.y]);
                    }
                }
            }
        }
        // The sphere is the only caster.
        frame.sun_visibility = frame.shadow_mask.clone();
        frame
    }
}
