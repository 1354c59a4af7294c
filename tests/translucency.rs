//! What is drawn over the surfaces (`PatchexTranslucencyInput`) on lavapipe through the C ABI:
//! taken apart from frame t's surfaces and placed at the target by its own motion, against the
//! plain-Rust reference on frames of the scene renderer (smoke, sparks and panes of glass over a
//! moving camera and animated characters, a fog they uncover, and smoke and fog in front of
//! them), with and without the translucency's own motion and frame t's colour before its
//! translucency; the gain where the particles are; the extremes of the mask (empty, full,
//! uniform, and values at every threshold); and bad inputs sanitised and counted or refused.
//!
//! Tolerance: the colour tolerance of `support/pipeline.rs` (2e-3 relative plus 1e-4),
//! loosened to 1e-3 absolute: the surface behind is a weighted mean of exponentials whose last
//! bits differ between the GPU and the reference, on top of the warp's.

mod support;

use std::ffi::c_void;

use ash::vk;
use glam::Vec2;
use patchex::abi::*;
use patchex::camera::Camera;
use patchex::error::PatchexResult;
use patchex::passes::warp::WarpSettings;
use patchex::reference::{self, Image};
use support::pipeline::{inputs, psnr, read_image, worst_output_error};
use support::rendered::Translucency;
use support::scene::{Frame, Scene};
use support::*;

/// A generated validation scene with a smoke column, sparks and panes of glass among its
/// characters, under a moving camera.
const SCENE: &str = "generated/autumn_07.toml";

/// A generated validation scene whose characters walk through smoke: they cover and uncover the
/// ground behind them by a pixel and more between frame t and the target.
const MOVERS: &str = "generated/platforms_06.toml";

/// A generated validation scene whose smoke rises between the camera and its characters.
const SMOKE_IN_FRONT: &str = "generated/autumn_09.toml";

/// What the frames show over the surfaces.
#[derive(Clone, Copy)]
enum Content {
    /// The scene as it is: particles and glass.
    Everything,
    /// The particles alone, the scene's glass taken out.
    Particles,
}

/// Frame t and the instant halfway to t+1 (frames 2 and 3 of the doubled stream), with frame t's
/// translucency input and the target's mask.
struct Frames {
    source: Frame,
    target: Frame,
    input: Translucency,
    target_mask: Image,
}

fn rendered_frames(width: u32, height: u32, content: Content) -> Frames {
    rendered_frames_of(SCENE, width, height, content)
}

/// The same frames of another scene.
fn rendered_frames_of(scene: &str, width: u32, height: u32, content: Content) -> Frames {
    let mut world = support::rendered::load(scene);
    if let Content::Particles = content {
        let mut description = world.description.clone();
        description.glass.clear();
        world =
            patchex_scene::World::from_description(description, &support::rendered::assets_dir())
                .expect("the scene without its glass loads");
    }
    let sequence = support::rendered::render_world(&world, 4, width, height);
    let mut translucency = sequence
        .translucency
        .into_iter()
        .skip(2)
        .map(|t| t.expect("the scene draws translucency"));
    let input = translucency.next().expect("frame 2");
    let target_mask = translucency.next().expect("frame 3").mask;
    let mut frames = sequence.frames.into_iter().skip(2);
    Frames {
        source: frames.next().expect("frame 2"),
        target: frames.next().expect("frame 3"),
        input,
        target_mask,
    }
}

/// How frame t goes.
#[derive(Clone, Copy)]
enum With {
    Nothing,
    /// The mask alone.
    Mask,
    /// The mask and the particles' motion.
    MaskAndMotion,
    /// The mask, the particles' motion and the colour before the translucency.
    Everything,
}

struct Outcome {
    output: Image,
    stats: PatchexFrameStats,
}

