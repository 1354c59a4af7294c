//! End-to-end extrapolation on lavapipe through the C ABI on the analytic scene, compared with
//! the plain-Rust reference of the same passes (tolerances in `support/pipeline.rs`).

mod support;

use glam::Vec2;
use patchex::abi::*;
use patchex::error::PatchexResult;
use patchex::passes::warp::WarpSettings;
use patchex::reference::Image;
use support::pipeline::{assert_matches_reference, psnr, run_plugin, Chained};
use support::scene::{Frame, Scene};
use support::*;

const WIDTH: usize = 96;
const HEIGHT: usize = 64;
/// Rendered frames are 1/30 s apart; the target sits halfway (alpha 0.5).
const FRAME_TIME: f32 = 1.0 / 30.0;

fn two_frame_case(scene: &Scene) -> (Frame, Frame) {
    let source = scene.render(0.0, Vec2::new(0.25, -0.25), -FRAME_TIME);
    let target = scene.render(0.5 * FRAME_TIME, Vec2::new(-0.125, 0.375), 0.0);
    (source, target)
}

#[test]
fn extrapolation_matches_reference_on_a_moving_textured_sphere() {
    let scene = Scene::new(WIDTH, HEIGHT);
    let (source, target) = two_frame_case(&scene);
    let rig = Rig::new(WIDTH as u32, HEIGHT as u32);
    let outcome = run_plugin(&rig, &source, &target, 0.5, &Chained::default());
    assert_matches_reference(&source, &target, &outcome, &Chained::default());

    // The case is real: the sphere moves and uncovers ground, and warping beats showing frame t.
    let stats = &outcome.stats.extrapolations[0];
    assert!(
        stats.hole_fraction > 0.002,
        "the sphere disoccludes ground ({})",
        stats.hole_fraction
    );
    let warped_psnr = psnr(&outcome.output, &target.color);
    let stale_psnr = psnr(&source.color, &target.color);
    println!("PSNR against the rendered target: extrapolated {warped_psnr:.2} dB, frame t {stale_psnr:.2} dB");
    assert!(
        warped_psnr > stale_psnr + 3.0,
        "extrapolated {warped_psnr:.2} dB vs frame t {stale_psnr:.2} dB"
    );
}

#[test]
fn extrapolation_matches_reference_with_reversed_infinite_depth() {
    let mut scene = Scene::new(WIDTH, HEIGHT);
    scene.depth_convention = PATCHEX_DEPTH_HARDWARE_REVERSED;
    let (source, target) = two_frame_case(&scene);
    let rig = Rig::new(WIDTH as u32, HEIGHT as u32);
    let outcome = run_plugin(&rig, &source, &target, 0.5, &Chained::default());
    assert_matches_reference(&source, &target, &outcome, &Chained::default());
}

#[test]
fn extrapolation_matches_reference_with_linear_view_depth() {
    let mut scene = Scene::new(WIDTH, HEIGHT);
    scene.depth_convention = PATCHEX_DEPTH_LINEAR_VIEW_Z;
    let (source, target) = two_frame_case(&scene);
    let rig = Rig::new(WIDTH as u32, HEIGHT as u32);
    let outcome = run_plugin(&rig, &source, &target, 0.5, &Chained::default());
    assert_matches_reference(&source, &target, &outcome, &Chained::default());
}

/// Each warp kind on the same moving case: the plugin matches the reference, and their quality
/// against the rendered target comes in the order the method expects: plain reprojection ghosts
/// the sphere over the ground it uncovers, occlusion motion vectors repair part of that, and the
/// G-buffer-guided warp also fixes silhouettes.
#[test]
fn every_warp_kind_matches_its_reference() {
    let scene = Scene::new(WIDTH, HEIGHT);
    let (source, target) = two_frame_case(&scene);
    let mut psnrs = Vec::new();
    for kind in [
        PATCHEX_WARP_MOTION_VECTOR,
        PATCHEX_WARP_OCCLUSION_MOTION_VECTOR,
        PATCHEX_WARP_GBUFFER_GUIDED,
    ] {
        let chained = Chained {
            warp: Some(WarpSettings {
                kind,
                ..WarpSettings::default()
            }),
            ..Chained::default()
        };
        let rig = Rig::new(WIDTH as u32, HEIGHT as u32);
        let outcome = run_plugin(&rig, &source, &target, 0.5, &chained);
        assert_matches_reference(&source, &target, &outcome, &chained);
        let quality = psnr(&outcome.output, &target.color);
        println!(
            "warp kind {kind}: PSNR {quality:.2} dB, holes {:.4}",
            outcome.stats.extrapolations[0].hole_fraction
        );
        psnrs.push(quality);
    }
    assert!(
        psnrs[0] + 1.0 < psnrs[1] && psnrs[1] + 1.0 < psnrs[2],
        "each warp beats the previous by over 1 dB (reprojection, occlusion motion vectors, \
         G-buffer-guided): {psnrs:?}"
    );
}

