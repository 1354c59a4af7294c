//! The shadow sub-task on lavapipe through the C ABI: separation, Farneback flow and the shadow
//! layer's warp against their plain-Rust references on frames of the scene renderer, the flow
//! against the true motion of an analytic shadow, the gain it brings, and that without a shadow
//! input nothing of it runs.
//!
//! Tolerances. The flow solves a 2x2 system per pixel from sums of a few hundred products, so
//! last-bit differences of exp() and fused multiply-adds grow where the system is weak; the flow
//! is compared within 0.02 pixel plus 1% of its length, after the f16 rounding of the
//! diagnostics image. The layers' luminances and the output follow the colour tolerance of
//! `support/pipeline.rs` (2e-3 relative plus 1e-4), loosened to 1e-3 absolute for the warped
//! layer, which samples the flow bilinearly.

mod support;

use std::ffi::c_void;

use ash::vk;
use glam::{Vec2, Vec3};
use patchex::abi::*;
use patchex::camera::Camera;
use patchex::error::PatchexResult;
use patchex::frame::counters::REGION_BYTES;
use patchex::passes::shadow_flow::{mask_step, FlowSettings, MAX_LEVELS, MAX_WINDOW_RADIUS};
use patchex::passes::warp::WarpSettings;
use patchex::reference::{self, round_to_f16, Image, ShadowInputs};
use support::pipeline::{inputs, pixels_of, psnr, read_image, worst_output_error};
use support::scene::{Frame, Scene};
use support::*;

const LUMINANCE: Vec3 = Vec3::new(0.2126, 0.7152, 0.0722);

/// A rig whose context runs the shadow sub-task on frames with a shadow input.
fn shadows_rig(max_width: u32, max_height: u32) -> Rig {
    Rig::with_create_info(max_width, max_height, |info| {
        info.preset = PATCHEX_PRESET_WARP_AND_SHADOWS
    })
}

/// What one run of three frames gave back.
struct ShadowOutcome {
    output: Image,
    /// RG flow, B layer luminance, A luminance of the shadows' share at the target
    /// (`PatchexShadowDiagnostics`).
    diagnostics: Image,
    stats: PatchexFrameStats,
}

/// Submits `previous` (frame 1) and `source` (frame 2), with their shadow inputs when
/// `with_shadows`, and extrapolates `target` at `alpha` from frame 2.
fn run_with_shadows(
    rig: &Rig,
    previous: &Frame,
    source: &Frame,
    target: &Frame,
    alpha: f32,
    with_shadows: bool,
) -> ShadowOutcome {
    let frames = [previous, source, target];
    run_with_shadows_warped(rig, frames, alpha, [with_shadows; 2], None, false, None)
}

/// `run_with_shadows` with the extrapolation's warp settings `warp`, a shadow input for each
/// submitted frame where `with_shadows` says so (with `flow` chained on it), and the target's
/// mask as a target shadow input when `target_shadows`.
fn run_with_shadows_warped(
    rig: &Rig,
    [previous, source, target]: [&Frame; 3],
    alpha: f32,
    with_shadows: [bool; 2],
    warp: Option<&WarpSettings>,
    target_shadows: bool,
    flow: Option<&PatchexShadowFlowSettings>,
) -> ShadowOutcome {
    let engine = &rig.engine;
    let family = engine.queue_family_index;
    let (width, height) = (source.color.width, source.color.height);
    let frames = [previous, source].map(|frame| GpuFrame::upload(engine, frame));
    let gpu_target = GpuFrame::upload(engine, target);
    let output = output_image(engine, width as u32, height as u32);
    let diagnostics_image = output_image(engine, width as u32, height as u32);
    let warp = warp.map(WarpSettings::to_abi);
    let diagnostics = PatchexShadowDiagnostics {
        header: PatchexStructHeader {
            next: warp
                .as_ref()
                .map_or(std::ptr::null(), |w| w as *const _ as *const c_void),
            ..PatchexStructHeader::of::<PatchexShadowDiagnostics>(
                PATCHEX_STRUCT_TYPE_SHADOW_DIAGNOSTICS,
            )
        },
        image: diagnostics_image.describe(OUTPUT_LAYOUT),
    };
    let target_shadow_input = PatchexTargetShadowInput {
        header: PatchexStructHeader {
            next: &diagnostics as *const _ as *const c_void,
            ..PatchexStructHeader::of::<PatchexTargetShadowInput>(
                PATCHEX_STRUCT_TYPE_TARGET_SHADOW_INPUT,
            )
        },
        mask: gpu_target.shadow_input().mask,
    };
    let shadow_inputs = frames.each_ref().map(|frame| PatchexShadowInput {
        header: PatchexStructHeader {
            next: flow.map_or(std::ptr::null(), |f| f as *const _ as *const c_void),
            ..frame.shadow_input().header
        },
        ..frame.shadow_input()
    });
    for (index, frame) in frames.iter().enumerate() {
        let mut desc = frame.frame_desc(1 + index as u64, family);
        if with_shadows[index] {
            desc.header.next = &shadow_inputs[index] as *const _ as *const c_void;
        }
        engine.run(|cmd| {
            rig.submit_ok(cmd, &desc);
            if index == 1 {
                let mut extrapolate = gpu_target.extrapolate_desc(&output, alpha, family);
                extrapolate.header.next = if target_shadows {
                    &target_shadow_input as *const _ as *const c_void
                } else {
                    &diagnostics as *const _ as *const c_void
                };
                rig.extrapolate_ok(cmd, &extrapolate);
            }
        });
    }
    let (result, stats) = rig.stats(2);
    assert_eq!(result, PatchexResult::Success, "{}", rig.last_error());
    ShadowOutcome {
        output: read_image(engine, &output, width, height),
        diagnostics: read_image(engine, &diagnostics_image, width, height),
        stats,
    }
}

