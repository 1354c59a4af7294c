//! Plays the engine for the plugin on dataset frames: uploads a frame's layers into engine-owned
//! images, calls `patchex_submit_gbuffers` and `patchex_extrapolate` through the C ABI of the
//! loaded shared library, and reads the output back. Each call goes to a context made with the
//! cheapest preset that runs it (and per weights folder and precision for the networks), made on
//! first use, so that what a context holds is what its configuration needs.

use std::cell::{Cell, RefCell};
use std::ffi::{c_void, CString};
use std::path::{Path, PathBuf};
use std::ptr;
use std::time::{Duration, Instant};

use ash::vk;
use patchex::abi::*;
use patchex::error::PatchexResult;
use patchex::ffi::PatchexContext;
use patchex::loader::PatchexLibrary;
use patchex::passes::shadow_flow::FlowSettings;
use patchex::passes::warp::WarpSettings;
use patchex_harness::{Engine, EngineImage, EngineOptions};
use patchex_scene::dataset::{
    FrameInfo, FrameLayers, Manifest, SunInfo, BASE_COLOR, CUSTOM_STENCIL, FINAL_IMAGE,
    FINAL_IMAGE_NO_DYNAMIC_SHADOWS, FINAL_IMAGE_OPAQUE, METALLIC, MOTION_VECTOR, ROUGHNESS,
    SCENE_DEPTH, SHADOW_MASK, SPECULAR, STATIC_SHADOW_MASK, TRANSLUCENCY_MASK, TRANSLUCENCY_MOTION,
    WORLD_NORMAL,
};

/// The layout the driver keeps every engine image in between calls.
const LAYOUT: vk::ImageLayout = vk::ImageLayout::GENERAL;

/// The inpainting networks a call runs (PATCHEX_PRESET_FULL).
#[derive(Clone, Debug, PartialEq)]
pub struct NetworkChoice {
    /// A folder with fi.safetensors and near_be.safetensors; the built-in weights without one.
    pub weights: Option<PathBuf>,
    /// The FI network over the whole frame (`PatchexNetworkSettings.whole_frame`).
    pub whole_frame: bool,
    /// Tensors stored in FP32 rather than FP16 (`PatchexNetworkPrecision`).
    pub fp32_tensors: bool,
    /// Frame pixels per network texel on each axis (`PatchexNetworkSettings`).
    pub resolution_divisor: u32,
    /// The paper's blend: corrections over valid pixels too, not only holes
    /// (`PatchexNetworkSettings.correct_valid_pixels`).
    pub correct_valid_pixels: bool,
    /// Network texels a patch may span per axis (`PatchexNetworkMemory`); the library's default
    /// without one.
    pub max_patch_side: Option<u32>,
}

impl Default for NetworkChoice {
    /// The built-in weights on their patches, at the frame's resolution, FP16 tensors.
    fn default() -> Self {
        Self {
            weights: None,
            whole_frame: false,
            fp32_tensors: false,
            resolution_divisor: 1,
            correct_valid_pixels: false,
            max_patch_side: None,
        }
    }
}

impl NetworkChoice {
    /// The paper's ablation of foveated segmentation: the FI network over the whole frame, at
    /// the frame's resolution (tensors for the whole frame).
    pub fn whole_frame() -> Self {
        Self {
            whole_frame: true,
            max_patch_side: Some(PATCHEX_MAX_NETWORK_PATCH_SIDE),
            ..Self::default()
        }
    }

    /// This choice, with `max_patch_side` (a command's option) where it names none itself.
    pub fn or_max_patch_side(self, max_patch_side: Option<u32>) -> Self {
        Self {
            max_patch_side: self.max_patch_side.or(max_patch_side),
            ..self
        }
    }
}

/// What a context is made with: its preset, the weights' folder, FP32 tensors, the tensors'
/// patch side (`whole_frame`, the divisor and the blend are chosen per call), whether its
/// frames come with target shadow masks and no flow, and the extras they come with.
type ContextKey = (
    PatchexPreset,
    Option<PathBuf>,
    bool,
    Option<u32>,
    bool,
    FrameExtras,
);

