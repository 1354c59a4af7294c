//! Numerical extremes, each run on lavapipe under validation and compared with the plain-Rust
//! reference: broken geometry (NaN and infinite depth, normals and motion), depth exactly at the
//! near and far planes in every convention, sub-pixel and far off-screen motion, frames of the
//! largest width and height, a frame that is all foreground or has no dynamic object, alpha
//! near 0 and exactly 1, and half-float inputs against float ones. Then the values real frames
//! hold: HDR colour over any albedo, black base colour in frame t, a camera far from the world's
//! origin, infinite and out-of-range depth, negative colour, and a near plane the projection
//! disagrees with (tests/c/extremes_test.c makes the same calls from C). (Colour and material
//! extremes, black and metallic surfaces, 1x1 and odd sizes and a camera cut are in
//! `tests/extrapolate.rs`; the translucency mask's, empty, full, uniform, without its motion and
//! at every threshold, in `tests/translucency.rs`.)

mod support;

use glam::Vec2;
use patchex::abi::*;
use patchex::context::MAX_EXTENT;
use patchex::error::PatchexResult;
use patchex::reference::Image;
use support::pipeline::{assert_matches_reference, psnr, run_plugin, run_plugin_on, Chained};
use support::scene::{Frame, Scene};
use support::*;

const WIDTH: usize = 64;
const HEIGHT: usize = 48;
const FRAME_TIME: f32 = 1.0 / 30.0;

const EVERY_DEPTH_CONVENTION: [PatchexDepthConvention; 3] = [
    PATCHEX_DEPTH_HARDWARE,
    PATCHEX_DEPTH_HARDWARE_REVERSED,
    PATCHEX_DEPTH_LINEAR_VIEW_Z,
];

/// The test scene, its depth stored in `convention`.
fn scene_in(convention: PatchexDepthConvention) -> Scene {
    let mut scene = Scene::new(WIDTH, HEIGHT);
    scene.depth_convention = convention;
    scene
}

/// Frame t, and the target `alpha` of a frame time later.
fn frames(scene: &Scene, alpha: f32) -> (Frame, Frame) {
    let source = scene.render(0.0, Vec2::new(0.25, -0.25), -FRAME_TIME);
    let target = scene.render(alpha * FRAME_TIME, Vec2::new(-0.125, 0.375), 0.0);
    (source, target)
}

/// Runs the case, checks it against the reference, and that the output is finite.
fn run_and_compare(source: &Frame, target: &Frame, alpha: f32) -> PatchexExtrapolationStats {
    let rig = Rig::new(source.color.width as u32, source.color.height as u32);
    let outcome = run_plugin(&rig, source, target, alpha, &Chained::default());
    assert_matches_reference(source, target, &outcome, &Chained::default());
    assert!(outcome.output.data.iter().all(|v| v.is_finite()));
    outcome.stats.extrapolations[0]
}

fn fill(image: &mut Image, value: &[f32]) {
    for pixel in image.data.chunks_mut(image.channels) {
        pixel.copy_from_slice(&value[..image.channels]);
    }
}

#[test]
fn nan_and_infinite_geometry_never_reaches_the_output() {
    let scene = Scene::new(WIDTH, HEIGHT);
    let (mut source, mut target) = frames(&scene, 0.5);
    let bad = [f32::NAN, f32::INFINITY, f32::NEG_INFINITY, 1e30, -1e30];
    for (i, &value) in bad.iter().enumerate() {
        let x = 4 + 12 * i;
        for frame in [&mut source, &mut target] {
            frame.depth.set(x, 8, &[value]);
            frame.normal.set(x, 16, &[value, 0.0, value, 0.0]);
            frame.normal.set(x + 1, 16, &[0.0; 4]);
            frame.motion.set(x, 24, &[value, 1.0]);
            frame.motion.set(x + 1, 24, &[0.0, value]);
        }
    }
    let rig = Rig::new(WIDTH as u32, HEIGHT as u32);
    let outcome = run_plugin(&rig, &source, &target, 0.5, &Chained::default());
    assert_matches_reference(&source, &target, &outcome, &Chained::default());
    assert!(outcome.output.data.iter().all(|v| v.is_finite()));
    // Hardware depth: every value is outside [0, 1], so all 5 depths count. Normals and motion
    // vectors: NaN, +inf and -inf (1e30 is finite). Frame t's depth and normal, and the target's
    // as well as its two motion vectors.
    assert_eq!(outcome.stats.source_invalid_geometry_pixels, 5 + 3);
    assert_eq!(
        outcome.stats.extrapolations[0].invalid_geometry_pixels,
        5 + 3 * 3
    );
}