fn reference_run(
    previous: &Frame,
    source: &Frame,
    target: &Frame,
    alpha: f32,
    warp: &WarpSettings,
    target_shadows: bool,
    flow: FlowSettings,
) -> reference::Extrapolation {
    let previous_camera = Camera::from_abi(&previous.camera, "previous").unwrap();
    let source_camera = Camera::from_abi(&source.camera, "source").unwrap();
    let target_camera = Camera::from_abi(&target.camera, "target").unwrap();
    reference::extrapolate(
        &inputs(source, &source_camera),
        &inputs(target, &target_camera),
        Some(&ShadowInputs {
            color_without_dynamic_shadows: &source.color_without_dynamic_shadows,
            mask: &source.shadow_mask,
            previous: Some((&previous.shadow_mask, &previous.stencil, &previous_camera)),
            flow,
            // The rigs are made for the frames' own size.
            mask_step: mask_step(vk::Extent2D {
                width: source.color.width as u32,
                height: source.color.height as u32,
            }),
            target_mask: target_shadows.then_some(&target.shadow_mask),
        }),
        alpha,
        warp,
        &Default::default(),
        Default::default(),
    )
}

fn luminance(pixel: &[f32]) -> f32 {
    Vec3::from_slice(pixel).dot(LUMINANCE)
}

/// Worst error of `got` against `want` in units of `absolute + relative * |want|`.
fn worst_error(got: f32, want: f32, absolute: f32, relative: f32) -> f32 {
    (got - want).abs() / (absolute + relative * want.abs())
}

/// Frames t-1 and t of `scene` (frames 0 and 2 of its doubled stream) and the instant halfway
/// to t+1 (frame 3), rendered at `width` x `height`.
fn rendered_frames(scene: &str, width: u32, height: u32) -> [Frame; 3] {
    let sequence = support::rendered::render(scene, 4, width, height);
    let Ok([previous, _, source, target]) = <[Frame; 4]>::try_from(sequence.frames) else {
        unreachable!("four frames")
    };
    [previous, source, target]
}

/// `run_with_shadows_warped` at alpha 1/2 on a fresh rig of the frames' size, under validation
/// that must stay silent.
fn run_validated(
    frames: [&Frame; 3],
    with_shadows: [bool; 2],
    warp: Option<&WarpSettings>,
    target_shadows: bool,
    flow: Option<&PatchexShadowFlowSettings>,
) -> ShadowOutcome {
    let (width, height) = (frames[1].color.width, frames[1].color.height);
    let rig = shadows_rig(width as u32, height as u32);
    let outcome =
        run_with_shadows_warped(&rig, frames, 0.5, with_shadows, warp, target_shadows, flow);
    let messages = rig.engine.take_validation_messages();
    assert!(messages.is_empty(), "validation: {messages:?}");
    outcome
}

#[test]
fn shadow_passes_match_their_references_on_rendered_frames() {
    assert_shadow_passes_match_their_references(
        "shadow_terrain.toml",
        128,
        72,
        &WarpSettings::default(),
        false,
    );
}

/// Under an orbiting camera, where the flow starts at the ground's motion between the cameras.
#[test]
fn shadow_passes_match_their_references_under_a_moving_camera() {
    assert_shadow_passes_match_their_references(
        "fast_run.toml",
        128,
        72,
        &WarpSettings::default(),
        false,
    );
}

/// With the target's mask as a target shadow input, under a moving camera: the flow's warp does
/// not run, the sun's share comes from the carried layer and from its mean.
#[test]
fn target_shadow_passes_match_their_references_under_a_moving_camera() {
    assert_shadow_passes_match_their_references(
        "fast_run.toml",
        128,
        72,
        &WarpSettings::default(),
        true,
    );
}

/// The target's mask gives the shadow of an animated character the shape it has at the target,
/// which the flow cannot: over the static pixels in the characters' shadow at frame t or at the
/// target, the output comes closer to the rendered target than with the shadows the flow moves.
#[test]
fn a_target_shadow_mask_brings_animated_shadows_closer_than_the_flow() {
    let frames = rendered_frames("fast_run.toml", 160, 90);
    let [_, source, target] = &frames;
    let run = |target_shadows| {
        run_validated(frames.each_ref(), [true; 2], None, target_shadows, None).output
    };
    let (flow, masked) = (run(false), run(true));
    let shadowed: Vec<usize> = (0..source.shadow_mask.data.len())
        .filter(|&i| source.shadow_mask.data[i] < 0.95 || target.shadow_mask.data[i] < 0.95)
        .filter(|&i| source.stencil.data[i] == 0.0 && target.stencil.data[i] == 0.0)
        .collect();
    let region = |image: &Image| pixels_of(image, &shadowed);
    let truth = region(&target.color);
    let (psnr_flow, psnr_masked) = (psnr(&region(&flow), &truth), psnr(&region(&masked), &truth));
    eprintln!(
        "{} shadow pixels: {psnr_flow:.2} dB with the flow's shadows, {psnr_masked:.2} dB with \
         the target's mask",
        shadowed.len()
    );
    assert!(
        shadowed.len() > 80,
        "only {} pixels in shadow",
        shadowed.len()
    );
    assert!(
        psnr_masked > psnr_flow + 3.0,
        "{psnr_masked} dB with the target's mask against {psnr_flow} dB with the flow"
    );
}