/// How the driver stores a frame's layers in engine images.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum InputFormats {
    /// 32-bit floats: exactly the rendered values.
    #[default]
    Float32,
    /// What a deferred renderer keeps (Unreal's G-buffer): colour RGBA16F, base colour RGBA8
    /// sRGB, material RGBA8, normals A2B10G10R10 (PATCHEX_NORMAL_UNORM), motion RG16F, linear
    /// depth R32F, stencil R8.
    Engine,
}

pub struct PluginDriver {
    contexts: RefCell<Vec<(ContextKey, *mut PatchexContext)>>,
    input_formats: InputFormats,
    library: PatchexLibrary,
    /// The scene's sky as an octahedral map, for the frames that go with a PatchexSkyLight
    /// (before `engine`, which outlives it).
    sky: Option<EngineImage>,
    pub engine: Engine,
    width: u32,
    height: u32,
    near: f32,
    far: f32,
    /// The scene's sun, for the frames that go with a PatchexSunLight.
    sun: Option<SunInfo>,
    /// How long each call repeats back to back before the one measured (`with_warm_up`).
    warm_up: Duration,
    /// Frame indices the repeats used, added to the caller's so that indices keep increasing.
    repeats: Cell<u64>,
}

/// The most copies of one call the warm-up runs in a batch: enough to keep a GPU busy for tens
/// of milliseconds between the CPU's turns.
const MAX_WARM_UP_COPIES: u32 = 16;

/// Texels a side of the sky's octahedral map: the renderer's sky is a smooth gradient.
pub const SKY_SIDE: usize = 64;

/// Interleaves single-channel layers into one RGBA image's values.
fn interleave(width: usize, height: usize, planes: &[Vec<f32>]) -> Vec<f32> {
    let mut values = vec![0.0; width * height * 4];
    for (channel, plane) in planes.iter().enumerate() {
        for (pixel, value) in plane.iter().enumerate() {
            values[pixel * 4 + channel] = *value;
        }
    }
    values
}

/// One instant's G-buffers in engine images.
struct UploadedFrame {
    color: Option<EngineImage>,
    base_color: EngineImage,
    material: EngineImage,
    depth: EngineImage,
    normal: EngineImage,
    stencil: EngineImage,
    motion: EngineImage,
    /// The shadow mask and the colour without dynamic shadows, when asked for.
    shadow: Option<(EngineImage, EngineImage)>,
    /// The sun's visibility (`PatchexSunLight.visibility`), when asked for.
    sun_visibility: Option<EngineImage>,
    /// The translucency's mask and motion (`PatchexTranslucencyInput`), when asked for and the
    /// frame has them, and its colour before the translucency pass when asked for.
    translucency: Option<(EngineImage, EngineImage, Option<EngineImage>)>,
    camera: PatchexCamera,
}

/// The optional inputs frame t (and frame t-1) go with, besides the shadow sub-task's.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FrameExtras {
    /// The scene's sun (`PatchexSunLight`).
    pub sun: bool,
    /// The scene's sky (`PatchexSkyLight`).
    pub sky: bool,
    /// The translucency mask and motion of frames whose scene has particles
    /// (`PatchexTranslucencyInput`); frames without them go without.
    pub translucency: bool,
    /// With the translucency input, frame t's colour before its translucency pass
    /// (`PatchexTranslucencyInput.opaque_color`).
    pub opaque_color: bool,
}

/// The shadow sub-task's inputs of one extrapolation.
#[derive(Clone, Copy, Default)]
pub struct ShadowRun<'a> {
    /// Frame t-1, submitted first with its shadow input so that the shadows' motion is tracked.
    pub earlier: Option<(&'a FrameLayers, &'a FrameInfo)>,
    /// The target's mask goes with the extrapolation as a PatchexTargetShadowInput, and the
    /// frames go without flow.
    pub target_mask: bool,
}