/// PSNR of the RGB channels over the pixels the diagnostics mark as holes.
fn hole_psnr(outcome: &support::pipeline::Outcome, truth: &Image) -> f64 {
    let mut squared = 0.0;
    let mut count = 0;
    for ((out, want), diag) in outcome
        .output
        .data
        .chunks(4)
        .zip(truth.data.chunks(4))
        .zip(outcome.diagnostics.data.chunks(4))
    {
        if diag[0] == 1.0 {
            for c in 0..3 {
                squared += ((out[c] - want[c]) as f64).powi(2);
                count += 1;
            }
        }
    }
    assert!(count > 0, "the case has holes");
    10.0 * (count as f64 / squared).log10()
}

/// Both hole fills match the reference on rendered frames (crossing_street, characters
/// crossing a textured street); over the holes the characters and the camera uncover, filling
/// from the uncovered side beats the nearest texel, which is mostly the character that hid them.
/// At 320x180, so that the holes are a sample (about 80 pixels) rather than a handful that one
/// specular texel decides: at 128x72 (29 holes) either fill can win by one pixel.
#[test]
fn uncovered_side_fill_beats_the_nearest_texel_over_holes() {
    let sequence = support::rendered::render("crossing_street.toml", 2, 320, 180);
    let (source, target) = (&sequence.frames[0], &sequence.frames[1]);
    let mut hole_psnrs = Vec::new();
    for hole_fill in [PATCHEX_HOLE_FILL_NEAREST, PATCHEX_HOLE_FILL_BACKGROUND] {
        let chained = Chained {
            warp: Some(WarpSettings {
                hole_fill,
                ..WarpSettings::default()
            }),
            ..Chained::default()
        };
        let rig = Rig::new(320, 180);
        let outcome = run_plugin(&rig, source, target, 0.5, &chained);
        assert_matches_reference(source, target, &outcome, &chained);
        hole_psnrs.push(hole_psnr(&outcome, &target.color));
        // Only the uncovered side's fill is a pass of its own; the nearest texel is the warp's.
        let stats = &outcome.stats.extrapolations[0];
        assert_eq!(
            stats.stages_run & 1 << PATCHEX_STAGE_FILL_HOLES != 0,
            hole_fill == PATCHEX_HOLE_FILL_BACKGROUND,
            "fill {hole_fill}: stages {:#b}",
            stats.stages_run
        );
    }
    println!(
        "PSNR over holes: nearest texel {:.2} dB, uncovered side {:.2} dB",
        hole_psnrs[0], hole_psnrs[1]
    );
    assert!(
        hole_psnrs[1] > hole_psnrs[0],
        "the uncovered side's fill beats the nearest texel over holes: {hole_psnrs:?}"
    );
}