/// Target masks at the extremes: all lit (the target has no dynamic shadow, so static ground
/// comes out as lit without one) and all in shadow (every static pixel loses the sun's share).
/// Both match the reference, and the shadowed output is darker wherever frame t had sun.
#[test]
fn target_shadow_masks_all_lit_and_all_shadowed_match_the_reference() {
    let [previous, source, target] = &rendered_frames("fast_run.toml", 128, 72);
    let outputs = [1.0, 0.0].map(|visibility| {
        let mut target = target.clone();
        target.shadow_mask.data.fill(visibility);
        let outcome = run_validated([previous, source, &target], [true; 2], None, true, None);
        let expected = reference_run(
            previous,
            source,
            &target,
            0.5,
            &WarpSettings::default(),
            true,
            FlowSettings::default(),
        );
        let worst = worst_output_error(&outcome.output, &expected.output);
        assert!(
            worst <= 1.0,
            "mask {visibility}: output differs from the reference ({worst})"
        );
        outcome.output
    });
    let [lit, shadowed] = &outputs;
    let pixels = lit.width * lit.height;
    let darker = (0..pixels)
        .filter(|&i| luminance(&shadowed.data[4 * i..]) < 0.98 * luminance(&lit.data[4 * i..]))
        .count();
    assert!(
        darker > pixels / 4,
        "only {darker} pixels darker all in shadow"
    );
}

/// With the flow off (levels 0), a target mask gives the very frames it gives with the flow,
/// and the submit runs no flow and holds no flow images; without a mask the shadows stay where
/// the frame's warp carries them, as the reference keeps them.
#[test]
fn with_the_flow_off_the_target_mask_gives_the_same_frames_for_less() {
    let frames = rendered_frames("fast_run.toml", 128, 72);
    let [previous, source, target] = &frames;
    let off = FlowSettings::off().to_abi();
    let run = |target_shadows, flow| {
        run_validated(frames.each_ref(), [true; 2], None, target_shadows, flow)
    };
    let with_flow = run(true, None);
    let without_flow = run(true, Some(&off));
    assert_eq!(with_flow.output, without_flow.output);
    assert_eq!(
        without_flow.stats.shadow_history,
        PATCHEX_SHADOW_HISTORY_SEPARATED
    );
    let flowed = |outcome: &ShadowOutcome| {
        outcome.stats.submit_stages_run & 1 << PATCHEX_STAGE_SHADOW_FLOW != 0
    };
    assert!(flowed(&with_flow) && !flowed(&without_flow));
    // Nor does the context hold the flow's atlases.
    assert!(
        without_flow.stats.device_memory_bytes < with_flow.stats.device_memory_bytes,
        "{} bytes without the flow against {} with it",
        without_flow.stats.device_memory_bytes,
        with_flow.stats.device_memory_bytes
    );

    let carried = run(false, Some(&off));
    let flow = FlowSettings::off();
    let expected = reference_run(
        previous,
        source,
        target,
        0.5,
        &WarpSettings::default(),
        false,
        flow,
    );
    support::pipeline::assert_stages_agree(&expected, &carried.stats);
    let worst = worst_output_error(&carried.output, &expected.output);
    assert!(worst <= 1.0, "output differs from the reference ({worst})");
    assert!(
        carried
            .diagnostics
            .data
            .chunks(4)
            .all(|p| p[0] == 0.0 && p[1] == 0.0),
        "no flow, no motion"
    );
}

/// With the motion-vector warp as the frame's, whose warp of the layer stores the shadow's
/// share as the G-buffer warp's does.
#[test]
fn shadow_passes_match_their_references_with_the_motion_vector_warp() {
    let warp = WarpSettings {
        kind: PATCHEX_WARP_MOTION_VECTOR,
        ..WarpSettings::default()
    };
    assert_shadow_passes_match_their_references("shadow_terrain.toml", 128, 72, &warp, false);
}

/// The target mask with the motion-vector warp as the frame's, which carries the layer for it
/// as the G-buffer warp does, and with the G-buffer warp's nearest-texel fill, which leaves no
/// holes to a fill pass.
#[test]
fn target_shadow_passes_match_their_references_with_other_warps() {
    for warp in [
        WarpSettings {
            kind: PATCHEX_WARP_MOTION_VECTOR,
            ..WarpSettings::default()
        },
        WarpSettings {
            hole_fill: PATCHEX_HOLE_FILL_NEAREST,
            ..WarpSettings::default()
        },
    ] {
        assert_shadow_passes_match_their_references("fast_run.toml", 128, 72, &warp, true);
    }
}

/// A frame wider than 1280 pixels: the flow's finest level averages 4 x 4 pixels.
#[test]
fn shadow_flow_of_a_large_frame_starts_coarser_as_the_reference_does() {
    let extent = vk::Extent2D {
        width: 1344,
        height: 96,
    };
    assert_eq!(mask_step(extent), 4);
    assert_shadow_passes_match_their_references(
        "shadow_terrain.toml",
        extent.width,
        extent.height,
        &WarpSettings::default(),
        false,
    );
}

/// The flow's windows at their extremes, one texel and the widest, and its deepest pyramid:
/// each iteration sums its window in workgroup memory, in strips that the width decides.
#[test]
fn shadow_flow_matches_its_reference_at_the_extremes_of_its_window() {
    for (window_radius, levels) in [(1, MAX_LEVELS), (MAX_WINDOW_RADIUS, MAX_LEVELS)] {
        let flow = FlowSettings {
            window_radius,
            levels,
            ..FlowSettings::default()
        };
        assert_shadow_passes_match_their_references_with(
            "fast_run.toml",
            160,
            90,
            &WarpSettings::default(),
            false,
            flow,
        );
    }
}

