//! Cross-checks of the G-buffers of rendered frames against each other and against the
//! camera matrices in the manifest: scene `crossing` (orbiting camera, two walking characters).

mod common;

use common::{project, render, RenderedSequence, HEIGHT, WIDTH};
use glam::{Vec2, Vec3};
use patchex_scene::dataset::*;
use patchex_scene::{FrameRequest, Renderer, World};
use std::sync::OnceLock;

const FRAMES: usize = 4;

fn crossing() -> &'static RenderedSequence {
    static SEQUENCE: OnceLock<RenderedSequence> = OnceLock::new();
    SEQUENCE.get_or_init(|| render("crossing.toml", FRAMES))
}

fn vec3(layer: &LayerImage, x: usize, y: usize) -> Vec3 {
    Vec3::from_slice(layer.pixel(x, y))
}

fn pixels() -> impl Iterator<Item = (usize, usize)> {
    (0..HEIGHT as usize).flat_map(|y| (0..WIDTH as usize).map(move |x| (x, y)))
}

#[test]
fn world_position_agrees_with_depth_and_camera_matrices() {
    let sequence = crossing();
    let far = sequence.dataset.manifest.far;
    for info in &sequence.dataset.manifest.frames {
        let frame = sequence.dataset.read_frame(info.index).unwrap();
        let (position, depth) = (frame.layer(WORLD_POSITION), frame.layer(SCENE_DEPTH));
        let camera = Vec3::from(info.camera_position);
        let mut geometry_pixels = 0;
        for (x, y) in pixels() {
            let world = vec3(position, x, y);
            let center = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
            let projected = project(info.view_proj_matrix(), world);
            assert!(
                projected.distance(center) < 0.02,
                "frame {} pixel ({x},{y}): world position projects to {projected}",
                info.index
            );
            let d = depth.value(x, y, 0);
            if d >= far {
                assert!(
                    ((world - camera).length() - far).abs() < far * 1e-4,
                    "sky point not at far"
                );
            } else {
                geometry_pixels += 1;
                let view_depth = -info.view_matrix().transform_point3(world).z;
                assert!(
                    (view_depth - d).abs() <= 1e-4 * d.max(1.0),
                    "frame {} pixel ({x},{y}): depth {d} but view-space depth {view_depth}",
                    info.index
                );
            }
        }
        assert!(
            geometry_pixels > (WIDTH * HEIGHT / 2) as usize,
            "the scene fills the view"
        );
    }
}

#[test]
fn motion_vectors_reproject_onto_the_previous_frame() {
    let sequence = crossing();
    let manifest = &sequence.dataset.manifest;
    let first = sequence.dataset.read_frame(0).unwrap();
    assert!(
        first.layer(MOTION_VECTOR).data.iter().all(|&m| m == 0.0),
        "frame 0 has no motion"
    );

    for k in 1..FRAMES {
        let before = &manifest.frames[k - 1];
        let current = sequence.dataset.read_frame(k).unwrap();
        let previous = sequence.dataset.read_frame(k - 1).unwrap();
        let motion = current.layer(MOTION_VECTOR);
        let stencil = current.layer(CUSTOM_STENCIL);
        let position = current.layer(WORLD_POSITION);
        let previous_position = previous.layer(WORLD_POSITION);
        let previous_depth = previous.layer(SCENE_DEPTH);
        let previous_stencil = previous.layer(CUSTOM_STENCIL);
        let (mut visible, mut static_pixels, mut position_errors) = (0, 0, Vec::new());
        let (mut dynamic_pixels, mut dynamic_same_object, mut dynamic_own_motion) = (0, 0, 0);
        for (x, y) in pixels() {
            let center = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
            let landing = center + Vec2::from_slice(motion.pixel(x, y));
            let world = vec3(position, x, y);
            let camera_only = project(before.view_proj_matrix(), world);
            let inside = landing.x >= 0.0
                && landing.y >= 0.0
                && landing.x < WIDTH as f32
                && landing.y < HEIGHT as f32;
            let (lx, ly) = (landing.x as usize, landing.y as usize);
            let id = stencil.value(x, y, 0);
            if id == 0.0 {
                // Static surfaces (and the sky) move with the camera only.
                assert!(
                    landing.distance(camera_only) < 0.05,
                    "frame {k} pixel ({x},{y}): motion lands on {landing}, camera says {camera_only}"
                );
                let sky = current.layer(SCENE_DEPTH).value(x, y, 0) >= manifest.far;
                if sky || !inside {
                    continue;
                }
                static_pixels += 1;
                // Visible in both frames when the previous depth there matches this point's.
                let expected_depth = -before.view_matrix().transform_point3(world).z;
                if (previous_depth.value(lx, ly, 0) - expected_depth).abs() < 0.05 * expected_depth
                {
                    visible += 1;
                    let error = (vec3(previous_position, lx, ly) - world).length() / expected_depth;
                    position_errors.push(error);
                }
            } else {
                dynamic_pixels += 1;
                if inside && previous_stencil.value(lx, ly, 0) == id {
                    dynamic_same_object += 1;
                }
                if landing.distance(camera_only) > 0.1 {
                    dynamic_own_motion += 1;
                }
            }
        }
        assert!(
            visible as f32 > 0.8 * static_pixels as f32,
            "frame {k}: {visible} of {static_pixels} stay visible"
        );
        position_errors.sort_by(f32::total_cmp);
        // Nearest-pixel lookup: within about one pixel footprint (relative to depth) for 95%.
        let p95 = position_errors[position_errors.len() * 95 / 100];
        let footprint = 2.0 * (55f32.to_radians() * 0.5).tan() / HEIGHT as f32;
        assert!(
            p95 < 1.5 * footprint,
            "frame {k}: 95th percentile world-position error {p95} (relative)"
        );
        assert!(dynamic_pixels > 50, "frame {k}: the characters are in view");
        assert!(
            dynamic_same_object as f32 > 0.85 * dynamic_pixels as f32,
            "frame {k}: {dynamic_same_object} of {dynamic_pixels} character pixels land on the same character"
        );
        assert!(
            dynamic_own_motion as f32 > 0.5 * dynamic_pixels as f32,
            "frame {k}: character motion vectors include the characters' own motion"
        );
    }
}

