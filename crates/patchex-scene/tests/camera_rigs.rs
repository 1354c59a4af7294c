//! Camera rigs of the scene format, evaluated on the CPU.

mod common;

use glam::Vec3;
use patchex_scene::scene::SceneDescription;
use patchex_scene::World;

fn world(camera: &str) -> World {
    let text = format!(
        r#"
        name = "rig"
        [camera]
        {camera}
        [[character]]
        name = "runner"
        asset = "characters/CesiumMan.glb"
        path = [[0.0, 0.0, 0.0], [10.0, 0.0, 0.0]]
        walk_speed = 2.0
        "#
    );
    let description: SceneDescription = toml::from_str(&text).unwrap();
    World::from_description(description, &common::assets_dir()).unwrap()
}

/// Unit forward vector of a view matrix (the camera looks down -z).
fn forward(view: glam::Mat4) -> Vec3 {
    -view.inverse().z_axis.truncate().normalize()
}

#[test]
fn follow_camera_keeps_its_offset_behind_the_character_and_looks_at_it() {
    let world = world(
        r#"kind = "follow"
        character = "runner"
        offset = [0.0, 2.0, -4.0]
        look_height = 1.0"#,
    );
    for time in [0.5f32, 2.0] {
        let camera = world.camera(time, 16.0 / 9.0);
        // Walking along +x at 2 m/s: "behind" is -x.
        let character = Vec3::new(2.0 * time, 0.0, 0.0);
        assert!(
            camera
                .position
                .abs_diff_eq(character + Vec3::new(-4.0, 2.0, 0.0), 1e-4),
            "{}",
            camera.position
        );
        let to_target = (character + Vec3::Y - camera.position).normalize();
        assert!(forward(camera.view).abs_diff_eq(to_target, 1e-4));
    }
}

#[test]
fn orbit_camera_circles_its_centre_at_the_given_rate() {
    let world = world(
        r#"kind = "orbit"
        center = [1.0, 1.0, 0.0]
        radius = 5.0
        height = 2.0
        degrees_per_second = 90.0"#,
    );
    let start = world.camera(0.0, 1.0).position;
    let quarter = world.camera(1.0, 1.0).position;
    assert!(start.abs_diff_eq(Vec3::new(6.0, 3.0, 0.0), 1e-4), "{start}");
    assert!(
        quarter.abs_diff_eq(Vec3::new(1.0, 3.0, 5.0), 1e-4),
        "{quarter}"
    );
}

#[test]
fn dolly_moves_along_its_path_and_shake_is_small_and_repeatable() {
    let rig = r#"kind = "dolly"
        path = [[0.0, 1.5, 5.0], [4.0, 1.5, 5.0]]
        speed = 1.0
        target = [0.0, 1.0, 0.0]"#;
    let steady = world(rig);
    assert!(steady
        .camera(1.5, 1.0)
        .position
        .abs_diff_eq(Vec3::new(1.5, 1.5, 5.0), 1e-4));
    let shaky = world(&format!(
        "{rig}\nshake = {{ amplitude = 0.05, frequency = 2.0 }}"
    ));
    let mut largest = 0.0f32;
    for i in 0..50 {
        let t = i as f32 * 0.05;
        let offset = shaky.camera(t, 1.0).position - steady.camera(t, 1.0).position;
        largest = largest.max(offset.length());
        assert_eq!(shaky.camera(t, 1.0), shaky.camera(t, 1.0));
    }
    assert!(
        largest > 0.01 && largest < 0.05 * 3.0,
        "shake offset {largest}"
    );
}