/// The flow's iterations report the bytes of the level they run over, not of the atlases that
/// hold every level: one more iteration at one level reads frame t's and frame t-1's expansions
/// (RGBA32F and R32F) and the estimate (RG32F) over level 0, and writes the new flow (RG32F).
#[test]
fn each_flow_iteration_counts_the_bytes_of_its_level() {
    let frames = rendered_frames("fast_run.toml", 128, 72);
    let flow_bytes = |iterations| {
        let flow = FlowSettings {
            levels: 1,
            iterations,
            ..FlowSettings::default()
        };
        let outcome = run_validated(
            frames.each_ref(),
            [true; 2],
            None,
            false,
            Some(&flow.to_abi()),
        );
        let stage = PATCHEX_STAGE_SHADOW_FLOW as usize;
        let traffic = &outcome.stats.submit_traffic;
        [traffic.bytes_read[stage], traffic.bytes_written[stage]]
    };
    let [one, two] = [flow_bytes(1), flow_bytes(2)];
    let level_texels = 64 * 36;
    assert_eq!(
        mask_step(vk::Extent2D {
            width: 128,
            height: 72
        }),
        2
    );
    assert_eq!(two[0] - one[0], (2 * (16 + 4) + 8) * level_texels, "read");
    assert_eq!(two[1] - one[1], 8 * level_texels, "written");
}

fn assert_shadow_passes_match_their_references(
    scene: &str,
    width: u32,
    height: u32,
    warp: &WarpSettings,
    target_shadows: bool,
) {
    assert_shadow_passes_match_their_references_with(
        scene,
        width,
        height,
        warp,
        target_shadows,
        FlowSettings::default(),
    );
}

fn assert_shadow_passes_match_their_references_with(
    scene: &str,
    width: u32,
    height: u32,
    warp: &WarpSettings,
    target_shadows: bool,
    flow: FlowSettings,
) {
    let frames = rendered_frames(scene, width, height);
    let [previous, source, target] = &frames;
    let outcome = run_validated(
        frames.each_ref(),
        [true; 2],
        Some(warp),
        target_shadows,
        Some(&flow.to_abi()),
    );
    let expected = reference_run(previous, source, target, 0.5, warp, target_shadows, flow);
    support::pipeline::assert_stages_agree(&expected, &outcome.stats);
    let shadows = expected.shadows.as_ref().expect("a shadow input was given");

    let (mut flow_worst, mut layer_worst, mut share_worst) = (0.0f32, 0.0f32, 0.0f32);
    let mut moving = 0;
    for y in 0..height as usize {
        for x in 0..width as usize {
            let got = outcome.diagnostics.at(x, y);
            let flow = shadows.flow.at(x, y);
            for c in 0..2 {
                let want = round_to_f16(flow[c]);
                flow_worst = flow_worst.max(worst_error(got[c], want, 0.02, 0.01));
            }
            moving += (Vec2::new(flow[0], flow[1]).length() > 0.5) as usize;
            let layer = round_to_f16(luminance(shadows.separated.shadow_layer.at(x, y)));
            layer_worst = layer_worst.max(worst_error(got[2], layer, 1e-4, 2e-3));
            let share = round_to_f16(luminance(shadows.share.at(x, y)));
            share_worst = share_worst.max(worst_error(got[3], share, 1e-3, 2e-3));
        }
    }
    let output_worst = worst_output_error(&outcome.output, &expected.output);
    eprintln!(
        "worst / tolerance: flow {flow_worst:.3}, layer {layer_worst:.3}, shadow share \
         {share_worst:.3}, output {output_worst:.3}; {moving} pixels of flow over 0.5 px"
    );
    assert!(flow_worst <= 1.0, "flow differs from the reference");
    assert!(
        layer_worst <= 1.0,
        "shadow layer differs from the reference"
    );
    assert!(
        share_worst <= 1.0,
        "shadow share differs from the reference"
    );
    assert!(output_worst <= 1.0, "output differs from the reference");
    // The case is real: the character's shadow moves and darkens the ground.
    assert!(moving > 50, "only {moving} pixels of the flow move");
    let shadowed = (0..(width * height) as usize)
        .filter(|&i| source.shadow_mask.data[i] < 0.5)
        .count();
    assert!(shadowed > 50, "only {shadowed} pixels in shadow");
    assert_eq!(
        outcome.stats.source_sanitized_pixels, shadows.separated.sanitized,
        "sanitised pixels of frame t"
    );
    assert_eq!(
        outcome.stats.extrapolations[0].sanitized_pixels, expected.target_sanitized,
        "sanitised pixels of the target"
    );
}