/// What one extrapolation produced.
pub struct Extrapolated {
    /// RGBA, linear HDR.
    pub color: Vec<f32>,
    /// RGBA, as `PatchexDiagnostics` describes: hole, region / 2, LBP code / 255; when asked.
    pub diagnostics: Option<Vec<f32>>,
    pub stats: PatchexFrameStats,
}

impl PluginDriver {
    pub fn new(manifest: &Manifest, validation: bool) -> Result<Self, String> {
        Self::on_device(manifest, validation, None)
    }

    /// As [`Self::new`], on the first device whose name contains `device` (case-insensitive);
    /// without one, as the engine picks (`PATCHEX_DEVICE`, else the first GPU).
    pub fn on_device(
        manifest: &Manifest,
        validation: bool,
        device: Option<&str>,
    ) -> Result<Self, String> {
        let defaults = EngineOptions::default();
        let engine = Engine::new(&EngineOptions {
            validation,
            device_name: device.map(str::to_owned).or(defaults.device_name),
        })?;
        let path = PatchexLibrary::beside_current_exe()?;
        // SAFETY: the library is built from this workspace.
        let library = unsafe { PatchexLibrary::open(&path)? };
        let (width, height) = (manifest.width as u32, manifest.height as u32);
        let sky = manifest.sky.map(|sky| {
            let map = EngineImage::new(
                &engine,
                vk::Format::R32G32B32A32_SFLOAT,
                SKY_SIDE as u32,
                SKY_SIDE as u32,
                vk::ImageUsageFlags::SAMPLED,
            );
            map.upload(&engine, &sky.octahedral_map(SKY_SIDE), LAYOUT);
            map
        });
        Ok(Self {
            contexts: RefCell::new(Vec::new()),
            input_formats: InputFormats::default(),
            library,
            engine,
            width,
            height,
            near: manifest.near,
            far: manifest.far,
            sun: manifest.sun,
            sky,
            warm_up: Duration::ZERO,
            repeats: Cell::new(0),
        })
    }

    /// Stores the frames' layers in `formats` from now on.
    pub fn with_input_formats(mut self, formats: InputFormats) -> Self {
        self.input_formats = formats;
        self
    }

    /// Repeats each call back to back for `warm_up` before the call whose results it returns:
    /// a GPU left idle between calls runs them at its idle clock, where a game's steady load
    /// keeps it at full clock.
    pub fn with_warm_up(mut self, warm_up: Duration) -> Self {
        self.warm_up = warm_up;
        self
    }

    /// The context for `networks` and `shadows`, made on first use; with the target's shadow
    /// mask (`target_mask`) one of its own, which never runs the flow, and with each set of
    /// `extras` one of its own, which holds their images, so that each one's memory is its own.
    fn context_for(
        &self,
        networks: Option<&NetworkChoice>,
        shadows: bool,
        target_mask: bool,
        extras: FrameExtras,
    ) -> Result<*mut PatchexContext, String> {
        let preset = match (networks.is_some(), shadows) {
            (false, false) => PATCHEX_PRESET_WARP_ONLY,
            (false, true) => PATCHEX_PRESET_WARP_AND_SHADOWS,
            (true, false) => PATCHEX_PRESET_NETWORKS,
            (true, true) => PATCHEX_PRESET_FULL,
        };
        let key = (
            preset,
            networks.and_then(|n| n.weights.clone()),
            networks.is_some_and(|n| n.fp32_tensors),
            networks.and_then(|n| n.max_patch_side),
            target_mask,
            extras,
        );
        let mut contexts = self.contexts.borrow_mut();
        if let Some((_, context)) = contexts.iter().find(|(k, _)| *k == key) {
            return Ok(*context);
        }
        let context = create(
            &self.library,
            &self.engine,
            self.width,
            self.height,
            preset,
            networks,
        )?;
        contexts.push((key, context));
        Ok(context)
    }

