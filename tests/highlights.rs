//! The sun's highlights and the sky's reflection (`PatchexSunLight`, `PatchexSkyLight`) on
//! lavapipe through the C ABI: frame t's taken out of its shading and the target's placed,
//! against the plain-Rust reference on frames of the scene renderer (glossy tiled ground, a
//! moving camera, animated characters), with and without the shadow sub-task; the gain over
//! glossy surfaces; and that bad inputs are refused or sanitised and counted.
//!
//! Tolerance: the colour tolerance of `support/pipeline.rs` (2e-3 relative plus 1e-4),
//! loosened to 1e-3 absolute: the highlight is a sum of pow(), sqrt() and a division whose last
//! bits differ between the GPU and the reference, on top of the warp's.

mod support;

use std::ffi::c_void;

use ash::vk;
use glam::Vec3;
use patchex::abi::*;
use patchex::camera::Camera;
use patchex::error::PatchexResult;
use patchex::passes::highlights::Sun;
use patchex::passes::shadow_flow::{mask_step, FlowSettings};
use patchex::passes::warp::WarpSettings;
use patchex::reference::{self, Image, ShadowInputs};
use patchex_harness::EngineImage;
use patchex_scene::dataset::{SkyInfo, SunInfo};
use support::pipeline::{
    assert_stages_agree, inputs, pixels_of, psnr, read_image, worst_output_error,
};
use support::scene::Frame;
use support::*;

/// A glossy generated scene: tiled ground of roughness 0.25 to 0.55 under a handheld camera,
/// with animated characters.
const SCENE: &str = "generated/autumn_01.toml";

/// Frames t-1 and t (frames 0 and 2 of the doubled stream), the instant halfway to t+1 (frame
/// 3), the scene's sun, and its sky.
fn rendered_frames(width: u32, height: u32) -> ([Frame; 3], SunInfo, SkyInfo) {
    let sequence = support::rendered::render(SCENE, 4, width, height);
    let sun = sequence.manifest.sun.expect("the renderer records its sun");
    let sky = sequence.manifest.sky.expect("the renderer records its sky");
    let Ok([previous, _, source, target]) = <[Frame; 4]>::try_from(sequence.frames) else {
        unreachable!("four frames")
    };
    ([previous, source, target], sun, sky)
}

/// The sky as a 32-texel octahedral map of one mip.
fn one_mip(sky: &SkyInfo) -> Vec<Image> {
    vec![sky_map(sky, 32)]
}

fn sky_map(sky: &SkyInfo, side: usize) -> Image {
    Image {
        width: side,
        height: side,
        channels: 4,
        data: sky.octahedral_map(side),
    }
}

/// What the frames of one run go with.
#[derive(Clone, Copy, Default)]
struct Inputs<'a> {
    /// Frame t-1 and frame t's shadow inputs (a context with the shadow sub-task).
    shadows: [bool; 2],
    /// The target's shadow mask as a target shadow input.
    target_mask: bool,
    sun: Option<&'a SunInfo>,
    /// The sky's octahedral map, one image a mip, with both frames.
    sky: Option<&'a [Image]>,
}

struct Outcome {
    output: Image,
    stats: PatchexFrameStats,
}