/// Frame t's shadows with no frame t-1 to measure their drift from stay on their receivers:
/// under an orbiting camera the output is the one without a shadow input, the shadows' share
/// is zero and the shadow warp stage only clears it, dispatching and reading nothing. (Moved by
/// a zero flow instead, they would stay put on the screen while the ground turns under them.)
#[test]
fn untracked_shadows_stay_on_their_receivers_under_a_moving_camera() {
    let (width, height) = (128, 72);
    let frames = rendered_frames("fast_run.toml", width, height);
    let source = &frames[1];
    let [started, without] = [[false, true], [false; 2]]
        .map(|with_shadows| run_validated(frames.each_ref(), with_shadows, None, false, None));

    assert_eq!(started.stats.shadow_history, PATCHEX_SHADOW_HISTORY_STARTED);
    let traffic = &started.stats.extrapolation_traffic[0];
    let stage = PATCHEX_STAGE_SHADOW_WARP as usize;
    assert_eq!(
        traffic.dispatches[stage], 0,
        "the shadow warp stage dispatched"
    );
    assert_eq!(traffic.bytes_read[stage], 0, "the shadow warp stage read");
    // The shadows' share, RGBA16F, cleared, after the extrapolation's counters, whose write
    // counts with the first stage recorded.
    assert_eq!(
        traffic.bytes_written[stage],
        8 * width as u64 * height as u64 + REGION_BYTES
    );
    let changed = started.diagnostics.data.chunks(4).filter(|d| d[3] != 0.0);
    assert_eq!(changed.count(), 0, "pixels with a shadow share");
    let output_worst = worst_output_error(&started.output, &without.output);
    eprintln!("worst / tolerance against the output without a shadow input: {output_worst:.3}");
    assert!(output_worst <= 1.0, "the shadows moved");
    // The case is real: the camera moves the ground by pixels, and it is in shadow.
    let reach = started.stats.extrapolations[0].largest_motion;
    assert!(reach > 2.0, "the fastest motion is {reach} px");
    let shadowed = source.shadow_mask.data.iter().filter(|&&v| v < 0.5).count();
    assert!(shadowed > 50, "only {shadowed} pixels in shadow");
}

/// The analytic scene with the sun behind the sphere, so its shadow falls towards the camera.
fn shadow_scene() -> Scene {
    Scene {
        casts_shadow: true,
        sun: Vec3::new(0.3, 0.8, -0.55).normalize(),
        sphere_speed: 4.0,
        camera_speed: 0.5,
        ..Scene::new(160, 96)
    }
}

const FRAME_TIME: f32 = 1.0 / 15.0;

#[test]
fn shadow_flow_follows_the_true_motion_of_the_shadow() {
    let scene = shadow_scene();
    let previous = scene.render(-FRAME_TIME, Vec2::ZERO, -2.0 * FRAME_TIME);
    let source = scene.render(0.0, Vec2::ZERO, -FRAME_TIME);
    let target = scene.render(0.5 * FRAME_TIME, Vec2::ZERO, 0.0);
    let rig = shadows_rig(160, 96);
    let outcome = run_with_shadows(&rig, &previous, &source, &target, 0.5, true);
    let truth = source
        .shadow_motion
        .as_ref()
        .expect("the analytic scene knows it");

    // Over the ground in the shadow's penumbra and umbra of frame t.
    let (mut error, mut length, mut count) = (0.0f32, 0.0f32, 0);
    for y in 0..96 {
        for x in 0..160 {
            let true_motion = Vec2::from_slice(truth.at(x, y));
            if !true_motion.is_finite() || source.shadow_mask.at(x, y)[0] > 0.95 {
                continue;
            }
            let got = Vec2::from_slice(&outcome.diagnostics.at(x, y)[..2]);
            error += (got - true_motion).length();
            length += true_motion.length();
            count += 1;
        }
    }
    assert!(count > 100, "only {count} shadowed ground pixels");
    let (mean_error, mean_length) = (error / count as f32, length / count as f32);
    eprintln!(
        "shadow flow over {count} pixels: mean endpoint error {mean_error:.2} px for a mean \
         true motion of {mean_length:.2} px"
    );
    assert!(
        mean_length > 3.0,
        "the shadow barely moves ({mean_length} px)"
    );
    assert!(
        mean_error < 0.15 * mean_length,
        "mean endpoint error {mean_error} px against {mean_length} px of motion"
    );
}

/// Mask-weighted centre of the shadow on static pixels: (1 - mask) where the stencil is 0.
fn shadow_centre(frame: &Frame) -> Vec2 {
    let (mut sum, mut weight) = (Vec2::ZERO, 0.0);
    for y in 0..frame.shadow_mask.height {
        for x in 0..frame.shadow_mask.width {
            if frame.stencil.at(x, y)[0] == 0.0 {
                let w = 1.0 - frame.shadow_mask.at(x, y)[0];
                sum += w * Vec2::new(x as f32, y as f32);
                weight += w;
            }
        }
    }
    sum / weight
}

/// On the scene renderer's terrain, a character walks in a straight line at constant speed under
/// a static camera, so its shadow translates: the shift of the shadow's centre between the
/// renderer's masks is the true displacement, which the mean flow over the shadow must match
/// within 30%. The centre also follows the legs' swing and the terrain's bumps (measured: 4.3 px
/// of flow against a 5.6 px shift).
#[test]
fn shadow_flow_matches_the_displacement_of_a_rendered_shadow() {
    const W: u32 = 320;
    const H: u32 = 180;
    // Frames 0 and 8 of the doubled stream, submitted as consecutive frames: a larger step.
    let sequence = support::rendered::render("shadow_terrain.toml", 9, W, H);
    let (previous, source) = (&sequence.frames[0], &sequence.frames[8]);
    let rig = shadows_rig(W, H);
    let outcome = run_with_shadows(&rig, previous, source, source, 0.5, true);
    let truth = shadow_centre(previous) - shadow_centre(source);
    let (mut flow, mut count) = (Vec2::ZERO, 0);
    for y in 0..H as usize {
        for x in 0..W as usize {
            if source.stencil.at(x, y)[0] == 0.0 && source.shadow_mask.at(x, y)[0] < 0.5 {
                flow += Vec2::from_slice(&outcome.diagnostics.at(x, y)[..2]);
                count += 1;
            }
        }
    }
    let mean = flow / count as f32;
    eprintln!(
        "rendered shadow: true shift {truth:?} px, mean flow {mean:?} px over {count} pixels"
    );
    assert!(truth.length() > 2.0, "the shadow moves ({truth:?} px)");
    assert!(
        (mean - truth).length() < 0.3 * truth.length(),
        "mean flow {mean:?} against the shadow's shift {truth:?}"
    );
}

