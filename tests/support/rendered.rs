//! Frames made by the project's scene renderer (`crates/patchex-scene`), as the tests' `Frame`:
//! real characters, skinning, textures and shadows, at a small size.

use std::path::Path;
use std::sync::Arc;

use patchex::abi::*;
use patchex::reference::Image;
use patchex_scene::dataset::{
    render_sequence, SequenceOptions, BASE_COLOR, CUSTOM_STENCIL, FINAL_IMAGE,
    FINAL_IMAGE_NO_DYNAMIC_SHADOWS, FINAL_IMAGE_OPAQUE, METALLIC, MOTION_VECTOR, ROUGHNESS,
    SCENE_DEPTH, SHADOW_MASK, SPECULAR, STATIC_SHADOW_MASK, TRANSLUCENCY_MASK, TRANSLUCENCY_MOTION,
    WORLD_NORMAL,
};
use patchex_scene::{Dataset, FrameLayers, Gpu, GpuOptions, Manifest, World};

use super::scene::Frame;

pub struct RenderedSequence {
    pub manifest: Manifest,
    pub frames: Vec<Frame>,
    /// Each frame's translucency, in a scene that draws translucency.
    pub translucency: Vec<Option<Translucency>>,
}

/// A frame's `PatchexTranslucencyInput`, as the renderer writes it.
#[derive(Clone)]
pub struct Translucency {
    /// Coverage, 1 channel.
    pub mask: Image,
    /// The translucency's own motion, 2 channels.
    pub motion: Image,
    /// The lit colour before the translucency is drawn, RGBA.
    pub opaque_color: Image,
}

/// The repository's assets folder.
pub fn assets_dir() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("assets")
}

/// The world of `scenes/<scene_file>`.
pub fn load(scene_file: &str) -> World {
    let repo = Path::new(env!("CARGO_MANIFEST_DIR"));
    World::load(&repo.join("scenes").join(scene_file), None).expect("scene loads")
}

/// Renders `frames` frames of `scenes/<scene_file>` at `width` x `height` under validation.
pub fn render(scene_file: &str, frames: usize, width: u32, height: u32) -> RenderedSequence {
    render_world(&load(scene_file), frames, width, height)
}

/// Renders `frames` frames of `world` at `width` x `height` under validation.
pub fn render_world(world: &World, frames: usize, width: u32, height: u32) -> RenderedSequence {
    let gpu = Arc::new(Gpu::new(GpuOptions { validation: true }).expect("renderer device"));
    let dir = tempfile::tempdir().expect("temporary folder");
    let options = SequenceOptions {
        targets_between: 1,
        frames,
        width,
        height,
        out_dir: dir.path().to_path_buf(),
    };
    render_sequence(&gpu, world, &options, &mut |_, _| {}).expect("scene renders");
    let messages = gpu.take_validation_messages();
    assert!(messages.is_empty(), "renderer validation: {messages:?}");
    let dataset = Dataset::open(dir.path()).expect("dataset opens");
    let (frames, translucency) = (0..frames)
        .map(|index| {
            let layers = dataset.read_frame(index).expect("frame reads");
            let translucency = layers
                .get(TRANSLUCENCY_MASK)
                .is_some()
                .then(|| Translucency {
                    mask: gather(&layers, &[(TRANSLUCENCY_MASK, 0)]),
                    motion: gather(
                        &layers,
                        &[(TRANSLUCENCY_MOTION, 0), (TRANSLUCENCY_MOTION, 1)],
                    ),
                    opaque_color: rgba(&layers, FINAL_IMAGE_OPAQUE),
                });
            (frame(&layers, &dataset.manifest, index), translucency)
        })
        .unzip();
    RenderedSequence {
        manifest: dataset.manifest,
        frames,
        translucency,
    }
}

/// Channels of `names` (layer, channel) gathered into one image.
fn gather(layers: &FrameLayers, names: &[(&str, usize)]) -> Image {
    Image::from_fn(layers.width, layers.height, names.len(), |x, y| {
        names
            .iter()
            .map(|(name, channel)| layers.layer(name).value(x, y, *channel))
            .collect()
    })
}

fn rgba(layers: &FrameLayers, name: &str) -> Image {
    let mut image = gather(layers, &[(name, 0), (name, 1), (name, 2), (name, 0)]);
    for pixel in image.data.chunks_mut(4) {
        pixel[3] = 1.0;
    }
    image
}

fn frame(layers: &FrameLayers, manifest: &Manifest, index: usize) -> Frame {
    let info = &manifest.frames[index];
    Frame {
        color: rgba(layers, FINAL_IMAGE),
        base_color: rgba(layers, BASE_COLOR),
        material: gather(
            layers,
            &[(METALLIC, 0), (SPECULAR, 0), (ROUGHNESS, 0), (ROUGHNESS, 0)],
        ),
        depth: gather(layers, &[(SCENE_DEPTH, 0)]),
        normal: rgba(layers, WORLD_NORMAL),
        stencil: gather(layers, &[(CUSTOM_STENCIL, 0)]),
        motion: gather(layers, &[(MOTION_VECTOR, 0), (MOTION_VECTOR, 1)]),
        camera: PatchexCamera {
            view: info.view,
            projection: info.proj,
            jitter: [0.0, 0.0],
            near_plane: manifest.near,
            far_plane: manifest.far,
            depth_convention: PATCHEX_DEPTH_LINEAR_VIEW_Z,
        },
        shadow_mask: gather(layers, &[(SHADOW_MASK, 0)]),
        color_without_dynamic_shadows: rgba(layers, FINAL_IMAGE_NO_DYNAMIC_SHADOWS),
        sun_visibility: Image::from_fn(layers.width, layers.height, 1, |x, y| {
            let through = |name| layers.layer(name).value(x, y, 0);
            vec![through(STATIC_SHADOW_MASK) * through(SHADOW_MASK)]
        }),
        static_visibility: gather(layers, &[(STATIC_SHADOW_MASK, 0)]),
        shadow_motion: None,
    }
}
