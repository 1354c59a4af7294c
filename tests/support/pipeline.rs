//! One extrapolation through the C ABI with every intermediate result read back (through a
//! chained `PatchexDiagnostics` image), and its comparison with the plain-Rust reference.
//!
//! Tolerance: the GPU and the reference run the same f32 arithmetic, but exp(), fused
//! multiply-adds and the order of matrix products differ in the last bits, and both round the
//! result to the RGBA16F output (one f16 step is 2^-10 relative). A pixel matches when it is
//! within 2e-3 relative (two f16 steps) plus 1e-4 absolute. The warp has two thresholds (the
//! agreeing share of the bilinear footprint, and the best agreement for holes); a last-bit
//! difference can flip a pixel whose reference value lies within 1e-4 of one, so only such
//! pixels may differ beyond the tolerance, and the check reports how many there were. Holes
//! follow the same rule. Regions, rectangles and pixel counts are integer results of integer
//! atomics and must match exactly. An LBP bit compares two luminances, so it may differ only
//! where those lie within the colour tolerance of each other or next to an excused pixel.

use std::ffi::c_void;

use patchex::abi::*;
use patchex::camera::Camera;
use patchex::context::NetworkSwitches;
use patchex::error::PatchexResult;
use patchex::passes::segmentation::SegmentationSettings;
use patchex::passes::stage_position;
use patchex::passes::warp::WarpSettings;
use patchex::reference::lbp::{luminance, NEIGHBOURS};
use patchex::reference::warp::{AGREEMENT_THRESHOLD, BILINEAR_ACCEPT};
use patchex::reference::{self, Extrapolation, FrameInputs, Image};

use super::scene::Frame;
use super::*;

/// How close to one of the warp's two thresholds a pixel's weight may be for the plugin and
/// the reference to take different sides. The weights are products of exponentials of inputs
/// stored as half floats (normals); where the whole frame is a dynamic object, the relative
/// depth test makes them this sensitive (0.5004 against 0.5 seen).
const NEAR_THRESHOLD: f32 = 1e-3;

pub fn inputs<'a>(frame: &'a Frame, camera: &'a Camera) -> FrameInputs<'a> {
    FrameInputs {
        color: Some(&frame.color),
        base_color: &frame.base_color,
        material: Some(&frame.material),
        depth: &frame.depth,
        normal: &frame.normal,
        stencil: Some(&frame.stencil),
        motion: Some(&frame.motion),
        camera,
        normal_encoding: PATCHEX_NORMAL_SIGNED,
        motion_vector_scale: [1.0, 1.0],
        sun: None,
        sky: None,
        translucency: None,
    }
}

/// Worst error of an output image against another in units of 1e-3 + 2e-3 x |want|: the colour
/// tolerance loosened for passes whose sums of exponentials and powers differ in their last bits
/// between the GPU and the reference, on top of the warp's.
pub fn worst_output_error(got: &Image, want: &Image) -> f32 {
    got.data
        .iter()
        .zip(&want.data)
        .map(|(&g, &w)| (g - w).abs() / (1e-3 + 2e-3 * w.abs()))
        .fold(0.0, f32::max)
}

/// The pixels `indices` of `image` (RGBA), in one row.
pub fn pixels_of(image: &Image, indices: &[usize]) -> Image {
    Image {
        width: indices.len(),
        height: 1,
        channels: 4,
        data: indices
            .iter()
            .flat_map(|&i| image.data[4 * i..4 * i + 4].to_vec())
            .collect(),
    }
}

/// PSNR of the RGB channels, for values in [0, 1].
pub fn psnr(a: &Image, b: &Image) -> f64 {
    let mut squared = 0.0;
    let mut count = 0;
    for (pa, pb) in a.data.chunks(4).zip(b.data.chunks(4)) {
        for c in 0..3 {
            squared += ((pa[c] - pb[c]) as f64).powi(2);
            count += 1;
        }
    }
    10.0 * (1.0 / (squared / count as f64)).log10()
}

pub struct Outcome {
    pub output: Image,
    /// The `PatchexDiagnostics` image: hole, region / 2, LBP code / 255.
    pub diagnostics: Image,
    pub stats: PatchexFrameStats,
}