#[test]
fn depth_at_the_near_and_far_planes_in_every_convention() {
    for convention in EVERY_DEPTH_CONVENTION {
        let scene = scene_in(convention);
        let (mut source, mut target) = frames(&scene, 0.5);
        let camera = source.camera;
        // (near plane, far plane): reversed depth has its far plane at infinity, 0.
        let planes = match convention {
            PATCHEX_DEPTH_HARDWARE => [0.0, 1.0],
            PATCHEX_DEPTH_HARDWARE_REVERSED => [1.0, 0.0],
            _ => [camera.near_plane, camera.far_plane],
        };
        for frame in [&mut source, &mut target] {
            for x in 0..WIDTH {
                frame.depth.set(x, 10, &[planes[0]]);
                frame.depth.set(x, 30, &[planes[1]]);
            }
        }
        run_and_compare(&source, &target, 0.5);
    }
}

#[test]
fn sub_pixel_motion_matches_the_reference() {
    let mut scene = Scene::new(WIDTH, HEIGHT);
    scene.sphere_speed = 0.1;
    scene.camera_speed = 0.05;
    let (source, target) = frames(&scene, 0.5);
    let largest = target
        .motion
        .data
        .iter()
        .fold(0.0f32, |m, v| m.max(v.abs()));
    assert!(
        largest > 0.0 && largest < 1.0,
        "sub-pixel motion: {largest}"
    );
    run_and_compare(&source, &target, 0.5);
}

#[test]
fn motion_far_off_screen_makes_the_frame_a_hole_and_says_so() {
    let scene = Scene::new(WIDTH, HEIGHT);
    let (source, mut target) = frames(&scene, 0.5);
    for value in &mut target.motion.data {
        *value = if *value == 0.0 { 1e7 } else { *value * 1e7 };
    }
    let stats = run_and_compare(&source, &target, 0.5);
    assert_eq!(stats.offscreen_fraction, 1.0);
    assert_eq!(stats.hole_fraction, 1.0);
    assert_ne!(
        stats.render_instead_reasons & PATCHEX_RENDER_INSTEAD_DISOCCLUSION,
        0
    );
}

/// A row and a column of the largest extent a context accepts: the dispatches' group counts
/// and the edge clamping at that size. (A full 16384x16384 frame needs 24 GB of working images,
/// more than this machine has.)
#[test]
fn frames_of_the_largest_width_and_height() {
    for (width, height) in [(MAX_EXTENT as usize, 1), (1, MAX_EXTENT as usize)] {
        let scene = Scene::new(width, height);
        let (source, target) = frames(&scene, 0.5);
        run_and_compare(&source, &target, 0.5);
    }
}

#[test]
fn a_frame_all_foreground_and_one_without_dynamic_objects() {
    let scene = Scene::new(WIDTH, HEIGHT);
    let (mut source, mut target) = frames(&scene, 0.5);
    for frame in [&mut source, &mut target] {
        fill(&mut frame.stencil, &[1.0]);
    }
    let stats = run_and_compare(&source, &target, 0.5);
    assert_eq!(stats.object_count, 1);
    assert_eq!(stats.fi_fraction, 1.0);

    for frame in [&mut source, &mut target] {
        fill(&mut frame.stencil, &[0.0]);
    }
    let stats = run_and_compare(&source, &target, 0.5);
    assert_eq!(stats.object_count, 0);
    assert_eq!((stats.fi_fraction, stats.near_be_fraction), (0.0, 0.0));
}

#[test]
fn alpha_near_zero_and_exactly_one() {
    let scene = Scene::new(WIDTH, HEIGHT);
    for alpha in [1e-6, 1.0] {
        let (source, target) = frames(&scene, alpha);
        let stats = run_and_compare(&source, &target, alpha);
        assert_eq!(stats.alpha, alpha);
    }
}

/// Half-float G-buffers give the same result as float G-buffers holding the same (rounded)
/// values, and differ from the unrounded float path only by the rounding of the inputs.
#[test]
fn half_float_inputs_match_the_reference_and_the_float_path() {
    let scene = Scene::new(WIDTH, HEIGHT);
    let (source, target) = frames(&scene, 0.5);
    let round = |frame: &Frame| {
        let mut rounded = frame.clone();
        for image in [
            &mut rounded.color,
            &mut rounded.base_color,
            &mut rounded.material,
            &mut rounded.normal,
            &mut rounded.motion,
        ] {
            for value in &mut image.data {
                *value = half::f16::from_f32(*value).to_f32();
            }
        }
        rounded
    };
    let (half_source, half_target) = (round(&source), round(&target));

    let rig = Rig::new(WIDTH as u32, HEIGHT as u32);
    let half = run_plugin_on(
        &rig,
        &GpuFrame::upload_half(&rig.engine, &source),
        &GpuFrame::upload_half(&rig.engine, &target),
        0.5,
        &Chained::default(),
    );
    assert_matches_reference(&half_source, &half_target, &half, &Chained::default());

    let float_rig = Rig::new(WIDTH as u32, HEIGHT as u32);
    let float = run_plugin(&float_rig, &source, &target, 0.5, &Chained::default());
    let agreement = psnr(&half.output, &float.output);
    println!("half-float against float inputs: PSNR {agreement:.1} dB");
    assert!(
        agreement > 60.0,
        "half-float inputs stay within input rounding of the float path: {agreement:.1} dB"
    );
}