/// A camera panning past a tree brings sky in at the frame's left edge, where frame t showed the
/// tree across the whole of the fill's window (the validation scene autumn_06): the fill looks
/// further in and finds the sky, instead of spreading the tree's shading over it, which the
/// sky's modulation turned nearly black.
#[test]
fn sky_entering_beside_an_occluder_at_the_edge_is_filled_with_sky() {
    let (width, height) = (640, 360);
    let sequence = support::rendered::render("generated/autumn_06.toml", 2, width, height);
    let (source, target) = (&sequence.frames[0], &sequence.frames[1]);
    let chained = Chained::default();
    let rig = Rig::new(width, height);
    let outcome = run_plugin(&rig, source, target, 0.5, &chained);
    assert_matches_reference(source, target, &outcome, &chained);
    // The target's sky whose motion leads off frame t's left edge.
    let (mut error, mut truth, mut pixels) = (0.0f64, 0.0f64, 0);
    for y in 0..height as usize {
        for x in 0..width as usize {
            let entering = x as f32 + 0.5 + target.motion.at(x, y)[0] < 0.0;
            if entering && target.depth.at(x, y)[0] >= sequence.manifest.far {
                for c in 0..3 {
                    let want = target.color.at(x, y)[c] as f64;
                    error += (outcome.output.at(x, y)[c] as f64 - want).abs();
                    truth += want;
                }
                pixels += 1;
            }
        }
    }
    assert!(
        pixels > 100,
        "the case brings sky in at the edge: {pixels} pixels"
    );
    let relative = error / truth;
    println!("entering sky: {pixels} pixels, mean error {relative:.3} of the sky's colour");
    assert!(
        relative < 0.1,
        "the entering sky is filled with sky: relative error {relative:.3}"
    );
}

#[test]
fn zero_motion_gives_back_the_submitted_frame() {
    let mut scene = Scene::new(WIDTH, HEIGHT);
    scene.sphere_speed = 0.0;
    scene.camera_speed = 0.0;
    let frame = scene.render(0.0, Vec2::ZERO, -FRAME_TIME);
    assert!(frame.motion.data.iter().all(|m| *m == 0.0));
    let rig = Rig::new(WIDTH as u32, HEIGHT as u32);
    let outcome = run_plugin(&rig, &frame, &frame, 0.5, &Chained::default());
    for (got, want) in outcome
        .output
        .data
        .chunks(4)
        .zip(frame.color.data.chunks(4))
    {
        for c in 0..3 {
            // Only the RGBA16F output's rounding separates them: under one f16 step (2^-10
            // relative), as Vulkan lets a driver round or truncate when it stores to f16.
            assert!(
                (got[c] - want[c]).abs() <= want[c].abs() * 9.77e-4 + 1e-6,
                "{got:?} vs {want:?}"
            );
        }
    }
    assert_eq!(outcome.stats.extrapolations[0].hole_fraction, 0.0);
}

#[test]
fn several_extrapolations_from_one_frame_report_their_own_stats() {
    let scene = Scene::new(WIDTH, HEIGHT);
    let source = scene.render(0.0, Vec2::ZERO, -FRAME_TIME);
    let alphas = [1.0 / 3.0, 2.0 / 3.0];
    let targets: Vec<Frame> = alphas
        .iter()
        .map(|a| scene.render(a * FRAME_TIME, Vec2::ZERO, 0.0))
        .collect();
    let rig = Rig::new(WIDTH as u32, HEIGHT as u32);
    let engine = &rig.engine;
    let family = engine.queue_family_index;
    let gpu_source = GpuFrame::upload(engine, &source);
    let gpu_targets: Vec<GpuFrame> = targets
        .iter()
        .map(|t| GpuFrame::upload(engine, t))
        .collect();
    let outputs: Vec<_> = alphas
        .iter()
        .map(|_| output_image(engine, WIDTH as u32, HEIGHT as u32))
        .collect();
    engine.run(|cmd| {
        assert_eq!(
            rig.submit(cmd, &gpu_source.frame_desc(7, family)),
            PatchexResult::Success
        );
        for ((target, output), alpha) in gpu_targets.iter().zip(&outputs).zip(alphas) {
            let result = rig.extrapolate(cmd, &target.extrapolate_desc(output, alpha, family));
            assert_eq!(result, PatchexResult::Success, "{}", rig.last_error());
        }
    });
    let (result, stats) = rig.stats(7);
    assert_eq!(result, PatchexResult::Success);
    assert_eq!(stats.extrapolation_count, 2);
    assert_eq!(stats.reset_reason, PATCHEX_RESET_FIRST_FRAME);
    assert_eq!((stats.width, stats.height), (WIDTH as u32, HEIGHT as u32));
    assert!(stats.device_memory_bytes > 0);
    let (first, second) = (&stats.extrapolations[0], &stats.extrapolations[1]);
    assert_eq!((first.alpha, second.alpha), (alphas[0], alphas[1]));
    // Farther from frame t, the sphere has uncovered more ground.
    assert!(
        second.hole_fraction > first.hole_fraction,
        "{} vs {}",
        second.hole_fraction,
        first.hole_fraction
    );
    assert_eq!(stats.timings_valid, 1);
    for stage in [PATCHEX_STAGE_DEMODULATE, PATCHEX_STAGE_PACK_SOURCE_GBUFFER] {
        assert!(
            stats.submit_gpu_ms[stage as usize] > 0.0,
            "submit stage {stage} has a GPU time"
        );
    }
    // The warp reads the target's G-buffer itself, and with nothing between it and the output
    // it remodulates too: a warp-only extrapolation is the warp, its hole fill and the
    // segmentation.
    let warp_only = [
        PATCHEX_STAGE_WARP,
        PATCHEX_STAGE_FILL_HOLES,
        PATCHEX_STAGE_SEGMENT,
    ];
    assert_eq!(
        first.stages_run,
        warp_only.iter().fold(0, |bits, stage| bits | 1 << stage)
    );
    for stage in warp_only {
        assert!(
            first.gpu_ms[stage as usize] > 0.0,
            "extrapolation stage {stage} has a GPU time"
        );
    }
    for (output, target) in outputs.iter().zip(&targets) {
        let values = Image {
            width: WIDTH,
            height: HEIGHT,
            channels: 4,
            data: output.read(engine, OUTPUT_LAYOUT),
        };
        assert!(psnr(&values, &target.color) > psnr(&source.color, &target.color));
    }
}