    fn upload(
        &self,
        layers: &FrameLayers,
        info: &FrameInfo,
        with_color: bool,
        with_shadow: bool,
        extras: FrameExtras,
    ) -> UploadedFrame {
        let (w, h) = (self.width, self.height);
        let (wu, hu) = (w as usize, h as usize);
        let image = |format, values: &[f32]| {
            let image = EngineImage::new(&self.engine, format, w, h, vk::ImageUsageFlags::SAMPLED);
            image.upload(&self.engine, values, LAYOUT);
            image
        };
        let rgb = |name: &str| {
            let layer = layers.layer(name);
            interleave(wu, hu, &[layer.plane(0), layer.plane(1), layer.plane(2)])
        };
        use vk::Format as F;
        let engine = self.input_formats == InputFormats::Engine;
        let pick = |exact, engine_format| if engine { engine_format } else { exact };
        let (color, unit) = (
            pick(F::R32G32B32A32_SFLOAT, F::R16G16B16A16_SFLOAT),
            pick(F::R32G32B32A32_SFLOAT, F::R8G8B8A8_UNORM),
        );
        let mut normal = rgb(WORLD_NORMAL);
        if engine {
            // A2B10G10R10 holds [0, 1]: PATCHEX_NORMAL_UNORM.
            normal.iter_mut().for_each(|n| *n = *n * 0.5 + 0.5);
        }
        UploadedFrame {
            color: with_color.then(|| image(color, &rgb(FINAL_IMAGE))),
            base_color: image(
                pick(F::R32G32B32A32_SFLOAT, F::R8G8B8A8_SRGB),
                &rgb(BASE_COLOR),
            ),
            material: image(
                unit,
                &interleave(
                    wu,
                    hu,
                    &[
                        layers.layer(METALLIC).plane(0),
                        layers.layer(SPECULAR).plane(0),
                        layers.layer(ROUGHNESS).plane(0),
                    ],
                ),
            ),
            depth: image(F::R32_SFLOAT, &layers.layer(SCENE_DEPTH).plane(0)),
            normal: image(
                pick(F::R32G32B32A32_SFLOAT, F::A2B10G10R10_UNORM_PACK32),
                &normal,
            ),
            stencil: image(F::R8_UINT, &layers.layer(CUSTOM_STENCIL).plane(0)),
            motion: image(
                pick(F::R32G32_SFLOAT, F::R16G16_SFLOAT),
                &layers.layer(MOTION_VECTOR).data,
            ),
            shadow: with_shadow.then(|| {
                (
                    image(F::R32_SFLOAT, &layers.layer(SHADOW_MASK).plane(0)),
                    image(color, &rgb(FINAL_IMAGE_NO_DYNAMIC_SHADOWS)),
                )
            }),
            // The term the colour was lit with: with a shadow input, the static casters' alone.
            sun_visibility: extras.sun.then(|| {
                let mut visibility = layers.layer(STATIC_SHADOW_MASK).plane(0);
                if !with_shadow {
                    let dynamic = layers.layer(SHADOW_MASK).plane(0);
                    visibility
                        .iter_mut()
                        .zip(dynamic)
                        .for_each(|(v, d)| *v *= d);
                }
                image(F::R32_SFLOAT, &visibility)
            }),
            translucency: layers
                .get(TRANSLUCENCY_MASK)
                .zip(layers.get(TRANSLUCENCY_MOTION))
                .filter(|_| extras.translucency)
                .map(|(mask, motion)| {
                    (
                        image(F::R32_SFLOAT, &mask.data),
                        image(pick(F::R32G32_SFLOAT, F::R16G16_SFLOAT), &motion.data),
                        (extras.opaque_color && layers.get(FINAL_IMAGE_OPAQUE).is_some())
                            .then(|| image(color, &rgb(FINAL_IMAGE_OPAQUE))),
                    )
                }),
            camera: PatchexCamera {
                view: info.view,
                projection: info.proj,
                jitter: [0.0, 0.0],
                near_plane: self.near,
                far_plane: self.far,
                depth_convention: PATCHEX_DEPTH_LINEAR_VIEW_Z,
            },
        }
    }