/// Submits `source` with as much of `given` as `with` says, and extrapolates the target at
/// alpha 1/2, on a fresh rig under validation that must stay silent.
fn run(frames: &Frames, given: &Translucency, with: With) -> Outcome {
    let (width, height) = (frames.source.color.width, frames.source.color.height);
    let rig = Rig::new(width as u32, height as u32);
    let engine = &rig.engine;
    let family = engine.queue_family_index;
    let source = GpuFrame::upload(engine, &frames.source);
    let target = GpuFrame::upload(engine, &frames.target);
    let output = output_image(engine, width as u32, height as u32);
    let gpu_mask = upload(engine, &given.mask, vk::Format::R32_SFLOAT, GBUFFER_LAYOUT);
    let gpu_motion = upload(
        engine,
        &given.motion,
        vk::Format::R32G32_SFLOAT,
        MOTION_LAYOUT,
    );
    let gpu_opaque = upload(
        engine,
        &given.opaque_color,
        vk::Format::R32G32B32A32_SFLOAT,
        GBUFFER_LAYOUT,
    );
    let input = PatchexTranslucencyInput {
        header: PatchexStructHeader::of::<PatchexTranslucencyInput>(
            PATCHEX_STRUCT_TYPE_TRANSLUCENCY_INPUT,
        ),
        mask: gpu_mask.describe(GBUFFER_LAYOUT),
        motion_vectors: match with {
            With::MaskAndMotion | With::Everything => gpu_motion.describe(MOTION_LAYOUT),
            _ => PatchexImage::default(),
        },
        motion_vector_scale: [1.0, 1.0],
        opaque_color: match with {
            With::Everything => gpu_opaque.describe(GBUFFER_LAYOUT),
            _ => PatchexImage::default(),
        },
    };
    let mut desc = source.frame_desc(1, family);
    if !matches!(with, With::Nothing) {
        desc.header.next = &input as *const _ as *const c_void;
    }
    engine.run(|cmd| {
        rig.submit_ok(cmd, &desc);
        let extrapolate = target.extrapolate_desc(&output, 0.5, family);
        rig.extrapolate_ok(cmd, &extrapolate);
    });
    let (result, stats) = rig.stats(1);
    assert_eq!(result, PatchexResult::Success, "{}", rig.last_error());
    let messages = engine.take_validation_messages();
    assert!(messages.is_empty(), "validation: {messages:?}");
    Outcome {
        output: read_image(engine, &output, width, height),
        stats,
    }
}

fn reference_run(frames: &Frames, given: &Translucency, with: With) -> reference::Extrapolation {
    let source_camera = Camera::from_abi(&frames.source.camera, "source").unwrap();
    let target_camera = Camera::from_abi(&frames.target.camera, "target").unwrap();
    let translucency = match with {
        With::Nothing => None,
        With::Mask | With::MaskAndMotion | With::Everything => {
            Some(reference::translucency::Input {
                mask: &given.mask,
                motion: matches!(with, With::MaskAndMotion | With::Everything)
                    .then_some((&given.motion, [1.0, 1.0])),
                opaque: matches!(with, With::Everything).then_some(&given.opaque_color),
            })
        }
    };
    reference::extrapolate(
        &reference::FrameInputs {
            translucency,
            ..inputs(&frames.source, &source_camera)
        },
        &inputs(&frames.target, &target_camera),
        None,
        0.5,
        &WarpSettings::default(),
        &Default::default(),
        Default::default(),
    )
}

