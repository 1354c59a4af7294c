//! Characters stand on props marked `ground`: their path heights become offsets above it.
//! (The terrain asset covers only about half of its bounding square; the path stays on it.)

mod common;

use glam::Vec3;
use patchex_scene::scene::SceneDescription;
use patchex_scene::World;

fn terrain_world(ground: bool) -> World {
    let text = format!(
        r#"
        name = "hills"
        [camera]
        kind = "static"
        position = [0.0, 3.0, 8.0]
        target = [0.0, 0.0, 0.0]
        [[environment]]
        asset = "environments/terrain.glb"
        ground = {ground}
        position = [0.0, -0.5, 0.0]
        scale = 4.0
        [[character]]
        name = "man"
        asset = "characters/CesiumMan.glb"
        path = [[-10.0, 0.0, 4.0], [-2.0, 0.0, 12.0]]
        walk_speed = 1.5
        "#
    );
    let description: SceneDescription = toml::from_str(&text).unwrap();
    World::from_description(description, &common::assets_dir()).unwrap()
}

#[test]
fn characters_walk_on_the_terrain_surface() {
    let world = terrain_world(true);
    let ground = world.ground.as_ref().expect("the terrain is ground");
    let mut heights = Vec::new();
    for step in 0..8 {
        let time = step as f32;
        let root = world
            .character_transform(&world.characters[0], time)
            .w_axis
            .truncate();
        let surface = ground
            .height_at(root.x, root.z)
            .unwrap_or_else(|| panic!("t = {time}: {root} is not over the terrain"));
        assert!(
            (root.y - surface).abs() < 1e-5,
            "t = {time}: root {root} over ground {surface}"
        );
        // CesiumMan's rest pose starts at its root, so the feet touch the surface.
        let feet = world
            .dynamic_vertices(time, time)
            .iter()
            .map(|v| Vec3::from(v.position).y)
            .fold(f32::MAX, f32::min);
        assert!(
            (feet - surface).abs() < 0.1,
            "t = {time}: feet at {feet}, ground at {surface}"
        );
        heights.push(surface);
    }
    let (low, high) = heights
        .iter()
        .fold((f32::MAX, f32::MIN), |(l, h), &y| (l.min(y), h.max(y)));
    assert!(
        high - low > 0.1,
        "the walk crosses uneven ground ({low}..{high})"
    );
}

#[test]
fn without_ground_props_paths_keep_their_heights() {
    let world = terrain_world(false);
    assert!(world.ground.is_none());
    let root = world
        .character_transform(&world.characters[0], 2.0)
        .w_axis
        .truncate();
    assert_eq!(root.y, 0.0);
}