/// Frames that grow replace the plugin's working images; the old ones are destroyed only once
/// every frame in flight that may use them has completed, as the reported device memory shows.
#[test]
fn growing_frames_retire_working_images_after_the_frames_in_flight() {
    let (small, large) = ((48, 32), (WIDTH, HEIGHT));
    let rig = Rig::new(WIDTH as u32, HEIGHT as u32);
    let engine = &rig.engine;
    let family = engine.queue_family_index;
    let frames: Vec<_> = [small, large]
        .iter()
        .map(|&(w, h)| {
            let scene = Scene::new(w, h);
            let source = GpuFrame::upload(engine, &scene.render(0.0, Vec2::ZERO, -FRAME_TIME));
            let target = GpuFrame::upload(engine, &scene.render(0.5 * FRAME_TIME, Vec2::ZERO, 0.0));
            (source, target, output_image(engine, w as u32, h as u32))
        })
        .collect();
    let mut memory = Vec::new();
    // frames_in_flight is 2. Frame 1 is small, frames 2 to 5 large.
    for frame_index in 1..=5u64 {
        let (source, target, output) = &frames[(frame_index > 1) as usize];
        engine.run(|cmd| {
            assert_eq!(
                rig.submit(cmd, &source.frame_desc(frame_index, family)),
                PatchexResult::Success
            );
            let desc = target.extrapolate_desc(output, 0.5, family);
            rig.extrapolate_ok(cmd, &desc);
        });
        memory.push(rig.stats(frame_index).1.device_memory_bytes);
    }
    // Frame 2 allocates the large images and holds the small ones, which frame 1 may still be
    // using; at frame 3 (frame 1 + 2 frames in flight) frame 1 has completed and they go.
    let small_images = memory[1] - memory[2];
    assert!(memory[1] > memory[0], "growth allocates: {memory:?}");
    assert!(
        small_images > 0,
        "retired images are freed after the frames in flight: {memory:?}"
    );
    assert!(
        memory[2] > memory[0],
        "the large images outweigh the small ones: {memory:?}"
    );
    assert_eq!(
        &memory[3..],
        &[memory[2], memory[2]],
        "steady state: {memory:?}"
    );
}