/// Submits `previous` (frame 1) and `source` (frame 2), each with what `with` gives it, and
/// extrapolates `target` at alpha 1/2 from frame 2, on a fresh rig under validation that must
/// stay silent.
fn run([previous, source, target]: [&Frame; 3], with: Inputs) -> Outcome {
    let (width, height) = (source.color.width, source.color.height);
    let rig = Rig::with_create_info(width as u32, height as u32, |info| {
        if with.shadows.contains(&true) {
            info.preset = PATCHEX_PRESET_WARP_AND_SHADOWS;
        }
    });
    let engine = &rig.engine;
    let family = engine.queue_family_index;
    let frames = [previous, source].map(|frame| GpuFrame::upload(engine, frame));
    let gpu_target = GpuFrame::upload(engine, target);
    let output = output_image(engine, width as u32, height as u32);
    let shadow_inputs = frames.each_ref().map(GpuFrame::shadow_input);
    let sky_image = with.sky.map(|mips| {
        let side = mips[0].width as u32;
        let format = vk::Format::R32G32B32A32_SFLOAT;
        let usage = vk::ImageUsageFlags::SAMPLED;
        let image = EngineImage::with_mips(engine, format, side, side, mips.len() as u32, usage);
        let values: Vec<&[f32]> = mips.iter().map(|mip| &mip.data[..]).collect();
        image.upload_mips(engine, &values, GBUFFER_LAYOUT);
        image
    });
    // Each frame's chain, back to front: its shadow input, its sky, its sun.
    let skies = [0, 1].map(|index| {
        sky_image.as_ref().map(|map| PatchexSkyLight {
            header: PatchexStructHeader {
                next: if with.shadows[index] {
                    &shadow_inputs[index] as *const _ as *const c_void
                } else {
                    std::ptr::null()
                },
                ..PatchexStructHeader::of::<PatchexSkyLight>(PATCHEX_STRUCT_TYPE_SKY_LIGHT)
            },
            radiance: map.describe(GBUFFER_LAYOUT),
            mip_levels: map.mip_levels,
        })
    });
    let below_sun = |index: usize| match (&skies[index], with.shadows[index]) {
        (Some(sky), _) => sky as *const _ as *const c_void,
        (None, true) => &shadow_inputs[index] as *const _ as *const c_void,
        (None, false) => std::ptr::null(),
    };
    let suns = [0, 1].map(|index| {
        with.sun.map(|sun| PatchexSunLight {
            header: PatchexStructHeader {
                next: below_sun(index),
                ..PatchexStructHeader::of::<PatchexSunLight>(PATCHEX_STRUCT_TYPE_SUN_LIGHT)
            },
            ..frames[index].sun_light(sun, with.shadows[index])
        })
    });
    let target_mask = PatchexTargetShadowInput {
        header: PatchexStructHeader::of::<PatchexTargetShadowInput>(
            PATCHEX_STRUCT_TYPE_TARGET_SHADOW_INPUT,
        ),
        mask: gpu_target.shadow_input().mask,
    };
    for (index, frame) in frames.iter().enumerate() {
        let mut desc = frame.frame_desc(1 + index as u64, family);
        desc.header.next = match &suns[index] {
            Some(sun) => sun as *const _ as *const c_void,
            None => below_sun(index),
        };
        engine.run(|cmd| {
            rig.submit_ok(cmd, &desc);
            if index == 1 {
                let mut extrapolate = gpu_target.extrapolate_desc(&output, 0.5, family);
                if with.target_mask {
                    extrapolate.header.next = &target_mask as *const _ as *const c_void;
                }
                rig.extrapolate_ok(cmd, &extrapolate);
            }
        });
    }
    let (result, stats) = rig.stats(2);
    assert_eq!(result, PatchexResult::Success, "{}", rig.last_error());
    let messages = engine.take_validation_messages();
    assert!(messages.is_empty(), "validation: {messages:?}");
    Outcome {
        output: read_image(engine, &output, width, height),
        stats,
    }
}

fn sun_of(info: &SunInfo) -> Sun {
    Sun {
        direction: Vec3::from(info.direction),
        illuminance: Vec3::from(info.illuminance),
    }
}

/// The reference's run of `run`.
fn reference_run(
    [previous, source, target]: [&Frame; 3],
    with: Inputs,
) -> reference::Extrapolation {
    let previous_camera = Camera::from_abi(&previous.camera, "previous").unwrap();
    let source_camera = Camera::from_abi(&source.camera, "source").unwrap();
    let target_camera = Camera::from_abi(&target.camera, "target").unwrap();
    // Frames with a shadow input give the static casters' visibility, which their colour
    // without dynamic shadows was lit with.
    let visibility = if with.shadows[1] {
        &source.static_visibility
    } else {
        &source.sun_visibility
    };
    let source_inputs = reference::FrameInputs {
        sun: with.sun.map(|sun| (sun_of(sun), visibility)),
        sky: with.sky,
        ..inputs(source, &source_camera)
    };
    let shadows = with.shadows[1].then(|| ShadowInputs {
        color_without_dynamic_shadows: &source.color_without_dynamic_shadows,
        mask: &source.shadow_mask,
        previous: with.shadows[0].then_some((
            &previous.shadow_mask,
            &previous.stencil,
            &previous_camera,
        )),
        flow: FlowSettings::default(),
        mask_step: mask_step(vk::Extent2D {
            width: source.color.width as u32,
            height: source.color.height as u32,
        }),
        target_mask: with.target_mask.then_some(&target.shadow_mask),
    });
    reference::extrapolate(
        &source_inputs,
        &inputs(target, &target_camera),
        shadows.as_ref(),
        0.5,
        &WarpSettings::default(),
        &Default::default(),
        Default::default(),
    )
}

