//! Shared fixtures of the GPU tests: a validated device, the test scenes, and sequences
//! rendered once per test binary.

#![allow(dead_code)]

use patchex_scene::dataset::{render_sequence, SequenceOptions};
use patchex_scene::{Dataset, Gpu, GpuOptions, World};
use std::path::{Path, PathBuf};
use std::sync::Arc;

pub const WIDTH: u32 = 160;
pub const HEIGHT: u32 = 90;

pub fn assets_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets")
}

pub fn test_scene(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/scenes")
        .join(name)
}

pub fn load_world(scene: &str) -> World {
    World::load(&test_scene(scene), Some(&assets_dir())).expect("test scene loads")
}

/// A device with the Khronos validation layer and synchronization validation on.
pub fn validated_gpu() -> Arc<Gpu> {
    Arc::new(
        Gpu::new(GpuOptions { validation: true })
            .expect("a Vulkan 1.3 device (lavapipe) is available"),
    )
}

pub fn assert_no_validation_messages(gpu: &Gpu) {
    let messages = gpu.take_validation_messages();
    assert!(
        messages.is_empty(),
        "validation messages:\n{}",
        messages.join("\n")
    );
}

/// A rendered sequence in a temporary folder, kept alive with its dataset.
pub struct RenderedSequence {
    pub dataset: Dataset,
    pub world: World,
    _dir: tempfile::TempDir,
}

pub fn render(scene: &str, frames: usize) -> RenderedSequence {
    render_world(load_world(scene), frames)
}

pub fn render_world(world: World, frames: usize) -> RenderedSequence {
    let gpu = validated_gpu();
    let dir = tempfile::tempdir().expect("temporary folder");
    let options = SequenceOptions {
        targets_between: 1,
        frames,
        width: WIDTH,
        height: HEIGHT,
        out_dir: dir.path().to_path_buf(),
    };
    render_sequence(&gpu, &world, &options, &mut |_, _| {}).expect("sequence renders");
    assert_no_validation_messages(&gpu);
    RenderedSequence {
        dataset: Dataset::open(dir.path()).expect("dataset opens"),
        world,
        _dir: dir,
    }
}

/// Pixel centre of (x, y) projected from a world position through `view_proj`.
pub fn project(view_proj: glam::Mat4, world: glam::Vec3) -> glam::Vec2 {
    let clip = view_proj * world.extend(1.0);
    let ndc = glam::Vec2::new(clip.x, clip.y) / clip.w;
    (ndc * 0.5 + 0.5) * glam::Vec2::new(WIDTH as f32, HEIGHT as f32)
}