#[test]
fn moving_the_shadow_brings_the_extrapolation_closer_to_the_rendered_target() {
    let scene = shadow_scene();
    let previous = scene.render(-FRAME_TIME, Vec2::ZERO, -2.0 * FRAME_TIME);
    let source = scene.render(0.0, Vec2::ZERO, -FRAME_TIME);
    let target = scene.render(0.5 * FRAME_TIME, Vec2::ZERO, 0.0);
    let rig = shadows_rig(160, 96);
    let without = run_with_shadows(&rig, &previous, &source, &target, 0.5, false);
    let rig = shadows_rig(160, 96);
    let with = run_with_shadows(&rig, &previous, &source, &target, 0.5, true);

    // Scored where frame t or the target has shadow: where the shadow was and where it went.
    let shadowed: Vec<usize> = (0..source.shadow_mask.data.len())
        .filter(|&i| source.shadow_mask.data[i] < 0.95 || target.shadow_mask.data[i] < 0.95)
        .collect();
    let region = |image: &Image| pixels_of(image, &shadowed);
    let truth = region(&target.color);
    let (psnr_without, psnr_with) = (
        psnr(&region(&without.output), &truth),
        psnr(&region(&with.output), &truth),
    );
    eprintln!("shadow region: {psnr_without:.1} dB without the shadow sub-task, {psnr_with:.1} dB with it");
    assert!(
        psnr_with > psnr_without + 2.0,
        "{psnr_with} dB with shadows against {psnr_without} dB without"
    );
    let messages = rig.engine.take_validation_messages();
    assert!(messages.is_empty(), "validation: {messages:?}");
}

#[test]
fn without_a_shadow_input_no_shadow_pass_runs() {
    let scene = shadow_scene();
    let previous = scene.render(-FRAME_TIME, Vec2::ZERO, -2.0 * FRAME_TIME);
    let source = scene.render(0.0, Vec2::ZERO, -FRAME_TIME);
    let target = scene.render(0.5 * FRAME_TIME, Vec2::ZERO, 0.0);
    let rig = shadows_rig(160, 96);
    let without = run_with_shadows(&rig, &previous, &source, &target, 0.5, false);
    let memory_without = without.stats.device_memory_bytes;
    let shadow_stages = |stats: &PatchexFrameStats| {
        (
            stats.submit_gpu_ms[PATCHEX_STAGE_SHADOW_FLOW as usize],
            stats.extrapolations[0].gpu_ms[PATCHEX_STAGE_SHADOW_WARP as usize],
        )
    };
    assert_eq!(shadow_stages(&without.stats), (0.0, 0.0));
    // Nothing of the shadow layer reached the diagnostics image, which stays as uploaded.
    assert!(without.diagnostics.data.iter().all(|v| *v == 0.0));

    let rig = shadows_rig(160, 96);
    let with = run_with_shadows(&rig, &previous, &source, &target, 0.5, true);
    assert_eq!(with.stats.timings_valid, 1);
    let (flow_ms, warp_ms) = shadow_stages(&with.stats);
    assert!(flow_ms > 0.0 && warp_ms > 0.0, "{flow_ms} ms, {warp_ms} ms");
    assert!(
        with.stats.device_memory_bytes > memory_without,
        "the shadow images are made only when a shadow input arrives"
    );
}

#[test]
fn bad_shadow_inputs_and_flow_settings_are_refused() {
    let scene = shadow_scene();
    let source = scene.render(0.0, Vec2::ZERO, -FRAME_TIME);
    let rig = shadows_rig(160, 96);
    let family = rig.engine.queue_family_index;
    let gpu = GpuFrame::upload(&rig.engine, &source);

    let settings = FlowSettings::default().to_abi();
    // Submits frame 1 with `shadow` and, when given, `settings` chained after it.
    let submit = |shadow: PatchexShadowInput, settings: Option<PatchexShadowFlowSettings>| {
        let mut shadow = shadow;
        if let Some(settings) = &settings {
            shadow.header.next = settings as *const _ as *const c_void;
        }
        let mut desc = gpu.frame_desc(1, family);
        desc.header.next = &shadow as *const _ as *const c_void;
        let mut result = PatchexResult::Success;
        rig.engine.run(|cmd| result = rig.submit(cmd, &desc));
        result
    };
    let bad_settings = [
        (
            PatchexShadowFlowSettings {
                levels: 7,
                ..settings
            },
            "levels 7",
        ),
        (
            PatchexShadowFlowSettings {
                window_radius: MAX_WINDOW_RADIUS + 1,
                ..settings
            },
            "window_radius",
        ),
        (
            PatchexShadowFlowSettings {
                poly_sigma: f32::NAN,
                ..settings
            },
            "poly_sigma",
        ),
    ];
    for (bad, named) in bad_settings {
        let result = submit(gpu.shadow_input(), Some(bad));
        assert_eq!(result, PatchexResult::ErrorInvalidArgument, "{named}");
        assert!(rig.last_error().contains(named), "{}", rig.last_error());
    }

    let mut no_mask = gpu.shadow_input();
    no_mask.mask.image = Default::default();
    assert_eq!(submit(no_mask, None), PatchexResult::ErrorNullPointer);
    assert!(
        rig.last_error().contains("PatchexShadowInput.mask"),
        "{}",
        rig.last_error()
    );
    // The context is unharmed: a valid frame with valid settings goes through.
    assert_eq!(
        submit(gpu.shadow_input(), Some(settings)),
        PatchexResult::Success
    );
    let messages = rig.engine.take_validation_messages();
    assert!(messages.is_empty(), "validation: {messages:?}");

    // A preset without the shadow sub-task refuses the input instead of ignoring it.
    let warp_only = Rig::new(160, 96);
    let gpu = GpuFrame::upload(&warp_only.engine, &source);
    let shadow = gpu.shadow_input();
    let mut desc = gpu.frame_desc(1, warp_only.engine.queue_family_index);
    desc.header.next = &shadow as *const _ as *const c_void;
    let mut result = PatchexResult::Success;
    warp_only
        .engine
        .run(|cmd| result = warp_only.submit(cmd, &desc));
    assert_eq!(result, PatchexResult::ErrorInvalidArgument);
    assert!(
        warp_only
            .last_error()
            .contains("PATCHEX_PRESET_WARP_AND_SHADOWS"),
        "{}",
        warp_only.last_error()
    );
}