/// The plugin against the reference for the frames with `with`: the same output, stages and
/// counts.
fn assert_matches_reference(frames: [&Frame; 3], with: Inputs) -> Outcome {
    let outcome = run(frames, with);
    let expected = reference_run(frames, with);
    if with.shadows[1] {
        // Without them, the warp remodulates as it writes: the plugin runs no remodulation
        // stage, which the reference lists.
        assert_stages_agree(&expected, &outcome.stats);
    }
    let ran = |stage: PatchexStage| outcome.stats.extrapolations[0].stages_run & 1 << stage != 0;
    assert_eq!(
        ran(PATCHEX_STAGE_HIGHLIGHTS),
        with.sun.is_some() || with.sky.is_some()
    );
    let worst = worst_output_error(&outcome.output, &expected.output);
    assert!(worst <= 1.0, "output differs from the reference ({worst})");
    assert_eq!(
        outcome.stats.source_sanitized_pixels,
        expected.source_sanitized
    );
    assert_eq!(
        outcome.stats.extrapolations[0].sanitized_pixels,
        expected.target_sanitized
    );
    outcome
}

#[test]
fn highlight_passes_match_their_references_under_a_moving_camera() {
    let (frames, sun, sky) = rendered_frames(128, 72);
    let sky = one_mip(&sky);
    for (sun, sky) in [
        (Some(&sun), None),
        (Some(&sun), Some(&sky[..])),
        (None, Some(&sky[..])),
    ] {
        let with = Inputs {
            sun,
            sky,
            ..Default::default()
        };
        assert_matches_reference(frames.each_ref(), with);
    }
}

/// With the shadow sub-task: on the first frame with a shadow input, whose shadows stay in its
/// shading (the visibility it holds is the static casters' times the dynamic mask); on the
/// second, whose shadows are separated (the layer made again without the highlight) and whose
/// share at the target takes the highlights' part away; and with the target's mask, which
/// takes it in the share's place; the sky's reflection with them, which no shadow takes.
#[test]
fn highlight_passes_match_their_references_with_the_shadow_sub_task() {
    let (frames, sun, sky) = rendered_frames(128, 72);
    let sky = one_mip(&sky);
    for (shadows, target_mask) in [
        ([false, true], false),
        ([true, true], false),
        ([true, true], true),
    ] {
        let with = Inputs {
            shadows,
            target_mask,
            sun: Some(&sun),
            sky: Some(&sky[..]),
        };
        let outcome = assert_matches_reference(frames.each_ref(), with);
        let ran = outcome.stats.extrapolations[0].stages_run & 1 << PATCHEX_STAGE_TARGET_SHADOWS;
        assert_eq!(ran != 0, target_mask);
    }
}

/// On the glossy surfaces the sun reaches, the highlights as the target sees them bring the
/// output closer to the rendered target than frame t's carried with the surface.
#[test]
fn the_sun_and_the_sky_bring_glossy_surfaces_closer_to_the_rendered_target() {
    let (frames, sun, sky) = rendered_frames(160, 90);
    let sky = one_mip(&sky);
    let [_, source, target] = &frames;
    let glossy: Vec<usize> = (0..target.color.width * target.color.height)
        .filter(|&i| target.material.data[4 * i + 2] < 0.5 && target.sun_visibility.data[i] > 0.5)
        .filter(|&i| source.stencil.data[i] == 0.0 && target.stencil.data[i] == 0.0)
        .collect();
    let region = |image: &Image| pixels_of(image, &glossy);
    let truth = region(&target.color);
    let without = run(frames.each_ref(), Inputs::default()).output;
    let with = Inputs {
        sun: Some(&sun),
        ..Default::default()
    };
    let with_sun = run(frames.each_ref(), with).output;
    let with = Inputs {
        sky: Some(&sky[..]),
        ..with
    };
    let with_sky = run(frames.each_ref(), with).output;
    let [before, sun_only, both] =
        [&without, &with_sun, &with_sky].map(|output| psnr(&region(output), &truth));
    eprintln!(
        "{} glossy lit pixels: {before:.2} dB without the sun, {sun_only:.2} dB with it, \
         {both:.2} dB with the sky too",
        glossy.len()
    );
    assert!(glossy.len() > 2000, "only {} glossy pixels", glossy.len());
    assert!(
        sun_only > before + 1.0,
        "{sun_only} dB with the sun against {before} dB without"
    );
    assert!(
        both > sun_only + 1.0,
        "{both} dB with the sky too against {sun_only} dB with the sun alone"
    );
}