/// The demodulation rule where its denominator vanishes: black albedo, near-black albedo and
/// black metal (whose specular term is 0 too) meet the floor of the modulation factor, and
/// remodulating with the same G-buffer gives their colour back.
#[test]
fn black_and_metallic_surfaces_demodulate_and_remodulate_safely() {
    let mut scene = Scene::new(WIDTH, HEIGHT);
    scene.sphere_speed = 0.0;
    scene.camera_speed = 0.0;
    let mut frame = scene.render(0.0, Vec2::ZERO, -FRAME_TIME);
    for y in 0..HEIGHT {
        for x in 0..WIDTH {
            // Three bands: black dielectric, near-black (1e-6) dielectric, black metal.
            let band = x * 3 / WIDTH;
            let albedo = if band == 1 { 1e-6 } else { 0.0 };
            frame.base_color.set(x, y, &[albedo, albedo, albedo, 1.0]);
            let mut material = frame.material.at(x, y).to_vec();
            material[0] = if band == 2 { 1.0 } else { 0.0 };
            frame.material.set(x, y, &material);
            // What a renderer may still show there: a specular highlight or emission.
            let glow = 0.05 + 0.5 * ((x + y) % 7) as f32 / 7.0;
            frame.color.set(x, y, &[glow, 0.5 * glow, 0.25 * glow, 1.0]);
        }
    }
    let rig = Rig::new(WIDTH as u32, HEIGHT as u32);
    let outcome = run_plugin(&rig, &frame, &frame, 0.5, &Chained::default());
    assert_matches_reference(&frame, &frame, &outcome, &Chained::default());
    for (got, want) in outcome
        .output
        .data
        .chunks(4)
        .zip(frame.color.data.chunks(4))
    {
        for c in 0..3 {
            assert!(got[c].is_finite());
            assert!(
                (got[c] - want[c]).abs() <= want[c].abs() * 9.77e-4 + 1e-6,
                "{got:?} vs {want:?}"
            );
        }
    }
}

/// What an engine may get wrong, in every channel the demodulation and remodulation read: NaN,
/// infinities, negative colours, colours beyond the largest half float, base colour and material outside [0, 1].
/// The output stays finite, matches the reference, and the statistics count every pixel that
/// was sanitised.
#[test]
fn unusable_inputs_are_sanitised_counted_and_never_reach_the_output() {
    let scene = Scene::new(WIDTH, HEIGHT);
    let (mut source, mut target) = two_frame_case(&scene);
    let bad = [
        f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        1e30,
        f32::MAX,
        -5.0,
        3.0,
    ];
    for (i, value) in bad.iter().enumerate() {
        // Frame t: one row of colours, one of base colours, one of metallic values; the
        // target: one row of base colours, one of specular values.
        let x = 5 + 11 * i;
        source.color.set(x, 10, &[*value, 0.5, 0.5, 1.0]);
        source.base_color.set(x, 20, &[0.5, *value, 0.5, 1.0]);
        let mut material = source.material.at(x, 30).to_vec();
        material[0] = *value;
        source.material.set(x, 30, &material);
        target.base_color.set(x, 40, &[0.5, 0.5, *value, 1.0]);
        let mut material = target.material.at(x, 50).to_vec();
        material[1] = *value;
        target.material.set(x, 50, &material);
    }
    let rig = Rig::new(WIDTH as u32, HEIGHT as u32);
    let outcome = run_plugin(&rig, &source, &target, 0.5, &Chained::default());
    let (expected, _) = assert_matches_reference(&source, &target, &outcome, &Chained::default());
    assert!(outcome.output.data.iter().all(|v| v.is_finite()));
    // Frame t: 6 of the 7 colours (3 is a usable colour; -5 is negative light), all 7 base
    // colours and all 7 metallic values. The target: 7 base colours and 7 specular values.
    assert_eq!(expected.source_sanitized, 6 + 7 + 7);
    assert_eq!(expected.target_sanitized, 7 + 7);
}

/// Sizes that do not fill whole 8x8 workgroups, down to a single pixel: every pass clamps its
/// neighbourhoods at the image edge and skips invocations outside it, as the reference does.
#[test]
fn one_pixel_and_odd_sizes_match_the_reference() {
    for (width, height) in [(1, 1), (7, 5), (33, 17)] {
        let scene = Scene::new(width, height);
        let (source, target) = two_frame_case(&scene);
        let rig = Rig::new(width as u32, height as u32);
        let outcome = run_plugin(&rig, &source, &target, 0.5, &Chained::default());
        assert_matches_reference(&source, &target, &outcome, &Chained::default());
        assert!(outcome.output.data.iter().all(|v| v.is_finite()));
    }
}