/// A target shadow input needs frame t's shadow input, and its mask is checked as frame t's is;
/// a refused call leaves the context able to take the next one.
#[test]
fn bad_target_shadow_inputs_are_refused() {
    let scene = shadow_scene();
    let source = scene.render(0.0, Vec2::ZERO, -FRAME_TIME);
    let target = scene.render(0.5 * FRAME_TIME, Vec2::ZERO, 0.0);
    let rig = shadows_rig(160, 96);
    let family = rig.engine.queue_family_index;
    let gpu = GpuFrame::upload(&rig.engine, &source);
    let gpu_target = GpuFrame::upload(&rig.engine, &target);
    let output = output_image(&rig.engine, 160, 96);
    let submit = |index, with_shadows: bool| {
        let shadow = gpu.shadow_input();
        let mut desc = gpu.frame_desc(index, family);
        if with_shadows {
            desc.header.next = &shadow as *const _ as *const c_void;
        }
        let mut result = PatchexResult::Success;
        rig.engine.run(|cmd| result = rig.submit(cmd, &desc));
        assert_eq!(result, PatchexResult::Success, "{}", rig.last_error());
    };
    let extrapolate = |mask: PatchexImage| {
        let input = PatchexTargetShadowInput {
            header: PatchexStructHeader::of::<PatchexTargetShadowInput>(
                PATCHEX_STRUCT_TYPE_TARGET_SHADOW_INPUT,
            ),
            mask,
        };
        let mut desc = gpu_target.extrapolate_desc(&output, 0.5, family);
        desc.header.next = &input as *const _ as *const c_void;
        let mut result = PatchexResult::Success;
        rig.engine.run(|cmd| result = rig.extrapolate(cmd, &desc));
        result
    };
    let mask = gpu_target.shadow_input().mask;

    submit(1, false);
    assert_eq!(extrapolate(mask), PatchexResult::ErrorInvalidArgument);
    assert!(
        rig.last_error()
            .contains("PatchexTargetShadowInput needs frame t"),
        "{}",
        rig.last_error()
    );
    submit(2, true);
    let stencil_as_mask = gpu_target.stencil.describe(GBUFFER_LAYOUT);
    assert_eq!(
        extrapolate(stencil_as_mask),
        PatchexResult::ErrorUnsupportedFormat
    );
    assert!(
        rig.last_error().contains("PatchexTargetShadowInput.mask"),
        "{}",
        rig.last_error()
    );
    let no_image = PatchexImage {
        image: Default::default(),
        ..mask
    };
    assert_eq!(extrapolate(no_image), PatchexResult::ErrorNullPointer);
    assert_eq!(extrapolate(mask), PatchexResult::Success);
    let messages = rig.engine.take_validation_messages();
    assert!(messages.is_empty(), "validation: {messages:?}");
}

/// NaN and infinity in the shadow inputs (frame t-1's mask and the target's included): the
/// output stays finite, the flow stays finite, and the sanitised pixels are counted as the
/// reference counts them.
#[test]
fn non_finite_shadow_inputs_are_sanitised_and_counted() {
    let scene = shadow_scene();
    let mut previous = scene.render(-FRAME_TIME, Vec2::ZERO, -2.0 * FRAME_TIME);
    let mut source = scene.render(0.0, Vec2::ZERO, -FRAME_TIME);
    let mut target = scene.render(0.5 * FRAME_TIME, Vec2::ZERO, 0.0);
    for (i, x) in (0..160).step_by(5).enumerate() {
        let bad = [f32::NAN, 2.0, -1.0, f32::INFINITY][i % 4];
        target.shadow_mask.set(x, 10 + (i * 7) % 80, &[bad]);
    }
    for (i, x) in (0..160).step_by(7).enumerate() {
        let y = 20 + (i * 3) % 70;
        previous.shadow_mask.set(x, y, &[f32::NAN]);
        source
            .shadow_mask
            .set(x, y, &[[f32::NAN, 2.0, -1.0][i % 3]]);
        let bad = [f32::INFINITY, f32::NAN, -f32::INFINITY][i % 3];
        source
            .color_without_dynamic_shadows
            .set(x, y + 1, &[bad, 0.5, bad, 1.0]);
    }
    let expected = |target_shadows| {
        reference_run(
            &previous,
            &source,
            &target,
            0.5,
            &WarpSettings::default(),
            target_shadows,
            FlowSettings::default(),
        )
    };
    let rig = shadows_rig(160, 96);
    let outcome = run_with_shadows(&rig, &previous, &source, &target, 0.5, true);
    let reference = expected(false);
    let shadows = reference
        .shadows
        .as_ref()
        .expect("a shadow input was given");
    assert!(outcome.output.data.iter().all(|v| v.is_finite()));
    assert!(outcome.diagnostics.data.iter().all(|v| v.is_finite()));
    assert!(
        shadows.separated.sanitized >= 2 * 23,
        "every bad pixel counts"
    );
    assert_eq!(
        outcome.stats.source_sanitized_pixels,
        shadows.separated.sanitized
    );
    let messages = rig.engine.take_validation_messages();
    assert!(messages.is_empty(), "validation: {messages:?}");

    // The target's mask, as a target shadow input, holds bad values too.
    let outcome = run_validated([&previous, &source, &target], [true; 2], None, true, None);
    assert!(outcome.output.data.iter().all(|v| v.is_finite()));
    let target_sanitized = outcome.stats.extrapolations[0].sanitized_pixels;
    assert!(
        target_sanitized >= 32,
        "every bad pixel of the target's mask counts"
    );
    assert_eq!(target_sanitized, expected(true).target_sanitized);
}