/// On the animated characters the sun lights, inside their outlines where a limb turned towards
/// or away from the sun between frame t and the target, the sun's input brings the output
/// closer to the rendered target: the warp carries the Lambert term as frame t lit it, and it is
/// lit again at the target's normal. Here the highlights' placement alone gains 1.8 dB, and with
/// the relighting 3.0 (measured by switching the relighting off).
#[test]
fn the_sun_relights_moving_objects_that_turned() {
    let (frames, sun, _) = rendered_frames(640, 360);
    let [_, source, target] = &frames;
    let direction = Vec3::from(sun.direction);
    let facing = |frame: &Frame, i: usize| {
        Vec3::from_slice(&frame.normal.data[4 * i..4 * i + 3])
            .dot(direction)
            .max(0.0)
    };
    let (width, height) = (target.color.width, target.color.height);
    let turned: Vec<usize> = (0..width * height)
        .filter(|&i| target.stencil.data[i] != 0.0 && target.sun_visibility.data[i] > 0.5)
        .filter(|&i| {
            // Frame t's texel the motion leads to, inside the object's outline there (its 3x3
            // on the same object), where the warp's own errors would not dominate.
            let (x, y) = ((i % width) as f32 + 0.5, (i / width) as f32 + 0.5);
            let [dx, dy] = [0, 1].map(|c| target.motion.data[target.motion.channels * i + c]);
            let (sx, sy) = ((x + dx).floor(), (y + dy).floor());
            let inside =
                sx >= 1.0 && sy >= 1.0 && sx + 1.0 < width as f32 && sy + 1.0 < height as f32;
            let s = sx as usize + sy as usize * width;
            let interior = inside
                && (0..9).all(|n| {
                    let neighbour = s + n % 3 + (n / 3) * width - 1 - width;
                    source.stencil.data[neighbour] == target.stencil.data[i]
                });
            interior && (facing(target, i) - facing(source, s)).abs() > 0.1
        })
        .collect();
    let region = |image: &Image| pixels_of(image, &turned);
    let truth = region(&target.color);
    let without = run(frames.each_ref(), Inputs::default()).output;
    let with = Inputs {
        sun: Some(&sun),
        ..Default::default()
    };
    let with_sun = run(frames.each_ref(), with).output;
    let [before, after] = [&without, &with_sun].map(|output| psnr(&region(output), &truth));
    eprintln!(
        "{} lit pixels of moving objects that turned: {before:.2} dB without the sun, \
         {after:.2} dB with it",
        turned.len()
    );
    assert!(turned.len() > 100, "only {} pixels", turned.len());
    assert!(
        after > before + 2.4,
        "{after} dB with the sun against {before} dB without"
    );
}

/// A sun that reaches no pixel takes nothing out and adds nothing: the frames are those without
/// one, bit for bit.
#[test]
fn a_sun_that_reaches_nothing_changes_nothing() {
    let (frames, sun, _) = rendered_frames(96, 54);
    let mut source = frames[1].clone();
    source.sun_visibility.data.fill(0.0);
    let frames = [&frames[0], &source, &frames[2]];
    let with = Inputs {
        sun: Some(&sun),
        ..Default::default()
    };
    assert_eq!(
        run(frames, with).output,
        run(frames, Inputs::default()).output
    );
}

/// NaN, infinite and out-of-range visibilities and roughnesses are sanitised and counted as the
/// reference counts them, and the output stays finite.
#[test]
fn bad_visibility_and_roughness_are_sanitised_and_counted() {
    let (frames, sun, _) = rendered_frames(96, 54);
    let [previous, source, target] = &frames;
    let (mut source, mut target) = (source.clone(), target.clone());
    let bad = [f32::NAN, f32::INFINITY, -0.5, 1.5, f32::NEG_INFINITY];
    for (i, value) in bad.iter().enumerate() {
        source.sun_visibility.data[7 * i + 3] = *value;
        // Roughness of lit pixels, which the sun's reflection reads.
        source.material.data[4 * (40 * i + 300) + 2] = *value;
        target.material.data[4 * (40 * i + 301) + 2] = *value;
    }
    let with = Inputs {
        sun: Some(&sun),
        ..Default::default()
    };
    let outcome = assert_matches_reference([previous, &source, &target], with);
    assert!(outcome.stats.source_sanitized_pixels >= bad.len() as u32);
    assert!(outcome.output.data.iter().all(|v| v.is_finite()));
}

