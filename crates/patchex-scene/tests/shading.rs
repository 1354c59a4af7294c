//! Final colour against an independent CPU evaluation of the lighting model from the frame's
//! own G-buffers: scene `shading` (one character on a flat plane, so the only shadow casters
//! are dynamic and the ShadowMask is the whole sun visibility), scene `glass` (the same,
//! partly behind a pane of tinted glass, blended over it by the forward pass) and scene
//! `glass_smoke` (smoke between the pane and the character, seen through the pane).

mod common;

use common::{assets_dir, project, render, render_world, RenderedSequence, HEIGHT, WIDTH};
use glam::Vec3;
use patchex_scene::dataset::*;
use std::f32::consts::PI;

struct Lighting {
    sun_direction: Vec3,
    sun_radiance: Vec3,
    sky_zenith: Vec3,
    sky_horizon: Vec3,
    ground_ambient: Vec3,
}

struct Surface {
    base_color: Vec3,
    metallic: f32,
    specular: f32,
    roughness: f32,
    normal: Vec3,
    to_camera: Vec3,
}

impl Lighting {
    fn sky(&self, direction: Vec3) -> Vec3 {
        self.sky_horizon
            .lerp(self.sky_zenith, direction.y.clamp(0.0, 1.0).sqrt())
    }

    /// Unreal's split: diffuse from BaseColor * (1 - Metallic), specular from
    /// lerp(0.08 * Specular, BaseColor, Metallic); GGX + Smith + Schlick for the sun, a
    /// hemisphere and Karis' environment BRDF fit for the sky.
    /// The lit colour and its view-dependent part (the sun's and sky's specular reflection).
    fn shade(&self, s: &Surface, sun_visibility: f32) -> (Vec3, Vec3) {
        let diffuse_color = s.base_color * (1.0 - s.metallic);
        let specular_color = Vec3::splat(0.08 * s.specular).lerp(s.base_color, s.metallic);
        let n_dot_v = s.normal.dot(s.to_camera).clamp(0.0, 1.0);
        let n_dot_l = s.normal.dot(self.sun_direction).clamp(0.0, 1.0);
        let h = (self.sun_direction + s.to_camera).normalize();
        let n_dot_h = s.normal.dot(h).clamp(0.0, 1.0);
        let v_dot_h = s.to_camera.dot(h).clamp(0.0, 1.0);
        let a2 = s.roughness.powi(4);
        let d = a2 / (PI * (n_dot_h * n_dot_h * (a2 - 1.0) + 1.0).powi(2));
        let nv = n_dot_v.max(1e-4);
        let smith = 0.5
            / (n_dot_l * (nv * nv * (1.0 - a2) + a2).sqrt()
                + nv * (n_dot_l * n_dot_l * (1.0 - a2) + a2).sqrt())
            .max(1e-6);
        let fw = (1.0 - v_dot_h).powi(5);
        let fresnel = specular_color * (1.0 - fw) + Vec3::splat(fw);
        let sun_diffuse = self.sun_radiance * diffuse_color / PI * n_dot_l;
        let sun_specular = self.sun_radiance * d * smith * fresnel * n_dot_l;

        let ambient = self
            .ground_ambient
            .lerp(self.sky_zenith, s.normal.y * 0.5 + 0.5);
        let reflected = (-s.to_camera) - 2.0 * (-s.to_camera).dot(s.normal) * s.normal;
        let r = s.roughness;
        let c = [
            (1.0f32 - r),
            (-0.0275 * r + 0.0425),
            (-0.572 * r + 1.04),
            (0.022 * r - 0.04),
        ];
        let a004 = (c[0] * c[0]).min((-9.28 * n_dot_v).exp2()) * c[0] + c[1];
        let env = specular_color * (-1.04 * a004 + c[2]) + Vec3::splat(1.04 * a004 + c[3]);
        let specular = self.sky(reflected) * env + sun_specular * sun_visibility;
        let total = diffuse_color * ambient + sun_diffuse * sun_visibility + specular;
        (total, specular)
    }
}

impl Lighting {
    fn of(world: &patchex_scene::World) -> Self {
        assert!(
            world.materials.iter().all(|m| m.emissive == Vec3::ZERO),
            "the oracle has no emissive term"
        );
        let sky = &world.description.sun;
        Self {
            sun_direction: world.sun.direction,
            sun_radiance: world.sun.radiance,
            sky_zenith: Vec3::from(sky.sky_zenith),
            sky_horizon: Vec3::from(sky.sky_horizon),
            ground_ambient: Vec3::from(sky.ground_ambient),
        }
    }
}

/// Where a pixel's ray from `camera` to the surface it shows at `position` crosses a pane's plane:
/// the point, whether it is inside the pane (2 cm clear of its edges) or on a side edge, and the
/// pane's lit radiance there.
struct PaneCrossing {
    hit: Vec3,
    inside: bool,
    on_edge: bool,
    radiance: Vec3,
}