/// Shadow frames through a resize (the shadow images are made again), a reset and a frame
/// without shadow input (the history breaks): every extrapolation stays finite and
/// validation-clean, the shadow stages run exactly on the frames with a shadow input, and the
/// statistics say when the shadows' motion was tracked.
#[test]
fn shadow_history_survives_resizes_resets_and_gaps() {
    let rig = shadows_rig(160, 96);
    let engine = &rig.engine;
    let family = engine.queue_family_index;
    // (size, reset, with shadow input, with the flow off, what the shadow sub-task had to work
    // with)
    const NONE: u32 = PATCHEX_SHADOW_HISTORY_NONE;
    const STARTED: u32 = PATCHEX_SHADOW_HISTORY_STARTED;
    const TRACKED: u32 = PATCHEX_SHADOW_HISTORY_TRACKED;
    const SEPARATED: u32 = PATCHEX_SHADOW_HISTORY_SEPARATED;
    let plan = [
        ((96, 64), false, true, false, STARTED),
        ((96, 64), false, true, false, TRACKED),
        ((160, 96), false, true, false, STARTED),
        ((160, 96), false, true, false, TRACKED),
        ((160, 96), true, true, false, STARTED),
        ((160, 96), false, false, false, NONE),
        ((160, 96), false, true, false, STARTED),
        ((160, 96), false, true, false, TRACKED),
        // A frame without flow leaves no expansion for the next frame's to track from.
        ((160, 96), false, true, true, SEPARATED),
        ((160, 96), false, true, false, STARTED),
        ((160, 96), false, true, false, TRACKED),
    ];
    let flow_off = FlowSettings::off().to_abi();
    for (index, &((width, height), reset, with_shadows, off, history)) in plan.iter().enumerate() {
        let scene = Scene {
            width,
            height,
            ..shadow_scene()
        };
        let time = index as f32 * FRAME_TIME;
        let source = GpuFrame::upload(engine, &scene.render(time, Vec2::ZERO, time - FRAME_TIME));
        let target = scene.render(time + 0.5 * FRAME_TIME, Vec2::ZERO, time);
        let target = GpuFrame::upload(engine, &target);
        let output = output_image(engine, width as u32, height as u32);
        let mut shadow = source.shadow_input();
        if off {
            shadow.header.next = &flow_off as *const _ as *const c_void;
        }
        let mut desc = source.frame_desc(1 + index as u64, family);
        desc.reset = reset as u32;
        if with_shadows {
            desc.header.next = &shadow as *const _ as *const c_void;
        }
        engine.run(|cmd| {
            rig.submit_ok(cmd, &desc);
            let extrapolate = target.extrapolate_desc(&output, 0.5, family);
            rig.extrapolate_ok(cmd, &extrapolate);
        });
        let (_, stats) = rig.stats(1 + index as u64);
        assert_eq!(stats.shadow_history, history, "frame {index}");
        let ran = |bits: u32, stage: PatchexStage| bits & (1 << stage) != 0;
        assert_eq!(
            ran(stats.submit_stages_run, PATCHEX_STAGE_SHADOW_FLOW),
            with_shadows && !off,
            "frame {index}"
        );
        let stages = stats.extrapolations[0].stages_run;
        // Without the flow the frame's warp carries the layer, and there is nothing to move.
        assert_eq!(
            ran(stages, PATCHEX_STAGE_SHADOW_WARP),
            with_shadows && !off,
            "frame {index}"
        );
        // Without shadow layers to move, the warp remodulates as it writes.
        assert!(ran(stages, PATCHEX_STAGE_WARP));
        assert_eq!(
            ran(stages, PATCHEX_STAGE_REMODULATE),
            with_shadows,
            "frame {index}"
        );
        // The scene's fastest motion: the sphere's, a few pixels a frame at these sizes.
        let reach = stats.extrapolations[0].largest_motion;
        assert!((1.0..40.0).contains(&reach), "frame {index}: {reach} px");
        let pixels = output.read(engine, OUTPUT_LAYOUT);
        assert!(pixels.iter().all(|v| v.is_finite()), "frame {index}");
    }
    let messages = engine.take_validation_messages();
    assert!(messages.is_empty(), "validation: {messages:?}");
}