/// What a test chains onto the extrapolation; `None` leaves the context's default.
#[derive(Default)]
pub struct Chained {
    pub warp: Option<WarpSettings>,
    pub segmentation: Option<SegmentationSettings>,
    /// Which networks run (a context made with PATCHEX_PRESET_NETWORKS only).
    pub networks: Option<NetworkSwitches>,
}

fn segmentation_struct(settings: &SegmentationSettings) -> PatchexSegmentationSettings {
    PatchexSegmentationSettings {
        header: PatchexStructHeader::of::<PatchexSegmentationSettings>(
            PATCHEX_STRUCT_TYPE_SEGMENTATION_SETTINGS,
        ),
        growth_x: settings.growth[0],
        growth_y: settings.growth[1],
    }
}

pub fn read_image(engine: &Engine, image: &EngineImage, width: usize, height: usize) -> Image {
    Image {
        width,
        height,
        channels: 4,
        data: image.read(engine, OUTPUT_LAYOUT),
    }
}

/// Submits `source` as frame 1 and extrapolates `target` from it on the GPU.
pub fn run_plugin(
    rig: &Rig,
    source: &Frame,
    target: &Frame,
    alpha: f32,
    chained: &Chained,
) -> Outcome {
    let gpu_source = GpuFrame::upload(&rig.engine, source);
    let gpu_target = GpuFrame::upload(&rig.engine, target);
    run_plugin_on(rig, &gpu_source, &gpu_target, alpha, chained)
}

/// As [`run_plugin`], on frames already uploaded (in whatever formats).
pub fn run_plugin_on(
    rig: &Rig,
    gpu_source: &GpuFrame,
    gpu_target: &GpuFrame,
    alpha: f32,
    chained: &Chained,
) -> Outcome {
    let format = vk::Format::R16G16B16A16_SFLOAT;
    run_plugin_into(rig, gpu_source, gpu_target, alpha, chained, format)
}

/// As [`run_plugin_on`], into an output image of `output_format`.
pub fn run_plugin_into(
    rig: &Rig,
    gpu_source: &GpuFrame,
    gpu_target: &GpuFrame,
    alpha: f32,
    chained: &Chained,
    output_format: vk::Format,
) -> Outcome {
    let (width, height) = (gpu_source.width as usize, gpu_source.height as usize);
    let engine = &rig.engine;
    let family = engine.queue_family_index;
    let output = output_image_as(engine, output_format, width as u32, height as u32);
    let diagnostics_image = output_image(engine, width as u32, height as u32);

    // The chain, linked back to front: diagnostics, then whatever settings the test gives.
    let mut segmentation = chained.segmentation.as_ref().map(segmentation_struct);
    let mut warp = chained.warp.as_ref().map(WarpSettings::to_abi);
    let networks = chained.networks.map(|run| PatchexNetworkSettings {
        header: PatchexStructHeader::of::<PatchexNetworkSettings>(
            PATCHEX_STRUCT_TYPE_NETWORK_SETTINGS,
        ),
        run_fi: run.fi as u32,
        run_near_be: run.near_be as u32,
        whole_frame: run.whole_frame as u32,
        resolution_divisor: run.divisor,
        correct_valid_pixels: run.correct_valid_pixels as u32,
    });
    let mut next: *const c_void = std::ptr::null();
    if let Some(networks) = &networks {
        next = networks as *const _ as *const c_void;
    }
    if let Some(segmentation) = &mut segmentation {
        segmentation.header.next = next;
        next = segmentation as *const _ as *const c_void;
    }
    if let Some(warp) = &mut warp {
        warp.header.next = next;
        next = warp as *const _ as *const c_void;
    }
    let mut diagnostics = PatchexDiagnostics {
        header: PatchexStructHeader::of::<PatchexDiagnostics>(PATCHEX_STRUCT_TYPE_DIAGNOSTICS),
        image: diagnostics_image.describe(OUTPUT_LAYOUT),
    };
    diagnostics.header.next = next;

    engine.run(|cmd| {
        assert_eq!(
            rig.submit(cmd, &gpu_source.frame_desc(1, family)),
            PatchexResult::Success,
            "{}",
            rig.last_error()
        );
        let mut desc = gpu_target.extrapolate_desc(&output, alpha, family);
        desc.header.next = &diagnostics as *const _ as *const c_void;
        assert_eq!(
            rig.extrapolate(cmd, &desc),
            PatchexResult::Success,
            "{}",
            rig.last_error()
        );
    });
    // Every engine image is read back in the layout it was handed in: validation reports any
    // image the plugin left in another layout.
    let output = read_image(engine, &output, width, height);
    let diagnostics = read_image(engine, &diagnostics_image, width, height);
    gpu_source.color.read(engine, COLOR_LAYOUT);
    gpu_source.depth.read(engine, DEPTH_LAYOUT);
    gpu_target.motion.read(engine, MOTION_LAYOUT);
    gpu_target.normal.read(engine, GBUFFER_LAYOUT);
    let (result, stats) = rig.stats(1);
    assert_eq!(result, PatchexResult::Success, "{}", rig.last_error());
    Outcome {
        output,
        diagnostics,
        stats,
    }
}