impl PaneCrossing {
    fn of(
        glass: &patchex_scene::scene::GlassDescription,
        lighting: &Lighting,
        camera: Vec3,
        position: Vec3,
    ) -> Self {
        let ray = position - camera;
        let t = (glass.position[2] - camera.z) / ray.z;
        let hit = camera + t * ray;
        let in_front = t > 0.0 && t < 1.0;
        let from_side = (hit.x - glass.position[0]).abs() - 0.5 * glass.size[0];
        let to_camera = (camera - hit).normalize();
        let pane = Surface {
            base_color: Vec3::from(glass.color),
            metallic: 0.0,
            specular: 0.5,
            roughness: glass.roughness,
            // Double-sided: the normal faces the viewer.
            normal: Vec3::Z * to_camera.z.signum(),
            to_camera,
        };
        Self {
            hit,
            inside: in_front && from_side < -0.02 && hit.y > glass.position[1] + 0.02,
            on_edge: in_front && from_side.abs() <= 0.02,
            radiance: lighting.shade(&pane, 1.0).0,
        }
    }
}

/// A glass scene's second frame, and the same frame rendered with the scene's panes taken out.
struct GlassFrames {
    sequence: RenderedSequence,
    frame: FrameLayers,
    behind: FrameLayers,
}

impl GlassFrames {
    fn render(scene: &str) -> Self {
        let sequence = render(scene, 2);
        let mut description = sequence.world.description.clone();
        description.glass.clear();
        let without = render_world(
            patchex_scene::World::from_description(description, &assets_dir()).unwrap(),
            2,
        );
        Self {
            frame: sequence.dataset.read_frame(1).unwrap(),
            behind: without.dataset.read_frame(1).unwrap(),
            sequence,
        }
    }
}

/// An RGB layer's value at (x, y).
fn v3(frame: &FrameLayers, name: &str, x: usize, y: usize) -> Vec3 {
    Vec3::from_slice(frame.layer(name).pixel(x, y))
}

#[test]
fn final_colour_equals_the_lighting_of_the_gbuffers() {
    let sequence = render("shading.toml", 2);
    let world = &sequence.world;
    let lighting = Lighting::of(world);
    let info = &sequence.dataset.manifest.frames[1];
    let camera = Vec3::from(info.camera_position);
    let far = sequence.dataset.manifest.far;
    let frame = sequence.dataset.read_frame(1).unwrap();
    let get = |name: &str, x: usize, y: usize| frame.layer(name).pixel(x, y).to_vec();
    let v3 = |name: &str, x: usize, y: usize| Vec3::from_slice(&get(name, x, y));
    let (mut shadowed_ground, mut checked) = (0, 0);
    for y in 0..HEIGHT as usize {
        for x in 0..WIDTH as usize {
            let final_image = v3(FINAL_IMAGE, x, y);
            let unshadowed = v3(FINAL_IMAGE_NO_DYNAMIC_SHADOWS, x, y);
            let position = v3(WORLD_POSITION, x, y);
            if get(SCENE_DEPTH, x, y)[0] >= far {
                let expected = lighting.sky((position - camera).normalize());
                assert!(
                    final_image.abs_diff_eq(expected, 1e-4),
                    "sky pixel ({x},{y})"
                );
                continue;
            }
            let surface = Surface {
                base_color: v3(BASE_COLOR, x, y),
                metallic: get(METALLIC, x, y)[0],
                specular: get(SPECULAR, x, y)[0],
                roughness: get(ROUGHNESS, x, y)[0],
                normal: v3(WORLD_NORMAL, x, y),
                to_camera: (camera - position).normalize(),
            };
            let mask = get(SHADOW_MASK, x, y)[0];
            let (expected, expected_specular) = lighting.shade(&surface, mask);
            let (expected_unshadowed, _) = lighting.shade(&surface, 1.0);
            let specular = v3(SPECULAR_LIGHT, x, y);
            let tolerance = 1e-3 * expected.max_element().max(1.0);
            assert!(
                final_image.abs_diff_eq(expected, tolerance),
                "pixel ({x},{y}): FinalImage {final_image} but the G-buffers give {expected}"
            );
            assert!(
                unshadowed.abs_diff_eq(expected_unshadowed, tolerance),
                "pixel ({x},{y}): FinalImageNoDynamicShadows {unshadowed} but {expected_unshadowed}"
            );
            assert!(
                specular.abs_diff_eq(expected_specular, tolerance),
                "pixel ({x},{y}): SpecularLight {specular} but {expected_specular}"
            );
            checked += 1;
            let on_ground = get(CUSTOM_STENCIL, x, y)[0] == 0.0;
            if on_ground && mask < 0.5 && surface.normal.dot(lighting.sun_direction) > 0.1 {
                shadowed_ground += 1;
                assert!(final_image.element_sum() < unshadowed.element_sum());
            }
        }
    }
    assert!(checked > 1000, "the frame shows geometry");
    assert!(
        shadowed_ground > 20,
        "the character casts a shadow on the ground ({shadowed_ground} pixels)"
    );
}