/// Each unusable PatchexSunLight is refused with INVALID_ARGUMENT (or the image's own error),
/// with a message naming the field, and the context goes on as before.
#[test]
fn unusable_sun_lights_are_refused() {
    let (frames, sun, _) = rendered_frames(64, 36);
    let rig = Rig::new(64, 36);
    let engine = &rig.engine;
    let source = GpuFrame::upload(engine, &frames[1]);
    let wrong_format = EngineImage::new(
        engine,
        vk::Format::R8G8B8A8_UINT,
        64,
        36,
        vk::ImageUsageFlags::SAMPLED,
    );
    let valid = source.sun_light(&sun, false);
    let cases: [(PatchexSunLight, PatchexResult, &str); 6] = [
        (
            PatchexSunLight {
                direction: [0.0; 3],
                ..valid
            },
            PatchexResult::ErrorInvalidArgument,
            "direction",
        ),
        (
            PatchexSunLight {
                direction: [f32::NAN, 1.0, 0.0],
                ..valid
            },
            PatchexResult::ErrorInvalidArgument,
            "direction",
        ),
        (
            PatchexSunLight {
                illuminance: [1.0, -1.0, 1.0],
                ..valid
            },
            PatchexResult::ErrorInvalidArgument,
            "illuminance",
        ),
        (
            PatchexSunLight {
                illuminance: [f32::INFINITY, 1.0, 1.0],
                ..valid
            },
            PatchexResult::ErrorInvalidArgument,
            "illuminance",
        ),
        (
            PatchexSunLight {
                visibility: PatchexImage::default(),
                ..valid
            },
            PatchexResult::ErrorNullPointer,
            "visibility",
        ),
        (
            PatchexSunLight {
                visibility: wrong_format.describe(GBUFFER_LAYOUT),
                ..valid
            },
            PatchexResult::ErrorUnsupportedFormat,
            "visibility",
        ),
    ];
    assert_refused_then_taken(&rig, &source, "PatchexSunLight", &cases, &valid);
}

/// NaN, negative and infinite texels of the sky's map are sanitised and counted, each once, as
/// the reference counts them, and the output stays finite.
#[test]
fn bad_sky_texels_are_sanitised_and_counted() {
    let (frames, sun, clean_sky) = rendered_frames(96, 54);
    let clean_sky = one_mip(&clean_sky);
    let mut sky = clean_sky.clone();
    let bad = [f32::NAN, f32::INFINITY, -0.5, f32::NEG_INFINITY, 1e6];
    for (i, value) in bad.iter().enumerate() {
        sky[0].data[4 * (37 * i + 5) + i % 3] = *value;
    }
    let with = Inputs {
        sun: Some(&sun),
        sky: Some(&sky[..]),
        ..Default::default()
    };
    let outcome = assert_matches_reference(frames.each_ref(), with);
    let clean = Inputs {
        sky: Some(&clean_sky[..]),
        ..with
    };
    let clean = run(frames.each_ref(), clean);
    assert_eq!(
        outcome.stats.source_sanitized_pixels,
        clean.stats.source_sanitized_pixels + bad.len() as u32
    );
    assert!(outcome.output.data.iter().all(|v| v.is_finite()));
}