    fn geometry(&self, frame: &UploadedFrame) -> PatchexGeometry {
        PatchexGeometry {
            depth: frame.depth.describe(LAYOUT),
            normal: frame.normal.describe(LAYOUT),
            normal_encoding: match self.input_formats {
                InputFormats::Float32 => PATCHEX_NORMAL_SIGNED,
                InputFormats::Engine => PATCHEX_NORMAL_UNORM,
            },
            stencil: frame.stencil.describe(LAYOUT),
            motion_vectors: frame.motion.describe(LAYOUT),
            motion_vector_scale: [1.0, 1.0],
            camera: frame.camera,
        }
    }

    /// An RGBA16F storage image the plugin writes.
    fn output_image(&self) -> EngineImage {
        let image = EngineImage::new(
            &self.engine,
            vk::Format::R16G16B16A16_SFLOAT,
            self.width,
            self.height,
            vk::ImageUsageFlags::STORAGE,
        );
        image.upload(
            &self.engine,
            &vec![0.0; (self.width * self.height * 4) as usize],
            LAYOUT,
        );
        image
    }

    /// The submit description of `frame`.
    fn frame_desc(&self, frame_index: u64, frame: &UploadedFrame) -> PatchexFrameDesc {
        PatchexFrameDesc {
            header: PatchexStructHeader::of::<PatchexFrameDesc>(PATCHEX_STRUCT_TYPE_FRAME_DESC),
            frame_index,
            reset: 0,
            queue_family_index: self.engine.queue_family_index,
            width: self.width,
            height: self.height,
            color: frame
                .color
                .as_ref()
                .expect("uploaded with colour")
                .describe(LAYOUT),
            base_color: frame.base_color.describe(LAYOUT),
            material: frame.material.describe(LAYOUT),
            geometry: self.geometry(frame),
        }
    }

