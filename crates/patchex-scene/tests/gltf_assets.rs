//! glTF loading and animation of the vendored assets (CPU only).

mod common;

use glam::Vec3;
use patchex_scene::asset::{load_model, ChannelValue, Pose, Property, TextureRole};
use patchex_scene::scene::SceneDescription;
use patchex_scene::World;

#[test]
fn robot_has_named_clips_skins_and_materials() {
    let model = load_model(&common::assets_dir().join("characters/RobotExpressive.glb")).unwrap();
    for clip in ["Dance", "Running", "Walking", "Idle"] {
        assert!(model.animation_index(clip).is_some(), "missing clip {clip}");
    }
    assert_eq!(model.skins.len(), 2);
    assert!(model.materials.len() >= 3);
    let dance = &model.animations[model.animation_index("Dance").unwrap()];
    assert!(
        (dance.duration - 3.33).abs() < 0.01,
        "Dance lasts {}",
        dance.duration
    );
}

#[test]
fn robot_face_morph_targets_load_and_deform_the_head() {
    let mut model =
        load_model(&common::assets_dir().join("characters/RobotExpressive.glb")).unwrap();
    let dance = &model.animations[model.animation_index("Dance").unwrap()];
    let channel = dance
        .channels
        .iter()
        .find(|c| c.property == Property::MorphWeights)
        .expect("Dance has a morph weight channel");
    assert!(
        matches!(channel.sample(1.0), ChannelValue::MorphWeights(ref w) if w.len() == channel.width)
    );
    let node = channel.node;
    let mesh = model.nodes[node]
        .mesh
        .expect("the animated node has a mesh");
    let targets = model.meshes[mesh].primitives[0].morph_targets.len();
    assert_eq!(channel.width, targets, "one weight per morph target");

    // The clips keep the expressions at 0; a weight set on the node deforms the face.
    let pose = |model: &patchex_scene::asset::Model| {
        let mut out = Vec::new();
        Pose::new(model, glam::Mat4::IDENTITY, None).vertices(model, &mut out);
        out
    };
    let neutral = pose(&model);
    let mut weights = vec![0.0; targets];
    weights[0] = 1.0;
    model.nodes[node].weights = Some(weights);
    let expressive = pose(&model);
    let moved = neutral
        .iter()
        .zip(&expressive)
        .filter(|(a, b)| a.position.distance(b.position) > 1e-3)
        .count();
    assert!(moved > 10, "morph target 0 moves {moved} vertices");
}

#[test]
fn textured_assets_load_their_maps_with_the_right_decoding() {
    let terrain = load_model(&common::assets_dir().join("environments/terrain.glb")).unwrap();
    let material = &terrain.materials[0];
    let base = material
        .base_color_texture
        .expect("terrain has a base colour map");
    assert_eq!(terrain.textures[base].role, TextureRole::Color);
    let normal = material.normal_texture.expect("terrain has a normal map");
    assert_eq!(terrain.textures[normal].role, TextureRole::Data);
    let texture = &terrain.textures[base];
    assert_eq!(
        texture.mips[0].len(),
        (texture.width * texture.height * 4) as usize
    );
    assert_eq!(texture.mip_size(texture.mips.len() - 1), (1, 1));
}

#[test]
fn skinned_pose_changes_over_the_clip_and_loops() {
    let model = load_model(&common::assets_dir().join("characters/CesiumMan.glb")).unwrap();
    let clip = 0;
    let duration = model.animations[clip].duration;
    let pose_at = |t: f32| {
        let mut out = Vec::new();
        Pose::new(
            &model,
            glam::Mat4::IDENTITY,
            Some((clip, model.animations[clip].looped_time(t))),
        )
        .vertices(&model, &mut out);
        out
    };
    let (a, b, looped) = (pose_at(0.3), pose_at(0.8), pose_at(0.3 + duration));
    let moved = a
        .iter()
        .zip(&b)
        .filter(|(p, q)| p.position.distance(q.position) > 0.01)
        .count();
    assert!(
        moved > a.len() / 10,
        "only {moved} of {} vertices move",
        a.len()
    );
    for (p, q) in a.iter().zip(&looped) {
        assert!(p.position.distance(q.position) < 1e-4, "the clip loops");
    }
    let height = a.iter().map(|v| v.position.y).fold(f32::MIN, f32::max);
    assert!(
        (1.2..1.8).contains(&height),
        "CesiumMan stands about 1.5 m tall, got {height}"
    );
}

#[test]
fn clip_speed_and_walking_path_drive_the_character() {
    let toml = |speed: f32| {
        format!(
            r#"
            name = "speed"
            [camera]
            kind = "static"
            position = [0.0, 1.0, 5.0]
            target = [0.0, 1.0, 0.0]
            [[character]]
            name = "man"
            asset = "characters/CesiumMan.glb"
            clip = "animation0"
            clip_speed = {speed}
            path = [[0.0, 0.0, 0.0], [10.0, 0.0, 0.0]]
            walk_speed = 2.0
            "#
        )
    };
    let world = |speed: f32| {
        let description: SceneDescription = toml::from_str(&toml(speed)).unwrap();
        World::from_description(description, &common::assets_dir()).unwrap()
    };
    let (normal, double) = (world(1.0), world(2.0));
    // The same pose: double playback speed at t equals normal speed at 2t, once the walk
    // offset (2 m/s) is removed.
    let at = |w: &World, t: f32| w.dynamic_vertices(t, t);
    let (fast, slow) = (at(&double, 0.2), at(&normal, 0.4));
    for (f, s) in fast.iter().zip(&slow) {
        let shift = Vec3::new(0.4, 0.0, 0.0);
        assert!((Vec3::from(f.position) + shift).distance(Vec3::from(s.position)) < 1e-4);
    }
    // Previous positions come from the previous instant.
    let vertices = normal.dynamic_vertices(0.5, 0.25);
    let prev = normal.dynamic_vertices(0.25, 0.25);
    for (v, p) in vertices.iter().zip(&prev) {
        assert_eq!(v.prev_position, p.position);
    }
}

#[test]
fn unknown_clip_names_are_reported_with_the_available_ones() {
    let description: SceneDescription = toml::from_str(
        r#"
        name = "bad"
        [camera]
        kind = "static"
        position = [0.0, 1.0, 5.0]
        target = [0.0, 1.0, 0.0]
        [[character]]
        name = "robot"
        asset = "characters/RobotExpressive.glb"
        clip = "Moonwalk"
        path = [[0.0, 0.0, 0.0]]
        "#,
    )
    .unwrap();
    let error = World::from_description(description, &common::assets_dir())
        .err()
        .expect("fails")
        .to_string();
    assert!(
        error.contains("Moonwalk") && error.contains("Dance"),
        "{error}"
    );
}

/// Files that require KHR_lights_punctual load; their lights are not used (a scene file sets
/// the sun).
#[test]
fn a_file_requiring_punctual_lights_loads() {
    let gltf = r#"{
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensionsRequired": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 10}]}},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [
            {"mesh": 0},
            {"translation": [0, 2, 0], "extensions": {"KHR_lights_punctual": {"light": 0}}}
        ],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "buffers": [{"byteLength": 36,
            "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
            "min": [0, 0, 0], "max": [1, 1, 0]}]
    }"#;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("lit.gltf");
    std::fs::write(&path, gltf).unwrap();
    let model = load_model(&path).expect("a file requiring KHR_lights_punctual loads");
    assert_eq!(model.nodes.len(), 2);
    assert_eq!(model.meshes.len(), 1);
}
