//! The dataset contract: manifest contents, file names, byte-identical re-renders, the reader
//! returning exactly what was rendered, and the G-buffer-only mode.

mod common;

use common::{render, validated_gpu, HEIGHT, WIDTH};
use patchex_scene::dataset::*;
use patchex_scene::{FrameRequest, Renderer};

#[test]
fn manifest_follows_the_contract() {
    let sequence = render("crossing.toml", 3);
    let manifest = &sequence.dataset.manifest;
    assert_eq!(
        (manifest.width, manifest.height),
        (WIDTH as usize, HEIGHT as usize)
    );
    assert_eq!(manifest.scene, "test_crossing");
    assert_eq!(manifest.fps, 30.0);
    assert_eq!(manifest.frames.len(), 3);
    let roles: Vec<FrameRole> = manifest.frames.iter().map(|f| f.role).collect();
    assert_eq!(
        roles,
        [FrameRole::Rendered, FrameRole::Target, FrameRole::Rendered]
    );
    for (index, frame) in manifest.frames.iter().enumerate() {
        assert_eq!(frame.index, index);
        assert!((frame.time - index as f32 / 30.0).abs() < 1e-6);
        let product = frame.proj_matrix() * frame.view_matrix();
        assert!(product.abs_diff_eq(frame.view_proj_matrix(), 1e-5));
        assert!(sequence
            .dataset
            .frame_path(index)
            .ends_with(format!("frame_{index:04}.exr")));
    }
    let objects: Vec<(u32, &str)> = manifest
        .dynamic_objects
        .iter()
        .map(|o| (o.stencil, o.name.as_str()))
        .collect();
    assert_eq!(objects, [(1, "cesium_man"), (2, "robot")]);
    let expected_layers: Vec<&str> = LAYERS.iter().map(|l| l.name).collect();
    assert_eq!(manifest.layers, expected_layers);

    let frame = sequence.dataset.read_frame(2).unwrap();
    assert_eq!(frame.names(), manifest.layers);
    assert_eq!(frame.layer(MOTION_VECTOR).channels, ["R", "G"]);
    assert!(
        sequence.dataset.read_frame(3).is_err(),
        "reading past the end fails"
    );

    let json: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(sequence.dataset.dir.join("manifest.json")).unwrap(),
    )
    .unwrap();
    for key in [
        "scene",
        "width",
        "height",
        "fps",
        "near",
        "far",
        "frames",
        "dynamic_objects",
        "layers",
    ] {
        assert!(json.get(key).is_some(), "manifest.json lacks {key}");
    }
    assert_eq!(json["frames"][1]["role"], "target");
}

#[test]
fn same_inputs_give_the_same_bytes_and_the_reader_returns_the_render() {
    let first = render("shading.toml", 2);
    let second = render("shading.toml", 2);
    for name in ["manifest.json", "frame_0000.exr", "frame_0001.exr"] {
        let a = std::fs::read(first.dataset.dir.join(name)).unwrap();
        let b = std::fs::read(second.dataset.dir.join(name)).unwrap();
        assert!(a == b, "{name} differs between two renders");
    }

    let gpu = validated_gpu();
    let world = &first.world;
    let mut renderer = Renderer::new(&gpu, world, WIDTH, HEIGHT).unwrap();
    let info = &first.dataset.manifest.frames[1];
    let previous = first.dataset.manifest.frames[0].time;
    let aspect = WIDTH as f32 / HEIGHT as f32;
    let lit = renderer
        .render(
            world,
            &FrameRequest::at(world, info.time, previous, aspect, true),
        )
        .unwrap();
    assert_eq!(
        first.dataset.read_frame(1).unwrap(),
        lit,
        "EXR round trip is exact"
    );
    let timings = renderer.last_timings().expect("lavapipe has timestamps");
    for (pass, ms) in [
        ("shadow", timings.shadow_ms),
        ("G-buffer", timings.gbuffer_ms),
        ("resolve", timings.resolve_ms),
    ] {
        assert!(ms > 0.0 && ms < 10_000.0, "{pass} pass took {ms} ms");
    }

    // G-buffer-only frames skip lighting: no lit layers, every other layer unchanged.
    let unlit = renderer
        .render(
            world,
            &FrameRequest::at(world, info.time, previous, aspect, false),
        )
        .unwrap();
    assert!(
        unlit.get(FINAL_IMAGE).is_none() && unlit.get(FINAL_IMAGE_NO_DYNAMIC_SHADOWS).is_none()
    );
    for layer in &unlit.layers {
        assert_eq!(
            Some(layer),
            lit.get(&layer.name),
            "{} differs without lighting",
            layer.name
        );
    }
    common::assert_no_validation_messages(&gpu);
}