/// A still scene: frame t and the target are the same rendered instant.
fn still_frame(scene: &mut Scene) -> Frame {
    scene.sphere_speed = 0.0;
    scene.camera_speed = 0.0;
    scene.render(0.0, Vec2::ZERO, -FRAME_TIME)
}

fn colour_channels(image: &Image) -> impl Iterator<Item = f32> + '_ {
    image
        .data
        .chunks(4)
        .flat_map(|pixel| pixel[..3].iter().copied())
}

/// Bright HDR colour comes back unchanged over any base colour, black included, with nothing
/// counted as sanitised: where the shading would not fit a half float, its divisor is scaled up
/// and remodulation scales it back.
#[test]
fn bright_colour_comes_back_unchanged_over_any_albedo() {
    let mut scene = Scene::new(WIDTH, HEIGHT);
    let mut frame = still_frame(&mut scene);
    let (bases, colours) = ([0.0, 0.2, 0.5, 0.8, 1.0], [30000.0, 3000.0, 65504.0]);
    for y in 0..HEIGHT {
        for x in 0..WIDTH {
            let base = bases[x * bases.len() / WIDTH];
            let colour = colours[y * colours.len() / HEIGHT];
            frame.base_color.set(x, y, &[base, base, base, 1.0]);
            frame.color.set(x, y, &[colour, colour, colour, 1.0]);
        }
    }
    let rig = Rig::new(WIDTH as u32, HEIGHT as u32);
    let outcome = run_plugin(&rig, &frame, &frame, 0.5, &Chained::default());
    assert_matches_reference(&frame, &frame, &outcome, &Chained::default());
    for (got, want) in colour_channels(&outcome.output).zip(colour_channels(&frame.color)) {
        assert!(
            (got - want).abs() <= want / 1024.0,
            "{got} for {want}: a half float's step at most"
        );
    }
    assert_eq!(outcome.stats.source_sanitized_pixels, 0);
    assert_eq!(outcome.stats.extrapolations[0].sanitized_pixels, 0);
}

/// A black, nearly black or NaN base colour in frame t under a lit one at the target: what is
/// warped from the dark surface never comes back brighter than its colour, so the output stays
/// within the inputs' range instead of multiplying a colour divided by the floor of the
/// modulation. The NaN base colours are counted.
#[test]
fn a_black_base_colour_in_frame_t_does_not_blow_up() {
    let scene = Scene::new(WIDTH, HEIGHT);
    let (mut source, target) = frames(&scene, 0.5);
    let bands = [0.0, 1e-7, f32::NAN];
    let mut nan_pixels = 0;
    for y in 0..HEIGHT {
        for x in 0..WIDTH {
            let base = bands[x * bands.len() / WIDTH];
            source.base_color.set(x, y, &[base, base, base, 1.0]);
            nan_pixels += base.is_nan() as u32;
        }
    }
    let rig = Rig::new(WIDTH as u32, HEIGHT as u32);
    let outcome = run_plugin(&rig, &source, &target, 0.5, &Chained::default());
    assert_matches_reference(&source, &target, &outcome, &Chained::default());
    let brightest_input = colour_channels(&source.color)
        .chain(colour_channels(&target.color))
        .fold(0.0f32, f32::max);
    let brightest_output = colour_channels(&outcome.output).fold(0.0f32, f32::max);
    assert!(
        brightest_output <= brightest_input * 1.001,
        "output {brightest_output} from inputs of at most {brightest_input}"
    );
    assert_eq!(outcome.stats.source_sanitized_pixels, nan_pixels);
}

/// Cameras 1e7 units from the world's origin (an open world's far corner): accepted, and the
/// extrapolation is the one the same scene gives at the origin. The camera stands still, so both
/// instants' view matrices round alike in f32.
#[test]
fn a_camera_far_from_the_origin_extrapolates_as_at_the_origin() {
    let mut scene = Scene::new(WIDTH, HEIGHT);
    scene.camera_speed = 0.0;
    let (source, target) = frames(&scene, 0.5);
    let far = |frame: &Frame| {
        let mut far = frame.clone();
        far.camera.view[14] += 1e7;
        far
    };
    let (far_source, far_target) = (far(&source), far(&target));
    let run = |source, target| {
        let rig = Rig::new(WIDTH as u32, HEIGHT as u32);
        run_plugin(&rig, source, target, 0.5, &Chained::default())
    };
    let (at_origin, far_away) = (run(&source, &target), run(&far_source, &far_target));
    assert_matches_reference(&far_source, &far_target, &far_away, &Chained::default());
    let agreement = psnr(&far_away.output, &at_origin.output);
    assert!(agreement > 60.0, "far from the origin: {agreement:.1} dB");
}