/// The pane is drawn over the lit surface behind it by its coverage, lit by the same model, and
/// leaves the G-buffer, the shadows and the light behind it as they were (FinalImageOpaque keeps
/// the frame before it); the mask is its
/// coverage, and the translucency's motion is the pane's own, not that of what lies behind it.
#[test]
fn glass_is_blended_over_the_lighting_of_what_lies_behind() {
    let GlassFrames {
        sequence,
        frame,
        behind,
    } = GlassFrames::render("glass.toml");
    let world = &sequence.world;
    let lighting = Lighting::of(world);
    let glass = &world.description.glass[0];
    let opacity = glass.opacity;
    let frames = &sequence.dataset.manifest.frames;
    let camera = Vec3::from(frames[1].camera_position);
    let previous_view_proj = frames[0].view_proj_matrix();
    let (mut covered, mut parallax) = (0, 0);
    for y in 0..HEIGHT as usize {
        for x in 0..WIDTH as usize {
            for layer in [
                WORLD_POSITION,
                WORLD_NORMAL,
                BASE_COLOR,
                MOTION_VECTOR,
                SHADOW_MASK,
            ] {
                assert_eq!(
                    frame.layer(layer).pixel(x, y),
                    behind.layer(layer).pixel(x, y),
                    "{layer} at ({x},{y}): the glass is not in the G-buffer and casts no shadow"
                );
            }
            let mask = frame.layer(TRANSLUCENCY_MASK).pixel(x, y)[0];
            let lit_behind = v3(&behind, FINAL_IMAGE, x, y);
            let final_image = v3(&frame, FINAL_IMAGE, x, y);
            assert_eq!(
                v3(&frame, FINAL_IMAGE_OPAQUE, x, y),
                lit_behind,
                "({x},{y}): FinalImageOpaque is the frame before the pane is drawn"
            );
            let pane = PaneCrossing::of(glass, &lighting, camera, v3(&frame, WORLD_POSITION, x, y));
            if pane.on_edge {
                continue;
            }
            if !pane.inside {
                assert_eq!(mask, 0.0, "({x},{y}) is not behind the pane");
                assert_eq!(final_image, lit_behind, "({x},{y}) is not behind the pane");
                continue;
            }
            covered += 1;
            assert!(
                (mask - opacity).abs() < 1e-6,
                "({x},{y}): mask {mask}, opacity {opacity}"
            );
            let centre = glam::Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
            let pane_motion = project(previous_view_proj, pane.hit) - centre;
            let motion = glam::Vec2::from_slice(frame.layer(TRANSLUCENCY_MOTION).pixel(x, y));
            assert!(
                motion.abs_diff_eq(pane_motion, 0.02),
                "({x},{y}): translucency motion {motion}, the pane's {pane_motion}"
            );
            let surface_motion = glam::Vec2::from_slice(frame.layer(MOTION_VECTOR).pixel(x, y));
            parallax += usize::from(surface_motion.distance(pane_motion) > 0.1);
            let expected = opacity * pane.radiance + (1.0 - opacity) * lit_behind;
            let tolerance = 1e-3 * expected.max_element().max(1.0);
            assert!(
                final_image.abs_diff_eq(expected, tolerance),
                "({x},{y}): FinalImage {final_image}, the pane over the surface gives {expected}"
            );
        }
    }
    assert!(
        covered > 1000,
        "the pane covers part of the frame ({covered} pixels)"
    );
    assert!(
        parallax > 500,
        "what lies behind the pane moves otherwise than the pane ({parallax} pixels)"
    );
}

/// Smoke behind the pane is seen through it: inside the pane the frame is the pane over the
/// frame without the pane (smoke included), and the mask composites the same way.
#[test]
fn particles_beyond_glass_are_seen_through_it() {
    let GlassFrames {
        sequence,
        frame,
        behind,
    } = GlassFrames::render("glass_smoke.toml");
    let world = &sequence.world;
    let lighting = Lighting::of(world);
    let glass = &world.description.glass[0];
    let opacity = glass.opacity;
    let camera = Vec3::from(sequence.dataset.manifest.frames[1].camera_position);
    let mut smoky = 0;
    for y in 0..HEIGHT as usize {
        for x in 0..WIDTH as usize {
            let pane = PaneCrossing::of(glass, &lighting, camera, v3(&frame, WORLD_POSITION, x, y));
            let smoke = behind.layer(TRANSLUCENCY_MASK).pixel(x, y)[0];
            if !pane.inside || smoke < 0.05 {
                continue;
            }
            smoky += 1;
            let expected =
                opacity * pane.radiance + (1.0 - opacity) * v3(&behind, FINAL_IMAGE, x, y);
            let final_image = v3(&frame, FINAL_IMAGE, x, y);
            let tolerance = 1e-3 * expected.max_element().max(1.0);
            assert!(
                final_image.abs_diff_eq(expected, tolerance),
                "({x},{y}): FinalImage {final_image}, the pane over the smoke gives {expected}"
            );
            let mask = frame.layer(TRANSLUCENCY_MASK).pixel(x, y)[0];
            let expected_mask = 1.0 - (1.0 - opacity) * (1.0 - smoke);
            assert!(
                (mask - expected_mask).abs() < 1e-5,
                "({x},{y}): mask {mask}, the pane over the smoke gives {expected_mask}"
            );
        }
    }
    assert!(smoky > 200, "smoke lies behind the pane ({smoky} pixels)");
}