/// The reference computed its stages in the order of the stage table, and each is a stage the
/// plugin ran (whose recorder holds its own calls to that order).
pub fn assert_stages_agree(expected: &Extrapolation, stats: &PatchexFrameStats) {
    let ran = stats.submit_stages_run | stats.extrapolations[0].stages_run;
    for pair in expected.stages.windows(2) {
        assert!(
            stage_position(pair[0]) < stage_position(pair[1]),
            "the reference computed stage {} before stage {}, against passes::STAGES",
            pair[0],
            pair[1]
        );
    }
    for &stage in &expected.stages {
        assert!(
            ran & (1 << stage) != 0,
            "the reference computed stage {stage}, which the plugin did not run ({ran:#b})"
        );
    }
}

/// Compares every result of the plugin with the reference; returns the reference's results and
/// the number of pixels excused as lying at a threshold.
pub fn assert_matches_reference(
    source: &Frame,
    target: &Frame,
    outcome: &Outcome,
    chained: &Chained,
) -> (Extrapolation, usize) {
    let (width, height) = (source.color.width, source.color.height);
    let source_camera = Camera::from_abi(&source.camera, "source").unwrap();
    let target_camera = Camera::from_abi(&target.camera, "target").unwrap();
    let expected = reference::extrapolate(
        &inputs(source, &source_camera),
        &inputs(target, &target_camera),
        None,
        outcome.stats.extrapolations[0].alpha,
        &chained.warp.unwrap_or_default(),
        &chained.segmentation.unwrap_or_default(),
        Default::default(),
    );
    assert_stages_agree(&expected, &outcome.stats);
    let warped = &expected.warped;
    let at_threshold = |x: usize, y: usize| {
        let i = y * width + x;
        (warped.bilinear_weight[i] - BILINEAR_ACCEPT).abs() < NEAR_THRESHOLD
            || (warped.best_agreement[i] - AGREEMENT_THRESHOLD).abs() < NEAR_THRESHOLD
    };
    let mut excused = 0;
    let mut worst = (0.0f32, 0, 0);
    for y in 0..height {
        for x in 0..width {
            let (got, want) = (outcome.output.at(x, y), expected.output.at(x, y));
            let error = (0..3)
                .map(|c| (got[c] - want[c]).abs() / (2e-3 * want[c].abs() + 1e-4))
                .fold(0.0, f32::max);
            let hole_differs = outcome.diagnostics.at(x, y)[0] != 1.0 - warped.warped.at(x, y)[3];
            if error > 1.0 || hole_differs {
                assert!(
                    at_threshold(x, y),
                    "pixel ({x}, {y}): plugin {got:?}, reference {want:?}, hole differs: \
                     {hole_differs}"
                );
                excused += 1;
            }
            if error > worst.0 {
                worst = (error, x, y);
            }
        }
    }
    let pixels = (width * height) as f32;
    // The stats give fractions; back to pixel counts, which f32 rounding may leave off by a hair.
    let count = |fraction: f32| (fraction * pixels).round();
    let stats = &outcome.stats.extrapolations[0];
    let hole_difference = (count(stats.hole_fraction) - warped.hole_pixels as f32).abs();
    assert!(
        hole_difference <= excused as f32,
        "holes: plugin {} pixels, reference {}",
        count(stats.hole_fraction),
        warped.hole_pixels
    );
    assert_eq!(
        count(stats.offscreen_fraction),
        warped.offscreen_pixels as f32
    );
    // The longest motion vector: the same vector, up to the last bits of its length.
    assert!(
        (stats.largest_motion - warped.largest_motion).abs()
            <= 1e-5 * warped.largest_motion.max(1.0),
        "largest motion: plugin {}, reference {}",
        stats.largest_motion,
        warped.largest_motion
    );
    assert_eq!(
        stats.stages_run & (1 << PATCHEX_STAGE_SHADOW_WARP),
        0,
        "no shadow input, no shadow warp"
    );

    // Sanitising: the same pixels counted.
    assert_eq!(
        outcome.stats.source_sanitized_pixels,
        expected.source_sanitized
    );
    assert_eq!(stats.sanitized_pixels, expected.target_sanitized);
    assert_eq!(
        outcome.stats.source_invalid_geometry_pixels,
        expected.source_invalid_geometry
    );
    assert_eq!(
        stats.invalid_geometry_pixels,
        expected.target_invalid_geometry
    );

    // Segmentation: exact.
    let segmented = &expected.segmented;
    for y in 0..height {
        for x in 0..width {
            assert_eq!(
                outcome.diagnostics.at(x, y)[1] * 2.0,
                segmented.regions.at(x, y)[0],
                "region of pixel ({x}, {y})"
            );
        }
    }
    assert_eq!(stats.object_count as usize, segmented.rects.len());
    let reported = segmented.rects.len().min(PATCHEX_MAX_REPORTED_OBJECTS);
    assert_eq!(&stats.rects[..reported], &segmented.rects[..reported]);
    assert_eq!(count(stats.fi_fraction), segmented.fi_pixels as f32);
    assert_eq!(
        count(stats.near_be_fraction),
        segmented.near_be_pixels as f32
    );

    // LBP: bits may differ only at near-ties.
    let mut lbp_ties = 0;
    for y in 0..height {
        for x in 0..width {
            let got = (outcome.diagnostics.at(x, y)[2] * 255.0).round() as u32;
            let want = (expected.lbp.at(x, y)[0] * 255.0).round() as u32;
            if got == want {
                continue;
            }
            let (xi, yi) = (x as i32, y as i32);
            let centre = luminance(&warped.warped, xi, yi);
            let near_excused = (-1..=1).any(|dy| {
                (-1..=1).any(|dx| {
                    let (nx, ny) = (xi + dx, yi + dy);
                    nx >= 0
                        && ny >= 0
                        && (nx as usize) < width
                        && (ny as usize) < height
                        && at_threshold(nx as usize, ny as usize)
                })
            });
            for (k, (dx, dy)) in NEIGHBOURS.iter().enumerate() {
                if (got ^ want) & (1 << k) != 0 {
                    let neighbour = luminance(&warped.warped, xi + dx, yi + dy);
                    let tie = (neighbour - centre).abs()
                        <= 4e-3 * centre.abs().max(neighbour.abs()) + 2e-4;
                    assert!(
                        tie || near_excused,
                        "LBP bit {k} of pixel ({x}, {y}): plugin {got:#010b}, reference \
                         {want:#010b}, luminances {centre} and {neighbour}"
                    );
                }
            }
            lbp_ties += 1;
        }
    }
    println!(
        "worst colour error {:.3} of tolerance at {:?}; {excused} pixel(s) at a warp threshold, \
         {lbp_ties} LBP code(s) at a near-tie; {} object(s), FI {:.4}, near-BE {:.4}",
        worst.0,
        (worst.1, worst.2),
        segmented.rects.len(),
        stats.fi_fraction,
        stats.near_be_fraction
    );
    (expected, excused)
}