/// Each unusable PatchexSkyLight is refused with INVALID_ARGUMENT (or the image's own error),
/// with a message naming the map, and the context goes on as before.
#[test]
fn unusable_sky_lights_are_refused() {
    let (frames, _, sky) = rendered_frames(64, 36);
    let sky = one_mip(&sky);
    let rig = Rig::new(64, 36);
    let engine = &rig.engine;
    let source = GpuFrame::upload(engine, &frames[1]);
    let map = |format, width, height| {
        EngineImage::new(engine, format, width, height, vk::ImageUsageFlags::SAMPLED)
    };
    let float = vk::Format::R16G16B16A16_SFLOAT;
    let images = [
        map(float, 32, 16),
        map(float, 1, 1),
        map(float, PATCHEX_MAX_SKY_SIDE + 1, PATCHEX_MAX_SKY_SIDE + 1),
        map(vk::Format::R8G8B8A8_UINT, 16, 16),
    ];
    let light = |radiance| PatchexSkyLight {
        header: PatchexStructHeader::of::<PatchexSkyLight>(PATCHEX_STRUCT_TYPE_SKY_LIGHT),
        radiance,
        mip_levels: 1,
    };
    let good = upload(
        engine,
        &sky[0],
        vk::Format::R16G16B16A16_SFLOAT,
        GBUFFER_LAYOUT,
    );
    // A 32-texel map: its sixth mip would be a texel a side.
    let mips = |mip_levels| PatchexSkyLight {
        mip_levels,
        ..light(good.describe(GBUFFER_LAYOUT))
    };
    let cases = [
        (
            light(images[0].describe(GBUFFER_LAYOUT)),
            PatchexResult::ErrorInvalidArgument,
            "radiance",
        ),
        (
            light(images[1].describe(GBUFFER_LAYOUT)),
            PatchexResult::ErrorInvalidArgument,
            "radiance",
        ),
        (
            light(images[2].describe(GBUFFER_LAYOUT)),
            PatchexResult::ErrorInvalidArgument,
            "radiance",
        ),
        (
            light(images[3].describe(GBUFFER_LAYOUT)),
            PatchexResult::ErrorUnsupportedFormat,
            "radiance",
        ),
        (
            light(PatchexImage {
                width: 16,
                height: 16,
                ..PatchexImage::default()
            }),
            PatchexResult::ErrorNullPointer,
            "radiance",
        ),
        (mips(6), PatchexResult::ErrorInvalidArgument, "mip_levels"),
        (
            mips(PATCHEX_MAX_SKY_MIPS + 1),
            PatchexResult::ErrorInvalidArgument,
            "mip_levels",
        ),
    ];
    let good = light(good.describe(GBUFFER_LAYOUT));
    assert_refused_then_taken(&rig, &source, "PatchexSkyLight.", &cases, &good);
}

/// Submits `source` with each of `cases` chained, each refused with its result and a message
/// naming `name` and the case's field; then with `good`, which is taken: refused calls leave
/// the context as it was.
fn assert_refused_then_taken<T>(
    rig: &Rig,
    source: &GpuFrame,
    name: &str,
    cases: &[(T, PatchexResult, &str)],
    good: &T,
) {
    let family = rig.engine.queue_family_index;
    for (index, (light, expected, field)) in cases.iter().enumerate() {
        let mut desc = source.frame_desc(1 + index as u64, family);
        desc.header.next = light as *const T as *const c_void;
        rig.engine
            .run(|cmd| assert_eq!(rig.submit(cmd, &desc), *expected, "{}", rig.last_error()));
        let message = rig.last_error();
        assert!(
            message.contains(name) && message.contains(field),
            "{message}"
        );
    }
    let mut desc = source.frame_desc(cases.len() as u64 + 1, family);
    desc.header.next = good as *const T as *const c_void;
    rig.engine.run(|cmd| {
        assert_eq!(
            rig.submit(cmd, &desc),
            PatchexResult::Success,
            "{}",
            rig.last_error()
        )
    });
}

/// A sky prefiltered by roughness (`mip_levels` above 1): the passes read between the two mips
/// around each pixel's roughness as the reference does, and the mips change the output.
#[test]
fn a_prefiltered_sky_matches_its_reference() {
    let (frames, sun, info) = rendered_frames(128, 72);
    let sky = one_mip(&info);
    // Three mips, each one tinted apart, so that reading the wrong one shows.
    let mips: Vec<Image> = (0..3)
        .map(|level| {
            let mut mip = sky_map(&info, 32 >> level);
            for texel in mip.data.chunks_mut(4) {
                texel[level] *= 2.0;
            }
            mip
        })
        .collect();
    let with = Inputs {
        sun: Some(&sun),
        sky: Some(&mips),
        ..Default::default()
    };
    let prefiltered = assert_matches_reference(frames.each_ref(), with);
    let one_mip = run(
        frames.each_ref(),
        Inputs {
            sky: Some(&sky[..]),
            ..with
        },
    );
    assert_ne!(prefiltered.output, one_mip.output);
}
