//! A dataset's frames as the plain-Rust reference's images, for the commands that run the
//! reference beside the plugin or instead of it.

use patchex::abi::{PatchexCamera, PATCHEX_DEPTH_LINEAR_VIEW_Z, PATCHEX_NORMAL_SIGNED};
use patchex::camera::Camera;
use patchex::reference::{FrameInputs, Image};
use patchex_scene::dataset::{
    Dataset, BASE_COLOR, CUSTOM_STENCIL, FINAL_IMAGE, FINAL_IMAGE_NO_DYNAMIC_SHADOWS,
    FINAL_IMAGE_OPAQUE, METALLIC, MOTION_VECTOR, ROUGHNESS, SCENE_DEPTH, SHADOW_MASK, SPECULAR,
    STATIC_SHADOW_MASK, TRANSLUCENCY_MASK, TRANSLUCENCY_MOTION, WORLD_NORMAL,
};
use patchex_scene::FrameLayers;

/// One instant's layers as the reference's images.
pub struct Frame {
    pub color: Image,
    pub base_color: Image,
    pub material: Image,
    pub depth: Image,
    pub normal: Image,
    pub stencil: Image,
    pub motion: Image,
    pub camera: Camera,
    /// The shadow input an engine would give: its mask and the colour without the dynamic
    /// objects' shadows.
    pub shadow_mask: Image,
    pub color_without_dynamic_shadows: Image,
    /// The sun's visibility through every caster (`PatchexSunLight.visibility` without a
    /// shadow input).
    pub sun_visibility: Image,
    /// In a scene with particles, the translucency input an engine would give.
    pub translucency: Option<Translucency>,
}

/// A frame's `PatchexTranslucencyInput`.
pub struct Translucency {
    pub mask: Image,
    pub motion: Image,
    /// The lit colour before the translucency pass.
    pub opaque_color: Image,
}

fn gather(layers: &FrameLayers, names: &[(&str, usize)]) -> Image {
    Image::from_fn(layers.width, layers.height, names.len(), |x, y| {
        names
            .iter()
            .map(|(name, channel)| layers.layer(name).value(x, y, *channel))
            .collect()
    })
}

fn rgb1(layers: &FrameLayers, name: &str) -> Image {
    Image::from_fn(layers.width, layers.height, 4, |x, y| {
        let p = layers.layer(name).pixel(x, y);
        vec![p[0], p[1], p[2], 1.0]
    })
}

/// Frame `index` of `dataset`, read from its file.
pub fn frame(dataset: &Dataset, index: usize) -> Result<Frame, Box<dyn std::error::Error>> {
    from_layers(&dataset.read_frame(index)?, dataset, index)
}

/// Frame `index` of `dataset` from its `layers`, already read.
pub fn from_layers(
    layers: &FrameLayers,
    dataset: &Dataset,
    index: usize,
) -> Result<Frame, Box<dyn std::error::Error>> {
    let info = &dataset.manifest.frames[index];
    let camera = PatchexCamera {
        view: info.view,
        projection: info.proj,
        jitter: [0.0, 0.0],
        near_plane: dataset.manifest.near,
        far_plane: dataset.manifest.far,
        depth_convention: PATCHEX_DEPTH_LINEAR_VIEW_Z,
    };
    Ok(Frame {
        color: rgb1(layers, FINAL_IMAGE),
        base_color: rgb1(layers, BASE_COLOR),
        material: gather(layers, &[(METALLIC, 0), (SPECULAR, 0), (ROUGHNESS, 0)]),
        depth: gather(layers, &[(SCENE_DEPTH, 0)]),
        normal: rgb1(layers, WORLD_NORMAL),
        stencil: gather(layers, &[(CUSTOM_STENCIL, 0)]),
        motion: gather(layers, &[(MOTION_VECTOR, 0), (MOTION_VECTOR, 1)]),
        camera: Camera::from_abi(&camera, "dataset camera")?,
        shadow_mask: gather(layers, &[(SHADOW_MASK, 0)]),
        color_without_dynamic_shadows: rgb1(layers, FINAL_IMAGE_NO_DYNAMIC_SHADOWS),
        sun_visibility: Image::from_fn(layers.width, layers.height, 1, |x, y| {
            let through = |name| layers.layer(name).value(x, y, 0);
            vec![through(STATIC_SHADOW_MASK) * through(SHADOW_MASK)]
        }),
        translucency: layers
            .get(TRANSLUCENCY_MASK)
            .is_some()
            .then(|| Translucency {
                mask: gather(layers, &[(TRANSLUCENCY_MASK, 0)]),
                motion: gather(
                    layers,
                    &[(TRANSLUCENCY_MOTION, 0), (TRANSLUCENCY_MOTION, 1)],
                ),
                opaque_color: rgb1(layers, FINAL_IMAGE_OPAQUE),
            }),
    })
}

pub fn inputs(frame: &Frame) -> FrameInputs<'_> {
    FrameInputs {
        color: Some(&frame.color),
        base_color: &frame.base_color,
        material: Some(&frame.material),
        depth: &frame.depth,
        normal: &frame.normal,
        stencil: Some(&frame.stencil),
        motion: Some(&frame.motion),
        camera: &frame.camera,
        normal_encoding: PATCHEX_NORMAL_SIGNED,
        motion_vector_scale: [1.0, 1.0],
        sun: None,
        sky: None,
        translucency: None,
    }
}