#[test]
fn a_camera_cut_asks_the_engine_to_render_instead() {
    let scene = Scene::new(WIDTH, HEIGHT);
    let mut turned = Scene::new(WIDTH, HEIGHT);
    turned.camera_turn = 90f32.to_radians();
    let rig = Rig::new(WIDTH as u32, HEIGHT as u32);
    let engine = &rig.engine;
    let family = engine.queue_family_index;
    let output = output_image(engine, WIDTH as u32, HEIGHT as u32);
    let source = GpuFrame::upload(engine, &scene.render(0.0, Vec2::ZERO, -FRAME_TIME));
    let ahead = GpuFrame::upload(engine, &scene.render(0.5 * FRAME_TIME, Vec2::ZERO, 0.0));
    let cut = GpuFrame::upload(engine, &turned.render(0.5 * FRAME_TIME, Vec2::ZERO, 0.0));
    engine.run(|cmd| {
        assert_eq!(
            rig.submit(cmd, &source.frame_desc(1, family)),
            PatchexResult::Success
        );
        let results = [&ahead, &cut]
            .map(|target| rig.extrapolate(cmd, &target.extrapolate_desc(&output, 0.5, family)));
        assert_eq!(
            results,
            [PatchexResult::Success, PatchexResult::RenderInstead],
            "the turned camera is a cut, known when recording"
        );
    });
    let (result, stats) = rig.stats(1);
    assert_eq!(result, PatchexResult::Success);
    let [trusted, cut] = [stats.extrapolations[0], stats.extrapolations[1]];
    assert_eq!(
        trusted.render_instead_reasons, 0,
        "an ordinary target is trusted (holes {})",
        trusted.hole_fraction
    );
    assert_ne!(
        cut.render_instead_reasons & PATCHEX_RENDER_INSTEAD_CAMERA_CUT,
        0
    );
    // Looking elsewhere, most of the target has nothing to come from in frame t.
    assert!(
        cut.hole_fraction > PATCHEX_MAX_TRUSTED_HOLE_FRACTION,
        "{}",
        cut.hole_fraction
    );
    assert_ne!(
        cut.render_instead_reasons & PATCHEX_RENDER_INSTEAD_DISOCCLUSION,
        0
    );
}

/// The stats report what each stage's passes move, derived from what they bind: nothing for a
/// stage that did not run, and for the G-buffer packing exactly the engine's geometry images
/// (plus its counter) as read.
#[test]
fn stats_report_each_stages_declared_traffic() {
    use ash::vk;
    use patchex::vk::image::texel_bytes;
    let scene = Scene::new(WIDTH, HEIGHT);
    let (source, target) = two_frame_case(&scene);
    let rig = Rig::new(WIDTH as u32, HEIGHT as u32);
    let outcome = run_plugin(&rig, &source, &target, 0.5, &Chained::default());
    let stats = &outcome.stats;
    let regions = [
        (stats.submit_stages_run, &stats.submit_traffic),
        (
            stats.extrapolations[0].stages_run,
            &stats.extrapolation_traffic[0],
        ),
    ];
    for (stages_run, traffic) in regions {
        for stage in 0..PATCHEX_STAGE_SLOTS {
            let moved = traffic.bytes_read[stage] + traffic.bytes_written[stage];
            if stages_run & (1 << stage) != 0 {
                assert!(moved > 0, "stage {stage} ran and moved nothing");
            } else if stage != PATCHEX_STAGE_INFERENCE as usize
                && stage != PATCHEX_STAGE_BLEND as usize
            {
                // (The networks' stages are recorded even when the GPU finds no patch.)
                assert_eq!(moved, 0, "stage {stage} did not run");
            }
        }
    }
    let pixels = (WIDTH * HEIGHT) as u64;
    let frame = GpuFrame::upload(&rig.engine, &source);
    let depth = vk::ImageAspectFlags::DEPTH;
    let engine_geometry = pixels
        * (texel_bytes(frame.depth.format, depth)
            + texel_bytes(frame.normal.format, vk::ImageAspectFlags::COLOR)
            + texel_bytes(frame.stencil.format, vk::ImageAspectFlags::STENCIL));
    let counter = 4;
    let pack = PATCHEX_STAGE_PACK_SOURCE_GBUFFER as usize;
    assert_eq!(
        stats.submit_traffic.bytes_read[pack],
        engine_geometry + counter
    );
    assert!(stats.submit_traffic.arithmetic_operations[pack] >= pixels);
}