/// The plugin against the reference: the same output, stages and counts.
fn assert_matches_reference(frames: &Frames, given: &Translucency, with: With) -> Outcome {
    let outcome = run(frames, given, with);
    let expected = reference_run(frames, given, with);
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
fn translucency_passes_match_their_references_with_each_input() {
    let frames = rendered_frames(128, 72, Content::Everything);
    for with in [With::Mask, With::MaskAndMotion, With::Everything] {
        let outcome = assert_matches_reference(&frames, &frames.input, with);
        let ran = outcome.stats.extrapolations[0].stages_run & 1 << PATCHEX_STAGE_TRANSLUCENCY;
        assert_ne!(ran, 0);
    }
}

/// Frame t's input replaced by a fog of coverage 0.5 held still on screen, bare at the texels
/// `bare(index, stencil id)` picks.
fn still_fog(frames: &Frames, bare: impl Fn(usize, f32) -> bool) -> Translucency {
    let mut fog = frames.input.clone();
    for (i, (a, id)) in fog
        .mask
        .data
        .iter_mut()
        .zip(&frames.source.stencil.data)
        .enumerate()
    {
        *a = if bare(i, *id) { 0.0 } else { 0.5 };
    }
    fog.motion.data.fill(0.0);
    fog
}

/// A fog over the ground behind the characters, held still on screen: where a character moves
/// off ground whose fog it hid in frame t, the splat brings nothing, and the layer is spread
/// there from the ground around, on the GPU as in the reference.
#[test]
fn a_layer_a_character_uncovers_matches_the_reference() {
    let frames = rendered_frames_of(MOVERS, 128, 72, Content::Everything);
    let fog = still_fog(&frames, |_, id| id != 0.0);
    let uncovered = frames
        .source
        .stencil
        .data
        .iter()
        .zip(&frames.target.stencil.data)
        .filter(|(t, target)| **t != 0.0 && **target == 0.0)
        .count();
    assert!(uncovered > 10, "the characters uncover {uncovered} pixels");
    for with in [With::MaskAndMotion, With::Everything] {
        assert_matches_reference(&frames, &fog, with);
    }
}

/// A layer in front of the characters: the scene's smoke, and a fog over everything with every
/// other texel of the characters left bare, held still on screen. Where the texel a character
/// showed in frame t is bare but its own texels around lie under the layer, the layer covers it,
/// on the GPU as in the reference.
#[test]
fn a_layer_over_a_character_matches_the_reference() {
    let frames = rendered_frames_of(SMOKE_IN_FRONT, 128, 72, Content::Everything);
    let width = frames.source.stencil.width;
    let fog = still_fog(&frames, |i, id| {
        id != 0.0 && (i % width + i / width) % 2 == 1
    });
    let characters = frames
        .source
        .stencil
        .data
        .iter()
        .filter(|id| **id != 0.0)
        .count();
    assert!(characters > 20, "the characters cover {characters} pixels");
    for given in [&frames.input, &fog] {
        for with in [With::MaskAndMotion, With::Everything] {
            assert_matches_reference(&frames, given, with);
        }
    }
}

/// Where the particles are, in frame t or at the target, the mask and their motion bring the
/// output closer to the rendered target than smoke carried as the surfaces behind it, and the
/// colour before the translucency closer still. (Panes of glass, which the warp already carries
/// well, gain less: the guides measure them.)
#[test]
fn the_mask_brings_the_particles_closer_to_the_rendered_target() {
    let frames = rendered_frames(320, 180, Content::Particles);
    let mask = &frames.input.mask;
    let covered: Vec<usize> = (0..mask.data.len())
        .filter(|&i| mask.data[i] > 0.02 || frames.target_mask.data[i] > 0.02)
        .collect();
    // Tone-mapped as the eval scores, so that the sparks' HDR does not outweigh the smoke.
    let region = |image: &Image| Image {
        width: covered.len(),
        height: 1,
        channels: 4,
        data: covered
            .iter()
            .flat_map(|&i| image.data[4 * i..4 * i + 4].iter().map(|v| v / (1.0 + v)))
            .collect(),
    };
    let truth = region(&frames.target.color);
    let score = |with| psnr(&region(&run(&frames, &frames.input, with).output), &truth);
    let without = score(With::Nothing);
    let with = score(With::MaskAndMotion);
    let exact = score(With::Everything);
    eprintln!(
        "{} covered pixels: {without:.2} dB without the mask, {with:.2} dB with it, {exact:.2} \
         dB with the colour before the translucency as well",
        covered.len()
    );
    assert!(covered.len() > 200, "only {} covered pixels", covered.len());
    assert!(
        with > without + 0.3,
        "{with} dB with the mask against {without} dB without"
    );
    assert!(
        exact > with + 0.3,
        "{exact} dB with the colour before the translucency against {with} dB without it"
    );
}

/// An empty mask changes nothing: the frame is the one without the input, bit for bit; nor does a
/// full mask or one as uniform as a pane of glass filling the view, nor the scene's own mask
/// thinned under a fifth without the colour from before the translucency, nor that mask moving
/// exactly as the surfaces behind it, even with that colour (glass set in a wall): each is left in
/// the colour and carried with them.
#[test]
fn an_empty_full_uniform_or_surface_bound_mask_changes_nothing() {
    let frames = rendered_frames(96, 54, Content::Everything);
    let (width, height) = (frames.input.mask.width, frames.input.mask.height);
    let without = run(&frames, &frames.input, With::Nothing).output;
    for coverage in [0.0, 1.0, 0.3] {
        let mut mask = Image::new(width, height, 1);
        mask.data.fill(coverage);
        let given = Translucency {
            mask,
            ..frames.input.clone()
        };
        let with = assert_matches_reference(&frames, &given, With::MaskAndMotion);
        assert_eq!(with.output, without, "a mask of {coverage} everywhere");
    }
    let thin = Translucency {
        mask: Image {
            data: frames.input.mask.data.iter().map(|a| 0.199 * a).collect(),
            ..frames.input.mask.clone()
        },
        ..frames.input.clone()
    };
    let with = assert_matches_reference(&frames, &thin, With::MaskAndMotion);
    assert_eq!(with.output, without, "the mask thinned under a fifth");
    let given = Translucency {
        motion: frames.source.motion.clone(),
        ..frames.input.clone()
    };
    for with in [With::MaskAndMotion, With::Everything] {
        let outcome = assert_matches_reference(&frames, &given, with);
        assert_eq!(outcome.output, without, "the mask moving with the surfaces");
    }
}

/// Coverage on each side of every threshold the passes hold it to (the least taken apart, with
/// and without the colour before the translucency, the uniform test's tolerance, subnormal, 1 and
/// just under), and motion at and past what a half float holds, match the reference with each
/// input and leave the output finite.
#[test]
fn mask_and_motion_at_their_thresholds_match_the_reference() {
    let frames = rendered_frames(96, 54, Content::Everything);
    let mut given = frames.input.clone();
    let coverages = [
        0.05 - 1e-6,
        0.05,
        0.2 - 1e-6,
        0.2,
        1e-40,
        1.0 - 1e-7,
        1.0,
        0.3,
        0.31,
        0.2999,
    ];
    let motions = [65504.0, -65504.0, 65520.0, 1e-8, -0.5];
    for (i, value) in given.mask.data.iter_mut().enumerate().step_by(3) {
        *value = coverages[(i / 3) % coverages.len()];
    }
    for (i, value) in given.motion.data.iter_mut().enumerate().step_by(5) {
        *value = motions[(i / 5) % motions.len()];
    }
    for with in [With::Mask, With::MaskAndMotion, With::Everything] {
        let outcome = assert_matches_reference(&frames, &given, with);
        assert!(outcome.output.data.iter().all(|v| v.is_finite()));
    }
}

/// NaN, infinite and out-of-range coverage, motion and colour before the translucency are
/// sanitised and counted as the reference counts them, and the output stays finite.
#[test]
fn bad_mask_motion_and_colour_are_sanitised_and_counted() {
    let frames = rendered_frames(96, 54, Content::Everything);
    let mut given = frames.input.clone();
    let bad = [f32::NAN, f32::INFINITY, -0.5, 1.5, f32::NEG_INFINITY];
    let covered: Vec<usize> = (0..given.mask.data.len())
        .filter(|&i| given.mask.data[i] > 0.1)
        .collect();
    assert!(covered.len() > 3 * bad.len(), "too few covered pixels");
    for (i, value) in bad.iter().enumerate() {
        given.mask.data[7 * i + 3] = *value;
        given.motion.data[2 * covered[3 * i]] = *value;
        given.motion.data[2 * covered[3 * i + 1] + 1] = 1e6;
        given.opaque_color.data[4 * covered[3 * i + 2] + i % 3] = *value * 1e5;
    }
    for with in [With::MaskAndMotion, With::Everything] {
        let outcome = assert_matches_reference(&frames, &given, with);
        assert!(outcome.stats.source_sanitized_pixels >= bad.len() as u32);
        assert!(outcome.output.data.iter().all(|v| v.is_finite()));
    }
}

/// A mask of another size than the frame, or none at all, and a colour before the translucency
/// of another size, are refused by name.
#[test]
fn a_missing_or_unusable_mask_or_colour_is_refused() {
    let rig = Rig::new(64, 36);
    let engine = &rig.engine;
    let frame = Scene::new(64, 36).render(0.0, Vec2::ZERO, 0.0);
    let source = GpuFrame::upload(engine, &frame);
    let small = upload(
        engine,
        &Image::new(32, 18, 1),
        vk::Format::R32_SFLOAT,
        GBUFFER_LAYOUT,
    );
    let mask = upload(
        engine,
        &Image::new(64, 36, 1),
        vk::Format::R32_SFLOAT,
        GBUFFER_LAYOUT,
    );
    let small_color = upload(
        engine,
        &Image::new(32, 18, 4),
        vk::Format::R32G32B32A32_SFLOAT,
        GBUFFER_LAYOUT,
    );
    let none = PatchexImage::default();
    for (mask, opaque_color, expected) in [
        (none, none, "PatchexTranslucencyInput.mask"),
        (
            small.describe(GBUFFER_LAYOUT),
            none,
            "PatchexTranslucencyInput.mask",
        ),
        (
            mask.describe(GBUFFER_LAYOUT),
            small_color.describe(GBUFFER_LAYOUT),
            "PatchexTranslucencyInput.opaque_color",
        ),
    ] {
        let input = PatchexTranslucencyInput {
            header: PatchexStructHeader::of::<PatchexTranslucencyInput>(
                PATCHEX_STRUCT_TYPE_TRANSLUCENCY_INPUT,
            ),
            mask,
            motion_vectors: none,
            motion_vector_scale: [1.0, 1.0],
            opaque_color,
        };
        let mut desc = source.frame_desc(1, engine.queue_family_index);
        desc.header.next = &input as *const _ as *const c_void;
        engine.run(|cmd| {
            assert_ne!(rig.submit(cmd, &desc), PatchexResult::Success);
        });
        let error = rig.last_error();
        assert!(error.contains(expected), "{error}");
    }
}
