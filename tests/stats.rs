//! Each statistic counts what the header says it counts. On a still scene (frame t and the target
//! the same rendered instant, so a clean run counts nothing), one input of one instant is spoiled
//! in a known set of pixels, and the statistic the header names for it must count exactly those
//! pixels while every other counter stays at zero. The stages' command counts match what the
//! plugin recorded into the engine's command buffer.

mod support;

use glam::Vec2;
use patchex::abi::*;
use patchex::error::PatchexResult;
use support::pipeline::{assert_matches_reference, run_plugin, Chained};
use support::scene::{Frame, Scene};
use support::*;

const WIDTH: usize = 48;
const HEIGHT: usize = 32;

/// The spoiled pixels: every fifth pixel of rows 4 to 11.
fn spoiled() -> Vec<(usize, usize)> {
    (4..12)
        .flat_map(|y| (0..WIDTH).map(move |x| (x, y)))
        .filter(|(x, y)| (x + y * WIDTH) % 5 == 0)
        .collect()
}

/// Everything the header calls a count, for one frame and its one extrapolation.
#[derive(Debug, Default, PartialEq)]
struct Counts {
    source_sanitized_pixels: u32,
    source_invalid_geometry_pixels: u32,
    sanitized_pixels: u32,
    invalid_geometry_pixels: u32,
    hole_pixels: u32,
    offscreen_pixels: u32,
}

fn still_frame() -> Frame {
    let mut scene = Scene::new(WIDTH, HEIGHT);
    scene.sphere_speed = 0.0;
    scene.camera_speed = 0.0;
    scene.render(0.0, Vec2::ZERO, -1.0 / 30.0)
}

/// Which instant a case spoils.
#[derive(Clone, Copy)]
enum Instant {
    FrameT,
    Target,
}

/// Extrapolates the still frame from itself with `spoil_frame` applied to `instant`'s copy,
/// checks the run against the reference, and returns the counts and the extrapolation's
/// statistics.
fn run_spoiled(
    instant: Instant,
    spoil_frame: impl FnOnce(&mut Frame),
) -> (Counts, PatchexExtrapolationStats) {
    let clean = still_frame();
    let mut spoiled = clean.clone();
    spoil_frame(&mut spoiled);
    let (source, target) = match instant {
        Instant::FrameT => (&spoiled, &clean),
        Instant::Target => (&clean, &spoiled),
    };
    let rig = Rig::new(WIDTH as u32, HEIGHT as u32);
    let outcome = run_plugin(&rig, source, target, 0.5, &Chained::default());
    assert_matches_reference(source, target, &outcome, &Chained::default());
    let stats = outcome.stats.extrapolations[0];
    let pixels = (WIDTH * HEIGHT) as f32;
    let count = |fraction: f32| (fraction * pixels).round() as u32;
    let counts = Counts {
        source_sanitized_pixels: outcome.stats.source_sanitized_pixels,
        source_invalid_geometry_pixels: outcome.stats.source_invalid_geometry_pixels,
        sanitized_pixels: stats.sanitized_pixels,
        invalid_geometry_pixels: stats.invalid_geometry_pixels,
        hole_pixels: count(stats.hole_fraction),
        offscreen_pixels: count(stats.offscreen_fraction),
    };
    (counts, stats)
}

