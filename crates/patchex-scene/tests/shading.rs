//! Final colour against an independent CPU evaluation of the lighting model from the frame's
//! own G-buffers: scene `shading` (one character on a flat plane, so the only shadow casters
//! are dynamic and the ShadowMask is the whole sun visibility).

mod common;

use common::{render, HEIGHT, WIDTH};
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

#[test]
fn final_colour_equals_the_lighting_of_the_gbuffers() {
    let sequence = render("shading.toml", 2);
    let world = &sequence.world;
    assert!(
        world.materials.iter().all(|m| m.emissive == Vec3::ZERO),
        "the oracle has no emissive term"
    );
    let sky = &world.description.sun;
    let lighting = Lighting {
        sun_direction: world.sun.direction,
        sun_radiance: world.sun.radiance,
        sky_zenith: Vec3::from(sky.sky_zenith),
        sky_horizon: Vec3::from(sky.sky_horizon),
        ground_ambient: Vec3::from(sky.ground_ambient),
    };
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