    /// Submits `source` as frame `frame_index` and extrapolates the `target` instant from it,
    /// with the context's default warp or `warp`, the inpainting `networks` if given, and the
    /// diagnostics image if asked. With `shadows`, both frames go with their shadow input, frame
    /// t-1 (when there is one) is submitted first as frame `frame_index - 1`, so the shadow's
    /// motion is tracked, and the target's mask goes with the extrapolation if asked. Frame t
    /// (and frame t-1) go with the `extras` asked for.
    #[allow(clippy::too_many_arguments)]
    pub fn extrapolate(
        &self,
        frame_index: u64,
        source: (&FrameLayers, &FrameInfo),
        target: (&FrameLayers, &FrameInfo),
        alpha: f32,
        warp: Option<WarpSettings>,
        networks: Option<&NetworkChoice>,
        with_diagnostics: bool,
        shadows: Option<ShadowRun>,
        extras: FrameExtras,
    ) -> Result<Extrapolated, String> {
        let with_shadows = shadows.is_some();
        let with_target_mask = shadows.is_some_and(|s| s.target_mask);
        let sun = match (extras.sun, self.sun) {
            (false, _) => None,
            (true, Some(sun)) => Some(sun),
            (true, None) => return Err("the scene's manifest has no sun".to_owned()),
        };
        let sky = match (extras.sky, &self.sky) {
            (false, _) => None,
            (true, Some(sky)) => Some(sky),
            (true, None) => return Err("the scene's manifest has no sky".to_owned()),
        };
        let sky_light = |next| {
            sky.map(|map| PatchexSkyLight {
                header: PatchexStructHeader {
                    next,
                    ..PatchexStructHeader::of::<PatchexSkyLight>(PATCHEX_STRUCT_TYPE_SKY_LIGHT)
                },
                radiance: map.describe(LAYOUT),
                mip_levels: 1,
            })
        };
        let context = self.context_for(networks, with_shadows, with_target_mask, extras)?;
        let earlier = shadows
            .and_then(|s| s.earlier)
            .map(|(layers, info)| self.upload(layers, info, true, true, extras));
        let source = self.upload(source.0, source.1, true, with_shadows, extras);
        let target = self.upload(
            target.0,
            target.1,
            false,
            with_target_mask,
            FrameExtras::default(),
        );
        let output = self.output_image();
        let diagnostics_image = with_diagnostics.then(|| self.output_image());
        let network_settings = networks.map(|networks| PatchexNetworkSettings {
            header: PatchexStructHeader::of::<PatchexNetworkSettings>(
                PATCHEX_STRUCT_TYPE_NETWORK_SETTINGS,
            ),
            run_fi: 1,
            run_near_be: 1,
            whole_frame: networks.whole_frame as PatchexBool,
            resolution_divisor: networks.resolution_divisor,
            correct_valid_pixels: networks.correct_valid_pixels as PatchexBool,
        });
        // The chain, back to front: network settings, warp settings, diagnostics, then the
        // target's shadow mask.
        let mut next: *const c_void = ptr::null();
        if let Some(settings) = &network_settings {
            next = settings as *const PatchexNetworkSettings as *const c_void;
        }
        let warp_settings = warp.map(|warp| {
            let mut settings = warp.to_abi();
            settings.header.next = next;
            settings
        });
        if let Some(settings) = &warp_settings {
            next = settings as *const PatchexWarpSettings as *const c_void;
        }
        let diagnostics = diagnostics_image.as_ref().map(|image| PatchexDiagnostics {
            header: PatchexStructHeader {
                next,
                ..PatchexStructHeader::of::<PatchexDiagnostics>(PATCHEX_STRUCT_TYPE_DIAGNOSTICS)
            },
            image: image.describe(LAYOUT),
        });
        if let Some(diagnostics) = &diagnostics {
            next = diagnostics as *const PatchexDiagnostics as *const c_void;
        }
        let target_shadow_input =
            target
                .shadow
                .as_ref()
                .map(|(mask, _)| PatchexTargetShadowInput {
                    header: PatchexStructHeader {
                        next,
                        ..PatchexStructHeader::of::<PatchexTargetShadowInput>(
                            PATCHEX_STRUCT_TYPE_TARGET_SHADOW_INPUT,
                        )
                    },
                    mask: mask.describe(LAYOUT),
                });
        if let Some(input) = &target_shadow_input {
            next = input as *const PatchexTargetShadowInput as *const c_void;
        }
        // With target masks on every extrapolation, the frames need no flow.
        let flow_off = FlowSettings::off().to_abi();
        let shadow_input = |frame: &UploadedFrame| {
            frame
                .shadow
                .as_ref()
                .map(|(mask, color)| PatchexShadowInput {
                    header: PatchexStructHeader {
                        next: if with_target_mask {
                            &flow_off as *const PatchexShadowFlowSettings as *const c_void
                        } else {
                            ptr::null()
                        },
                        ..PatchexStructHeader::of::<PatchexShadowInput>(
                            PATCHEX_STRUCT_TYPE_SHADOW_INPUT,
                        )
                    },
                    mask: mask.describe(LAYOUT),
                    color_without_dynamic_shadows: color.describe(LAYOUT),
                })
        };
        let translucency_input = |frame: &UploadedFrame, next| {
            frame
                .translucency
                .as_ref()
                .map(|(mask, motion, opaque)| PatchexTranslucencyInput {
                    header: PatchexStructHeader {
                        next,
                        ..PatchexStructHeader::of::<PatchexTranslucencyInput>(
                            PATCHEX_STRUCT_TYPE_TRANSLUCENCY_INPUT,
                        )
                    },
                    mask: mask.describe(LAYOUT),
                    motion_vectors: motion.describe(LAYOUT),
                    motion_vector_scale: [1.0, 1.0],
                    opaque_color: opaque
                        .as_ref()
                        .map_or(PatchexImage::default(), |o| o.describe(LAYOUT)),
                })
        };
        let sun_light = |frame: &UploadedFrame, next| {
            sun.zip(frame.sun_visibility.as_ref())
                .map(|(sun, visibility)| PatchexSunLight {
                    header: PatchexStructHeader {
                        next,
                        ..PatchexStructHeader::of::<PatchexSunLight>(PATCHEX_STRUCT_TYPE_SUN_LIGHT)
                    },
                    direction: sun.direction,
                    illuminance: sun.illuminance,
                    visibility: visibility.describe(LAYOUT),
                })
        };
        fn link<T>(input: &Option<T>, otherwise: *const c_void) -> *const c_void {
            input
                .as_ref()
                .map_or(otherwise, |input| input as *const T as *const c_void)
        }
        let warm_until = Instant::now() + self.warm_up;
        // Each call is recorded once and run `copies` times back to back, so that the GPU has
        // no idle gap while the CPU records the next: a driver clocks a GPU by how busy it is,
        // and the cheapest calls, recorded one at a time, left it idle often enough to run them
        // at a lower clock. The copies of the last call are the measured ones.
        let mut copies = 1;
        let (index, results) = loop {
            let index = frame_index + self.repeats.get();
            // A frame's chain, built back to front: its translucency, its sun, its sky, then its
            // shadow input. Each link points at a local that lives until the frame is submitted.
            let source_shadow = shadow_input(&source);
            let mut chain = link(&source_shadow, ptr::null());
            let source_sky = sky_light(chain);
            chain = link(&source_sky, chain);
            let source_sun = sun_light(&source, chain);
            chain = link(&source_sun, chain);
            let source_translucency = translucency_input(&source, chain);
            let mut frame = self.frame_desc(index, &source);
            frame.header.next = link(&source_translucency, chain);
            let earlier_shadow = earlier.as_ref().and_then(shadow_input);
            let mut chain = link(&earlier_shadow, ptr::null());
            let earlier_sky = earlier.as_ref().and_then(|_| sky_light(chain));
            chain = link(&earlier_sky, chain);
            let earlier_sun = earlier.as_ref().and_then(|e| sun_light(e, chain));
            chain = link(&earlier_sun, chain);
            let earlier_translucency = earlier.as_ref().and_then(|e| translucency_input(e, chain));
            let earlier_frame = earlier.as_ref().map(|earlier| {
                let mut desc = self.frame_desc(index - 1, earlier);
                desc.header.next = link(&earlier_translucency, chain);
                desc
            });
            let mut extrapolate = PatchexExtrapolateDesc {
                header: PatchexStructHeader::of::<PatchexExtrapolateDesc>(
                    PATCHEX_STRUCT_TYPE_EXTRAPOLATE_DESC,
                ),
                queue_family_index: self.engine.queue_family_index,
                alpha,
                width: self.width,
                height: self.height,
                base_color: target.base_color.describe(LAYOUT),
                material: target.material.describe(LAYOUT),
                geometry: self.geometry(&target),
                output: output.describe(LAYOUT),
            };
            extrapolate.header.next = next;
            let mut results = [PatchexResult::Success; 3];
            let batch_started = Instant::now();
            self.engine.run_repeated(copies, |cmd| {
                // SAFETY: live context; the images live until the submission completes.
                unsafe {
                    if let Some(earlier_frame) = &earlier_frame {
                        results[0] = (self.library.submit_gbuffers)(context, cmd, earlier_frame);
                    }
                    results[1] = (self.library.submit_gbuffers)(context, cmd, &frame);
                    results[2] = (self.library.extrapolate)(context, cmd, &extrapolate);
                }
            });
            let now = Instant::now();
            if now >= warm_until {
                break (index, results);
            }
            // As many copies as fill what is left of the warm-up, up to MAX_WARM_UP_COPIES.
            let per_copy = batch_started.elapsed().as_secs_f64() / copies as f64;
            let left = (warm_until - now).as_secs_f64();
            copies = (left / per_copy.max(1e-6)).clamp(1.0, MAX_WARM_UP_COPIES as f64) as u32;
            self.repeats.set(self.repeats.get() + 2);
        };
        // A camera cut (RENDER_INSTEAD, positive) still writes the output: the stats say so.
        if results.iter().any(|result| (*result as i32) < 0) {
            // SAFETY: live context.
            return Err(format!("patchex: {}", unsafe {
                self.library.last_error_message(context)
            }));
        }
        // SAFETY: zeroed stats are a valid bit pattern; the header is set before the call.
        let mut stats: PatchexFrameStats = unsafe { std::mem::zeroed() };
        stats.header =
            PatchexStructHeader::of::<PatchexFrameStats>(PATCHEX_STRUCT_TYPE_FRAME_STATS);
        // SAFETY: live context, writable stats; the frame's fence has signalled.
        let result = unsafe { (self.library.get_frame_stats)(context, index, &mut stats) };
        if result != PatchexResult::Success {
            return Err(format!("patchex_get_frame_stats returned {result:?}"));
        }
        Ok(Extrapolated {
            color: output.read(&self.engine, LAYOUT),
            diagnostics: diagnostics_image.map(|image| image.read(&self.engine, LAYOUT)),
            stats,
        })
    }