/// A case's name and how it spoils a frame.
type Spoiling = (&'static str, fn(&mut Frame));

/// Spoils channel `channel` of `image` at the spoiled pixels with `value`.
fn spoil(image: &mut patchex::reference::Image, channel: usize, value: f32) {
    for (x, y) in spoiled() {
        let mut pixel = image.at(x, y).to_vec();
        pixel[channel] = value;
        image.set(x, y, &pixel);
    }
}

#[test]
fn a_clean_still_frame_counts_nothing() {
    let (counts, stats) = run_spoiled(Instant::Target, |_| {});
    assert_eq!(counts, Counts::default());
    assert_eq!(stats.render_instead_reasons, 0);
    assert_eq!(stats.largest_motion, 0.0);
}

/// `source_sanitized_pixels`: frame t's colour NaN, infinite, negative or beyond 65504, or its
/// base colour or material outside [0, 1].
#[test]
fn source_sanitized_pixels_counts_frame_ts_unusable_colour_and_material() {
    let k = spoiled().len() as u32;
    let cases: [Spoiling; 6] = [
        ("NaN colour", |f| spoil(&mut f.color, 0, f32::NAN)),
        ("infinite colour", |f| spoil(&mut f.color, 1, f32::INFINITY)),
        ("negative colour", |f| spoil(&mut f.color, 2, -0.25)),
        ("colour beyond 65504", |f| spoil(&mut f.color, 0, 1e6)),
        ("base colour above 1", |f| spoil(&mut f.base_color, 1, 1.5)),
        ("metallic below 0", |f| spoil(&mut f.material, 0, -0.5)),
    ];
    for (case, spoil_frame) in cases {
        let (counts, _) = run_spoiled(Instant::FrameT, spoil_frame);
        let want = Counts {
            source_sanitized_pixels: k,
            ..Counts::default()
        };
        assert_eq!(counts, want, "{case}");
    }
}

/// `sanitized_pixels`: the target's base colour or material outside [0, 1] or NaN.
#[test]
fn sanitized_pixels_counts_the_targets_unusable_material() {
    let k = spoiled().len() as u32;
    for (case, channel, value) in [("NaN", 0, f32::NAN), ("above 1", 2, 3.0)] {
        let (counts, _) = run_spoiled(Instant::Target, |f| {
            spoil(&mut f.base_color, channel, value)
        });
        let want = Counts {
            sanitized_pixels: k,
            ..Counts::default()
        };
        assert_eq!(counts, want, "base colour {case}");
    }
}

/// `source_invalid_geometry_pixels`: frame t's depth NaN or out of range, or its normal not
/// finite. The target's pixels that fetch from them find no agreeing source: holes.
#[test]
fn source_invalid_geometry_pixels_counts_frame_ts_unusable_depth_and_normals() {
    let k = spoiled().len() as u32;
    let cases: [Spoiling; 3] = [
        ("NaN depth", |f| spoil(&mut f.depth, 0, f32::NAN)),
        ("depth above 1", |f| spoil(&mut f.depth, 0, 2.0)),
        ("infinite normal", |f| {
            spoil(&mut f.normal, 1, f32::INFINITY)
        }),
    ];
    for (case, spoil_frame) in cases {
        let (counts, _) = run_spoiled(Instant::FrameT, spoil_frame);
        assert_eq!(counts.source_invalid_geometry_pixels, k, "{case}");
        assert_eq!(
            (
                counts.source_sanitized_pixels,
                counts.invalid_geometry_pixels
            ),
            (0, 0),
            "{case}"
        );
    }
}

/// `invalid_geometry_pixels`: the target's depth NaN or out of range, or its normal or motion
/// vector not finite; each is a hole, counted in `hole_fraction`.
#[test]
fn invalid_geometry_pixels_counts_the_targets_unusable_geometry_as_holes() {
    let k = spoiled().len() as u32;
    let cases: [Spoiling; 4] = [
        ("NaN depth", |f| spoil(&mut f.depth, 0, f32::NAN)),
        ("negative depth", |f| spoil(&mut f.depth, 0, -0.5)),
        ("NaN normal", |f| spoil(&mut f.normal, 2, f32::NAN)),
        ("infinite motion", |f| {
            spoil(&mut f.motion, 0, f32::INFINITY)
        }),
    ];
    for (case, spoil_frame) in cases {
        let (counts, _) = run_spoiled(Instant::Target, spoil_frame);
        assert_eq!(counts.invalid_geometry_pixels, k, "{case}");
        assert_eq!(counts.hole_pixels, k, "{case}: each is a hole");
        assert_eq!(
            (
                counts.source_invalid_geometry_pixels,
                counts.sanitized_pixels
            ),
            (0, 0),
            "{case}"
        );
    }
}

/// `offscreen_fraction`: target pixels whose motion leads out of frame t, each a hole;
/// `largest_motion`: the longest motion vector, in pixels.
#[test]
fn offscreen_fraction_and_largest_motion_measure_the_targets_motion() {
    let k = spoiled().len() as u32;
    let (counts, stats) = run_spoiled(Instant::Target, |f| spoil(&mut f.motion, 0, 1000.0));
    let want = Counts {
        offscreen_pixels: k,
        hole_pixels: k,
        ..Counts::default()
    };
    assert_eq!(counts, want);
    assert_eq!(stats.largest_motion, 1000.0);

    let (_, stats) = run_spoiled(Instant::Target, |f| f.motion.set(20, 16, &[-3.0, 4.0]));
    assert_eq!(stats.largest_motion, 5.0);
}

/// `object_count`, `fi_fraction` and each rectangle's `pixel_count` and mean motion: the
/// target's dynamic objects, by stencil id.
#[test]
fn object_statistics_count_the_targets_stencil_ids() {
    let mut pixels_of = [0u32; 3];
    let mut motion_x_of = [0.0f32; 3];
    let (_, stats) = run_spoiled(Instant::Target, |target| {
        for y in 0..HEIGHT {
            for x in 0..WIDTH {
                let id = [0, 1, 2][(x / 16 + y / 16) % 3];
                target.stencil.set(x, y, &[id as f32]);
                let motion = if id == 2 { 0.25 } else { 0.0 };
                target.motion.set(x, y, &[motion, 0.0]);
                pixels_of[id] += 1;
                motion_x_of[id] += motion;
            }
        }
    });
    assert_eq!(stats.object_count, 2);
    let pixels = (WIDTH * HEIGHT) as f32;
    assert_eq!(
        stats.fi_fraction,
        (pixels_of[1] + pixels_of[2]) as f32 / pixels
    );
    for (rect, id) in stats.rects[..2].iter().zip([1, 2]) {
        assert_eq!(rect.object_id, id as u32);
        assert_eq!(rect.pixel_count, pixels_of[id]);
        assert!((rect.mean_motion_x - motion_x_of[id] / pixels_of[id] as f32).abs() < 1e-6);
    }
}

#[test]
fn stage_commands_count_every_dispatch_the_plugin_records() {
    let (width, height) = (WIDTH as u32, HEIGHT as u32);
    for preset in [PATCHEX_PRESET_WARP_ONLY, PATCHEX_PRESET_NETWORKS] {
        let rig = Rig::intercepted_with_create_info(width, height, |info| info.preset = preset);
        let intercept = rig.intercept.as_ref().expect("intercepted");
        let (source, target) = frame_pair(&rig.engine, width, height, 1);
        let output = output_image(&rig.engine, width, height);
        let family = rig.engine.queue_family_index;
        let mut recorded = None;
        rig.engine.run(|cmd| {
            intercept.take_recorded(cmd);
            assert_eq!(
                rig.submit(cmd, &source.frame_desc(1, family)),
                PatchexResult::Success
            );
            let desc = target.extrapolate_desc(&output, 0.5, family);
            assert_eq!(rig.extrapolate(cmd, &desc), PatchexResult::Success);
            recorded = Some(intercept.take_recorded(cmd));
        });
        let recorded = recorded.expect("recorded");
        let (result, stats) = rig.stats(1);
        assert_eq!(result, PatchexResult::Success, "{}", rig.last_error());
        rig.engine.assert_validation_clean();

        let calls = [
            (&stats.submit_traffic, stats.submit_stages_run),
            (
                &stats.extrapolation_traffic[0],
                stats.extrapolations[0].stages_run,
            ),
        ];
        let mut dispatches = 0;
        let mut barriers = 0;
        for (traffic, stages_run) in calls {
            for stage in 0..PATCHEX_STAGE_SLOTS {
                if stages_run & (1 << stage) != 0 {
                    assert!(
                        traffic.dispatches[stage] > 0,
                        "preset {preset}: stage {stage} ran without a dispatch"
                    );
                }
                dispatches += traffic.dispatches[stage];
                barriers += traffic.barriers[stage];
            }
        }
        assert_eq!(
            dispatches, recorded.dispatches,
            "preset {preset}: every dispatch is a stage's"
        );
        // The rest wait for the engine's work, hand its images back and make the counters
        // readable: outside every stage.
        assert!(
            barriers > 0 && barriers < recorded.barriers,
            "preset {preset}: {barriers} barriers in stages of {} recorded",
            recorded.barriers
        );
    }
}