/// Depth no engine means: +infinity and values outside [0, 1] in hardware depth, a negative
/// linear depth. Each pixel is counted as invalid geometry in both frames and is a hole, so an
/// all-invalid frame asks to be rendered instead. +infinity in linear depth is sky: valid.
#[test]
fn infinite_and_out_of_range_depth_is_counted_and_a_hole() {
    for (convention, depth, usable) in [
        (PATCHEX_DEPTH_HARDWARE, f32::INFINITY, false),
        (PATCHEX_DEPTH_HARDWARE, -0.5, false),
        (PATCHEX_DEPTH_HARDWARE, 1.5, false),
        (PATCHEX_DEPTH_HARDWARE_REVERSED, -0.5, false),
        (PATCHEX_DEPTH_LINEAR_VIEW_Z, -5.0, false),
        (PATCHEX_DEPTH_LINEAR_VIEW_Z, f32::INFINITY, true),
    ] {
        let (mut source, mut target) = frames(&scene_in(convention), 0.5);
        for frame in [&mut source, &mut target] {
            fill(&mut frame.depth, &[depth]);
        }
        let rig = Rig::new(WIDTH as u32, HEIGHT as u32);
        let outcome = run_plugin(&rig, &source, &target, 0.5, &Chained::default());
        assert_matches_reference(&source, &target, &outcome, &Chained::default());
        let stats = &outcome.stats.extrapolations[0];
        let invalid = if usable { 0 } else { (WIDTH * HEIGHT) as u32 };
        let case = format!("depth {depth} in convention {convention}");
        assert_eq!(
            outcome.stats.source_invalid_geometry_pixels, invalid,
            "{case}"
        );
        assert_eq!(stats.invalid_geometry_pixels, invalid, "{case}");
        if !usable {
            assert_eq!(stats.hole_fraction, 1.0, "{case}");
            assert_ne!(
                stats.render_instead_reasons & PATCHEX_RENDER_INSTEAD_DISOCCLUSION,
                0,
                "{case}"
            );
        }
        assert!(outcome.output.data.iter().all(|v| v.is_finite()), "{case}");
    }
}

/// Negative colour is not light: it becomes 0 and is counted, and no output is negative.
#[test]
fn negative_colour_is_counted_and_never_reaches_the_output() {
    let scene = Scene::new(WIDTH, HEIGHT);
    let (mut source, target) = frames(&scene, 0.5);
    for x in 0..WIDTH {
        let mut pixel = source.color.at(x, 5).to_vec();
        pixel[0] = -1.0;
        source.color.set(x, 5, &pixel);
    }
    let rig = Rig::new(WIDTH as u32, HEIGHT as u32);
    let outcome = run_plugin(&rig, &source, &target, 0.5, &Chained::default());
    assert_matches_reference(&source, &target, &outcome, &Chained::default());
    assert_eq!(outcome.stats.source_sanitized_pixels, WIDTH as u32);
    assert!(colour_channels(&outcome.output).all(|v| v >= 0.0));
}

/// A near plane other than the one the projection puts depth 0 (or 1, reversed) at is refused
/// with a message that names it, in every depth convention; within 1% it is accepted.
#[test]
fn a_near_plane_the_projection_disagrees_with_is_refused() {
    for convention in EVERY_DEPTH_CONVENTION {
        let scene = scene_in(convention);
        let (mut source, _) = frames(&scene, 0.5);
        let rig = Rig::new(WIDTH as u32, HEIGHT as u32);
        let family = rig.engine.queue_family_index;
        let true_near = source.camera.near_plane;
        for (near, accepted) in [(true_near * 1.005, true), (true_near * 5.0, false)] {
            source.camera.near_plane = near;
            let gpu = GpuFrame::upload(&rig.engine, &source);
            let mut result = PatchexResult::Success;
            rig.engine
                .run(|cmd| result = rig.submit(cmd, &gpu.frame_desc(1, family)));
            if accepted {
                assert_eq!(result, PatchexResult::Success, "{}", rig.last_error());
            } else {
                assert_eq!(result, PatchexResult::ErrorInvalidArgument);
                assert!(
                    rig.last_error().contains("near_plane"),
                    "{}",
                    rig.last_error()
                );
            }
        }
    }
}