#[test]
fn stencil_covers_exactly_the_characters() {
    let sequence = crossing();
    let mut description = sequence.world.description.clone();
    description.character.clear();
    let empty = World::from_description(description, &common::assets_dir()).unwrap();
    let gpu = common::validated_gpu();
    let mut renderer = Renderer::new(&gpu, &empty, WIDTH, HEIGHT).unwrap();
    for info in &sequence.dataset.manifest.frames {
        let with_characters = sequence.dataset.read_frame(info.index).unwrap();
        let request = FrameRequest::at(
            &empty,
            info.time,
            info.time,
            WIDTH as f32 / HEIGHT as f32,
            false,
        );
        let without = renderer.render(&empty, &request).unwrap();
        let (stencil, depth) = (
            with_characters.layer(CUSTOM_STENCIL),
            with_characters.layer(SCENE_DEPTH),
        );
        let static_depth = without.layer(SCENE_DEPTH);
        let mut ids_seen = std::collections::BTreeSet::new();
        for (x, y) in pixels() {
            let id = stencil.value(x, y, 0);
            let character_in_front = depth.value(x, y, 0) < static_depth.value(x, y, 0);
            assert_eq!(
                id != 0.0,
                character_in_front,
                "frame {} pixel ({x},{y}): stencil {id}, depth {} vs {} without characters",
                info.index,
                depth.value(x, y, 0),
                static_depth.value(x, y, 0)
            );
            assert_eq!(id, id.round(), "stencil ids are integers");
            if id != 0.0 {
                ids_seen.insert(id as u32);
            }
        }
        let expected: Vec<u32> = sequence
            .dataset
            .manifest
            .dynamic_objects
            .iter()
            .map(|o| o.stencil)
            .collect();
        assert_eq!(
            ids_seen.into_iter().collect::<Vec<_>>(),
            expected,
            "every character is in view"
        );
    }
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn normals_are_unit_length_and_face_the_camera() {
    let sequence = crossing();
    let frame = sequence.dataset.read_frame(1).unwrap();
    let (normal, nov, position) = (
        frame.layer(WORLD_NORMAL),
        frame.layer(NOV),
        frame.layer(WORLD_POSITION),
    );
    let camera = Vec3::from(sequence.dataset.manifest.frames[1].camera_position);
    for (x, y) in pixels() {
        let n = vec3(normal, x, y);
        assert!(
            (n.length() - 1.0).abs() < 1e-3,
            "pixel ({x},{y}): |n| = {}",
            n.length()
        );
        let expected = n
            .dot((camera - vec3(position, x, y)).normalize())
            .clamp(0.0, 1.0);
        assert!(
            (nov.value(x, y, 0) - expected).abs() < 1e-3,
            "pixel ({x},{y}): NoV"
        );
    }
    let facing = nov.data.iter().filter(|&&v| v > 0.05).count();
    assert!(
        facing as f32 > 0.9 * nov.data.len() as f32,
        "only {facing} pixels face the camera"
    );
}