    pub fn validation_messages(&self) -> Vec<String> {
        self.engine.take_validation_messages()
    }
}

impl Drop for PluginDriver {
    fn drop(&mut self) {
        // SAFETY: every submission was waited on; the context is not used again.
        unsafe {
            let _ = self.engine.device.device_wait_idle();
            for (_, context) in self.contexts.get_mut().drain(..) {
                (self.library.destroy)(context);
            }
        }
    }
}

/// A context for `width` x `height` on `engine` with `preset`, and with `networks` the weights
/// folder they name (or the built-in ones) in their precision.
fn create(
    library: &PatchexLibrary,
    engine: &Engine,
    width: u32,
    height: u32,
    preset: PatchexPreset,
    networks: Option<&NetworkChoice>,
) -> Result<*mut PatchexContext, String> {
    let mut info = engine.create_info(width, height);
    let path = |name: &str, folder: &Path| {
        CString::new(folder.join(name).to_string_lossy().as_bytes())
            .map_err(|_| format!("{}: a path with a NUL byte", folder.display()))
    };
    let paths = match networks.and_then(|n| n.weights.as_deref()) {
        Some(folder) => Some((
            path("fi.safetensors", folder)?,
            path("near_be.safetensors", folder)?,
        )),
        None => None,
    };
    // The chain: the weights (when a folder is named), then the precision (when FP32), then the
    // tensors' patch side (when one is named).
    let memory = networks
        .and_then(|n| n.max_patch_side)
        .map(|max_patch_side| PatchexNetworkMemory {
            header: PatchexStructHeader::of::<PatchexNetworkMemory>(
                PATCHEX_STRUCT_TYPE_NETWORK_MEMORY,
            ),
            max_patch_side,
        });
    let memory_link = memory.as_ref().map_or(ptr::null(), |m| {
        m as *const PatchexNetworkMemory as *const c_void
    });
    let precision = networks
        .filter(|n| n.fp32_tensors)
        .map(|_| PatchexNetworkPrecision {
            header: PatchexStructHeader {
                next: memory_link,
                ..PatchexStructHeader::of::<PatchexNetworkPrecision>(
                    PATCHEX_STRUCT_TYPE_NETWORK_PRECISION,
                )
            },
            tensors: PATCHEX_TENSOR_PRECISION_FP32,
        });
    let precision_link = precision.as_ref().map_or(memory_link, |p| {
        p as *const PatchexNetworkPrecision as *const c_void
    });
    let weights = paths.as_ref().map(|(fi, near_be)| PatchexNetworkWeights {
        header: PatchexStructHeader {
            next: precision_link,
            ..PatchexStructHeader::of::<PatchexNetworkWeights>(PATCHEX_STRUCT_TYPE_NETWORK_WEIGHTS)
        },
        fi_path: fi.as_ptr(),
        near_be_path: near_be.as_ptr(),
    });
    info.preset = preset;
    info.header.next = weights.as_ref().map_or(precision_link, |w| {
        w as *const PatchexNetworkWeights as *const c_void
    });
    let mut context = ptr::null_mut();
    // SAFETY: valid create info from a live engine; the chained paths outlive the call.
    let result = unsafe { (library.create)(&info, &mut context) };
    if result != PatchexResult::Success {
        // SAFETY: NULL asks for this thread's last error.
        return Err(format!("patchex_create: {}", unsafe {
            library.last_error_message(ptr::null())
        }));
    }
    Ok(context)
}
