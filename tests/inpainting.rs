//! PATCHEX_PRESET_NETWORKS through the C ABI under validation: the planned patches, both
//! networks and the blend against the plain-Rust reference on rendered frames; a frame without
//! dynamic objects runs no network; networks switched off per call; weight files by path.
//!
//! Tolerance: outside the networks' regions the plugin must match the reference as the warp-only
//! pipeline does (`support/pipeline.rs`). Inside them the networks add f16 storage of every
//! tensor, and a pixel at one of the warp's thresholds (excused there) changes the inputs of
//! every network pixel that sees it, so a repaired pixel matches within 1% plus 2e-3 and at most
//! 1% of the repaired pixels may miss that.

mod support;

use std::ffi::{c_void, CString};

use patchex::abi::*;
use patchex::camera::Camera;
use patchex::context::NetworkSwitches;
use patchex::error::PatchexResult;
use patchex::network::{self, Network, TensorPrecision};
use patchex::passes::segmentation::{REGION_FI, REGION_NEAR_BE};
use patchex::reference::inpaint::Networks;
use patchex::reference::{self, Extrapolation, Image};
use support::pipeline::{inputs, run_plugin, Chained, Outcome};
use support::rendered::render;
use support::scene::Frame;
use support::*;

const WIDTH: u32 = 128;
const HEIGHT: u32 = 72;

fn shipped() -> [Network; 2] {
    [
        Network::from_safetensors(network::SHIPPED_FI, "fi").unwrap(),
        Network::from_safetensors(network::SHIPPED_NEAR_BE, "near_be").unwrap(),
    ]
}

/// What the reference runs for a call with `switches`, with the networks of `shipped`.
fn reference_networks(switches: NetworkSwitches, shipped: &[Network; 2]) -> Networks<'_> {
    let [fi, near_be] = shipped;
    Networks {
        fi: switches.fi.then_some(fi),
        near_be: switches.near_be.then_some(near_be),
        whole_frame: switches.whole_frame,
        divisor: switches.divisor,
        correct_valid_pixels: switches.correct_valid_pixels,
        ..Networks::default()
    }
}

fn networks_rig() -> Rig {
    Rig::with_create_info(WIDTH, HEIGHT, |info| info.preset = PATCHEX_PRESET_NETWORKS)
}

fn expected(source: &Frame, target: &Frame, networks: Networks) -> Extrapolation {
    let source_camera = Camera::from_abi(&source.camera, "source").unwrap();
    let target_camera = Camera::from_abi(&target.camera, "target").unwrap();
    reference::extrapolate(
        &inputs(source, &source_camera),
        &inputs(target, &target_camera),
        None,
        0.5,
        &Default::default(),
        &Default::default(),
        networks,
    )
}

/// Largest component difference relative to the tolerance `relative * |want| + absolute`.
fn error(got: &[f32], want: &[f32], relative: f32, absolute: f32) -> f32 {
    (0..3)
        .map(|c| (got[c] - want[c]).abs() / (relative * want[c].abs() + absolute))
        .fold(0.0, f32::max)
}

/// Checks the plugin's output against the reference with networks; returns the mean absolute
/// change the networks made to the repaired pixels (every pixel with `whole_frame`).
fn assert_matches(
    outcome: &Outcome,
    with: &Extrapolation,
    without: &Extrapolation,
    whole_frame: bool,
) -> f32 {
    let regions = &with.segmented.regions;
    let (mut repaired, mut missed, mut outside_missed, mut change) = (0, 0, 0, 0.0);
    for y in 0..HEIGHT as usize {
        for x in 0..WIDTH as usize {
            let (got, want) = (outcome.output.at(x, y), with.output.at(x, y));
            let region = regions.at(x, y)[0] as u32;
            if whole_frame || region == REGION_FI || region == REGION_NEAR_BE {
                repaired += 1;
                missed += (error(got, want, 1e-2, 2e-3) > 1.0) as usize;
                let before = without.output.at(x, y);
                change += (0..3).map(|c| (want[c] - before[c]).abs()).sum::<f32>() / 3.0;
            } else {
                outside_missed += (error(got, want, 2e-3, 1e-4) > 1.0) as usize;
            }
        }
    }
    println!("{missed} of {repaired} repaired pixels and {outside_missed} others missed");
    assert!(repaired > 0, "the frame has dynamic objects");
    assert!(
        missed * 100 <= repaired,
        "{missed} of {repaired} repaired pixels differ"
    );
    // Far background is the warp's, bit for bit but for threshold pixels (support/pipeline.rs).
    assert!(outside_missed * 200 <= (WIDTH * HEIGHT) as usize);
    change / repaired as f32
}

#[test]
fn networks_repair_their_regions_as_the_reference_does() {
    let sequence = render("crossing_street.toml", 2, WIDTH, HEIGHT);
    let (source, target) = (&sequence.frames[0], &sequence.frames[1]);
    let rig = networks_rig();
    let outcome = run_plugin(&rig, source, target, 0.5, &Chained::default());
    let [fi, near_be] = shipped();
    let with = expected(
        source,
        target,
        Networks {
            fi: Some(&fi),
            near_be: Some(&near_be),
            ..Networks::default()
        },
    );
    support::pipeline::assert_stages_agree(&with, &outcome.stats);
    let without = expected(source, target, Networks::default());
    let change = assert_matches(&outcome, &with, &without, false);
    println!("the networks change repaired pixels by {change} on average");
    assert!(change > 1e-4, "the networks changed the repaired pixels");

    let stats = &outcome.stats.extrapolations[0];
    for stage in [PATCHEX_STAGE_INFERENCE, PATCHEX_STAGE_BLEND] {
        assert!(stats.stages_run & 1 << stage != 0, "stage {stage} ran");
        assert!(
            stats.gpu_ms[stage as usize] > 0.0,
            "stage {stage} was timed"
        );
    }
    let pixels = (WIDTH * HEIGHT) as f32;
    let segmented = &with.segmented;
    let repaired = (segmented.fi_pixels + segmented.near_be_pixels) as f32 / pixels;
    assert_eq!(stats.repaired_fraction, repaired);
    let patches = with.inpainted.as_ref().unwrap().patches;
    println!("patches: {patches:?}");
    assert_eq!(
        stats.network_divisors,
        [1, 1],
        "both ran at the frame's resolution"
    );
    // Cost follows the objects: the patches cover the characters, not the frame.
    let area = |p: reference::inpaint::Patch| p.extent[0] * p.extent[1];
    assert!(area(patches.near_be) < WIDTH * HEIGHT);
}

/// By default a correction replaces only the warp's holes: every pixel the warp found a source
/// for is the warp's, as without networks. With `correct_valid_pixels` (the paper's blend) the
/// corrections cover their regions, as the reference does.
#[test]
fn corrections_replace_only_holes_unless_asked_for_every_pixel() {
    let sequence = render("crossing_street.toml", 2, WIDTH, HEIGHT);
    let (source, target) = (&sequence.frames[0], &sequence.frames[1]);
    let rig = networks_rig();
    let [fi, near_be] = shipped();
    let networks = Networks {
        fi: Some(&fi),
        near_be: Some(&near_be),
        ..Networks::default()
    };
    let without = expected(source, target, Networks::default());
    let gated = expected(source, target, networks);
    let (mut valid, mut holes_changed) = (0, 0);
    for y in 0..HEIGHT as usize {
        for x in 0..WIDTH as usize {
            let (got, before) = (gated.output.at(x, y), without.output.at(x, y));
            if without.warped.warped.at(x, y)[3] != 0.0 {
                valid += 1;
                assert_eq!(got, before, "valid pixel ({x}, {y}) was corrected");
            } else if got != before {
                holes_changed += 1;
            }
        }
    }
    println!("{valid} valid pixels kept; {holes_changed} hole pixels corrected");
    assert!(holes_changed > 0, "the networks corrected some holes");

    let every_pixel = Chained {
        networks: Some(NetworkSwitches {
            correct_valid_pixels: true,
            ..NetworkSwitches::default()
        }),
        ..Chained::default()
    };
    let outcome = run_plugin(&rig, source, target, 0.5, &every_pixel);
    let with = expected(
        source,
        target,
        Networks {
            correct_valid_pixels: true,
            ..networks
        },
    );
    let change = assert_matches(&outcome, &with, &without, false);
    assert!(change > 1e-4, "the networks changed the repaired pixels");
}

#[test]
fn a_network_switched_off_leaves_its_region_to_the_warp() {
    let sequence = render("crossing_street.toml", 2, WIDTH, HEIGHT);
    let (source, target) = (&sequence.frames[0], &sequence.frames[1]);
    let rig = networks_rig();
    let switches = NetworkSwitches {
        fi: false,
        ..NetworkSwitches::default()
    };
    let chained = Chained {
        networks: Some(switches),
        ..Chained::default()
    };
    let outcome = run_plugin(&rig, source, target, 0.5, &chained);
    let shipped = shipped();
    let with = expected(source, target, reference_networks(switches, &shipped));
    let without = expected(source, target, Networks::default());
    assert_matches(&outcome, &with, &without, false);
    let stats = &outcome.stats.extrapolations[0];
    let pixels = (WIDTH * HEIGHT) as f32;
    assert_eq!(
        stats.repaired_fraction,
        with.segmented.near_be_pixels as f32 / pixels
    );
}

/// Both networks at half and at a quarter of the frame's resolution, per call: the patches
/// hold a half (a quarter) of the texels per axis, each the mean of its block, and the results
/// are upsampled onto the regions as the reference does.
#[test]
fn networks_at_a_lower_resolution_match_the_reference() {
    let sequence = render("crossing_street.toml", 2, WIDTH, HEIGHT);
    let (source, target) = (&sequence.frames[0], &sequence.frames[1]);
    let shipped = shipped();
    let without = expected(source, target, Networks::default());
    let mut extents = Vec::new();
    for divisor in [1, 2, 4] {
        let rig = networks_rig();
        // Every region pixel corrected, so that the whole upsampled correction is checked.
        let switches = NetworkSwitches {
            divisor,
            correct_valid_pixels: true,
            ..NetworkSwitches::default()
        };
        let chained = Chained {
            networks: Some(switches),
            ..Chained::default()
        };
        let outcome = run_plugin(&rig, source, target, 0.5, &chained);
        let with = expected(source, target, reference_networks(switches, &shipped));
        let change = assert_matches(&outcome, &with, &without, false);
        let patches = with.inpainted.as_ref().unwrap().patches;
        println!("divisor {divisor}: {patches:?}, change {change}");
        assert!(change > 1e-4, "the networks changed the repaired pixels");
        extents.push(patches.near_be.extent);
        let stats = &outcome.stats.extrapolations[0];
        assert!(stats.stages_run & 1 << PATCHEX_STAGE_INFERENCE != 0);
    }
    // The texels per axis shrink with the divisor (up to rounding to the network's multiple).
    assert!(extents[1][0] * 2 <= extents[0][0] + 8 && extents[2][0] * 4 <= extents[0][0] + 32);
}

/// The ablation of foveated segmentation: the FI network over the whole frame, every pixel
/// repaired, as the reference does. In tensors smaller than the frame (`PatchexNetworkMemory`)
/// the patch doubles its divisor until it fits, the stats report it, and the upsampled
/// correction (over every pixel, `correct_valid_pixels`) is the reference's.
#[test]
fn whole_frame_runs_the_fi_network_over_every_pixel() {
    let sequence = render("crossing_street.toml", 2, WIDTH, HEIGHT);
    let (source, target) = (&sequence.frames[0], &sequence.frames[1]);
    let shipped = shipped();
    let without = expected(source, target, Networks::default());
    // 128 x 72 pixels in at most 32 texels a side: a quarter of the resolution.
    const SIDE: u32 = PATCHEX_NETWORK_PATCH_SIDE_MULTIPLE;
    for (max_patch_side, divisor) in [(None, 1), (Some(SIDE), 4)] {
        let memory = max_patch_side.map(|max_patch_side| PatchexNetworkMemory {
            header: PatchexStructHeader::of::<PatchexNetworkMemory>(
                PATCHEX_STRUCT_TYPE_NETWORK_MEMORY,
            ),
            max_patch_side,
        });
        let rig = Rig::with_create_info(WIDTH, HEIGHT, |info| {
            info.preset = PATCHEX_PRESET_NETWORKS;
            if let Some(memory) = &memory {
                info.header.next = memory as *const _ as *const c_void;
            }
        });
        let switches = NetworkSwitches {
            whole_frame: true,
            correct_valid_pixels: max_patch_side.is_some(),
            ..NetworkSwitches::default()
        };
        let chained = Chained {
            networks: Some(switches),
            ..Chained::default()
        };
        let outcome = run_plugin(&rig, source, target, 0.5, &chained);
        let networks = Networks {
            max_patch_side: max_patch_side.unwrap_or(PATCHEX_DEFAULT_NETWORK_MAX_PATCH_SIDE),
            ..reference_networks(switches, &shipped)
        };
        let with = expected(source, target, networks);
        assert_matches(&outcome, &with, &without, true);
        let patches = with.inpainted.as_ref().unwrap().patches;
        println!("max_patch_side {max_patch_side:?}: {patches:?}");
        assert_eq!(patches.fi.divisor, divisor);
        assert_eq!(patches.blend.extent, [WIDTH, HEIGHT]);
        assert!(patches.near_be.is_empty());
        let stats = &outcome.stats.extrapolations[0];
        assert_eq!(stats.network_divisors, [divisor, 0]);
        assert_eq!(stats.repaired_fraction, 1.0);
    }
}

/// PATCHEX_PRESET_FULL on a static frame without a shadow input: a warp alone.
#[test]
fn a_frame_without_dynamic_objects_runs_no_network_and_no_shadow_pass() {
    let sequence = render("crossing_street.toml", 2, WIDTH, HEIGHT);
    let static_frame = |frame: &Frame| {
        let mut frame = frame.clone();
        frame.stencil = Image::new(WIDTH as usize, HEIGHT as usize, 1);
        frame
    };
    let (source, target) = (
        static_frame(&sequence.frames[0]),
        static_frame(&sequence.frames[1]),
    );
    let rig = Rig::with_create_info(WIDTH, HEIGHT, |info| info.preset = PATCHEX_PRESET_FULL);
    let outcome = run_plugin(&rig, &source, &target, 0.5, &Chained::default());
    let stats = &outcome.stats.extrapolations[0];
    assert_eq!(stats.object_count, 0);
    assert_eq!(stats.repaired_fraction, 0.0);
    for stage in [PATCHEX_STAGE_INFERENCE, PATCHEX_STAGE_SHADOW_WARP] {
        assert_eq!(stats.stages_run & 1 << stage, 0, "stage {stage} ran");
    }
    // The blend remodulates the frame all the same.
    assert_ne!(stats.stages_run & 1 << PATCHEX_STAGE_BLEND, 0);
    assert_eq!(
        outcome.stats.submit_stages_run & 1 << PATCHEX_STAGE_SHADOW_FLOW,
        0
    );
    assert_ne!(stats.stages_run & 1 << PATCHEX_STAGE_WARP, 0);
    // And the output is the warp-only pipeline's.
    let without = expected(&source, &target, Networks::default());
    let missed = (0..HEIGHT as usize)
        .flat_map(|y| (0..WIDTH as usize).map(move |x| (x, y)))
        .filter(|&(x, y)| error(outcome.output.at(x, y), without.output.at(x, y), 2e-3, 1e-4) > 1.0)
        .count();
    assert!(
        missed * 200 <= (WIDTH * HEIGHT) as usize,
        "{missed} pixels differ"
    );
}

/// The networks preset at the extremes, on rendered frames: around the characters, colours at
/// the largest half float, NaN and infinite colours, black and near-black albedo and full
/// metals. With either tensor precision the output stays finite and not negative, the
/// sanitised pixels are counted as the reference counts them, and every pixel outside the
/// networks' regions matches the reference. Inside them the demodulated colours reach the
/// half-float limit, far outside what the networks were trained on, and their sums cancel, so
/// the driver's exp and order of summation decide the last digits: at most one in a hundred
/// repaired pixels may differ from the reference by more than 10% (measured on lavapipe: none
/// of 877; before corrections stopped at zero, 4.7% with FP16 and 2.1% with FP32).
#[test]
fn networks_at_the_numerical_extremes() {
    let sequence = render("crossing_street.toml", 2, WIDTH, HEIGHT);
    let (mut source, mut target) = (sequence.frames[0].clone(), sequence.frames[1].clone());
    // Every second pixel of the characters, cycling through the extremes.
    let moving: Vec<(usize, usize)> = (0..HEIGHT as usize)
        .flat_map(|y| (0..WIDTH as usize).map(move |x| (x, y)))
        .filter(|&(x, y)| source.stencil.at(x, y)[0] != 0.0 && (x + y) % 2 == 0)
        .collect();
    assert!(moving.len() > 50, "{} character pixels", moving.len());
    let max_half = 65504.0;
    for (i, &(x, y)) in moving.iter().enumerate() {
        match i % 5 {
            0 => source.color.set(x, y, &[max_half, max_half, max_half, 1.0]),
            1 => source.color.set(x, y, &[f32::NAN, 1.0, f32::INFINITY, 1.0]),
            2 => source.base_color.set(x, y, &[0.0, 0.0, 0.0, 1.0]),
            3 => source.base_color.set(x, y, &[1e-6, 1e-6, 1e-6, 1.0]),
            _ => {
                for frame in [&mut source, &mut target] {
                    frame.material.set(x, y, &[1.0, 0.5, 0.2, 1.0]);
                }
            }
        }
    }
    let [fi, near_be] = shipped();
    let fp32 = PatchexNetworkPrecision {
        header: PatchexStructHeader::of::<PatchexNetworkPrecision>(
            PATCHEX_STRUCT_TYPE_NETWORK_PRECISION,
        ),
        tensors: PATCHEX_TENSOR_PRECISION_FP32,
    };
    for precision in [TensorPrecision::F16, TensorPrecision::F32] {
        let rig = Rig::with_create_info(WIDTH, HEIGHT, |info| {
            info.preset = PATCHEX_PRESET_NETWORKS;
            if precision == TensorPrecision::F32 {
                info.header.next = &fp32 as *const _ as *const c_void;
            }
        });
        let outcome = run_plugin(&rig, &source, &target, 0.5, &Chained::default());
        assert!(outcome.output.data.iter().all(|v| v.is_finite()));
        // No input colour is below zero, so no output colour is: a correction stops at zero.
        let negative = outcome.output.data.iter().filter(|&&v| v < 0.0).count();
        assert_eq!(negative, 0, "{precision:?}: negative output channels");
        let with = expected(
            &source,
            &target,
            Networks {
                fi: Some(&fi),
                near_be: Some(&near_be),
                precision,
                ..Networks::default()
            },
        );
        let sanitized = outcome.stats.source_sanitized_pixels;
        assert!(sanitized as usize >= moving.len() / 5, "{sanitized}");
        assert_eq!(sanitized, with.source_sanitized);
        // Repaired pixels beyond 1% and 10% (+ 2e-3) of the reference; every other pixel
        // matches it as on ordinary frames.
        let (mut repaired, mut beyond) = (0, [0; 2]);
        for y in 0..HEIGHT as usize {
            for x in 0..WIDTH as usize {
                let (got, want) = (outcome.output.at(x, y), with.output.at(x, y));
                let region = with.segmented.regions.at(x, y)[0] as u32;
                if region == REGION_FI || region == REGION_NEAR_BE {
                    repaired += 1;
                    for (count, relative) in beyond.iter_mut().zip([1e-2, 1e-1]) {
                        *count += (error(got, want, relative, 2e-3) > 1.0) as usize;
                    }
                } else {
                    assert!(
                        error(got, want, 2e-3, 1e-4) <= 1.0,
                        "{x},{y}: {got:?} {want:?}"
                    );
                }
            }
        }
        println!("{precision:?}: of {repaired} repaired pixels {beyond:?} beyond 1% and 10%");
        assert!(beyond[1] * 100 <= repaired, "{beyond:?}");
    }
}

/// `PatchexNetworkWeights` loads weight files by path (the test's tiny network); a missing or
/// broken file, and network settings without the networks preset, are refused with a reason.
#[test]
fn weight_files_and_network_settings_are_checked_at_create() {
    let tiny = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/fixtures/network/tiny.safetensors"
    );
    let tiny = CString::new(tiny).unwrap();
    let missing = CString::new("/nonexistent/fi.safetensors").unwrap();
    let broken_file = tempfile::NamedTempFile::new().unwrap();
    std::fs::write(broken_file.path(), b"not a network").unwrap();
    let broken = CString::new(broken_file.path().to_str().unwrap()).unwrap();
    let engine = patchex_harness::Engine::new(&Default::default()).unwrap();
    let library = open_library();
    let weights = |fi: &CString| PatchexNetworkWeights {
        header: PatchexStructHeader::of::<PatchexNetworkWeights>(
            PATCHEX_STRUCT_TYPE_NETWORK_WEIGHTS,
        ),
        fi_path: fi.as_ptr(),
        near_be_path: std::ptr::null(),
    };
    let create_with = |preset, chain: *const c_void| {
        let mut info = engine.create_info(64, 32);
        info.preset = preset;
        info.header.next = chain;
        create(&library, &info)
    };

    let tiny_weights = weights(&tiny);
    let context = create_with(PATCHEX_PRESET_NETWORKS, &tiny_weights as *const _ as _)
        .unwrap_or_else(|(_, message)| panic!("{message}"));
    // SAFETY: a live context of this library, destroyed once.
    unsafe { (library.destroy)(context) };

    for (path, reason) in [(&missing, "cannot read"), (&broken, "safetensors")] {
        let chain = weights(path);
        let (result, message) =
            create_with(PATCHEX_PRESET_NETWORKS, &chain as *const _ as _).expect_err("refused");
        assert_eq!(result, PatchexResult::ErrorInvalidArgument);
        assert!(message.contains(reason), "{message}");
    }
    let (result, message) =
        create_with(PATCHEX_PRESET_WARP_ONLY, &tiny_weights as *const _ as _).expect_err("refused");
    assert_eq!(result, PatchexResult::ErrorInvalidArgument);
    assert!(message.contains("PATCHEX_PRESET_NETWORKS"), "{message}");
    let whole_frame_without_fi = PatchexNetworkSettings {
        header: PatchexStructHeader::of::<PatchexNetworkSettings>(
            PATCHEX_STRUCT_TYPE_NETWORK_SETTINGS,
        ),
        run_fi: 0,
        run_near_be: 1,
        whole_frame: 1,
        resolution_divisor: 1,
        correct_valid_pixels: 0,
    };
    let valid = PatchexNetworkSettings {
        run_fi: 1,
        whole_frame: 0,
        ..whole_frame_without_fi
    };
    for (settings, reason) in [
        (whole_frame_without_fi, "whole_frame"),
        (
            PatchexNetworkSettings {
                resolution_divisor: 3,
                ..valid
            },
            "resolution_divisor 3",
        ),
        (
            PatchexNetworkSettings {
                correct_valid_pixels: 2,
                ..valid
            },
            "correct_valid_pixels",
        ),
    ] {
        let chain = &settings as *const _ as _;
        let (result, message) = create_with(PATCHEX_PRESET_NETWORKS, chain).expect_err("refused");
        assert_eq!(result, PatchexResult::ErrorInvalidArgument);
        assert!(message.contains(reason), "{message}");
    }
    let (result, message) = create_with(7, std::ptr::null()).expect_err("refused");
    assert_eq!(result, PatchexResult::ErrorInvalidArgument);
    assert!(message.contains("preset 7"), "{message}");

    // FP32 tensors (after the tiny weights, which compile fast); an unknown precision, or one
    // without networks, is refused.
    let precision = |tensors| PatchexNetworkPrecision {
        header: PatchexStructHeader::of::<PatchexNetworkPrecision>(
            PATCHEX_STRUCT_TYPE_NETWORK_PRECISION,
        ),
        tensors,
    };
    let fp32 = precision(PATCHEX_TENSOR_PRECISION_FP32);
    let tiny_fp32 = PatchexNetworkWeights {
        header: PatchexStructHeader {
            next: &fp32 as *const _ as _,
            ..tiny_weights.header
        },
        ..tiny_weights
    };
    let context = create_with(PATCHEX_PRESET_FULL, &tiny_fp32 as *const _ as _)
        .unwrap_or_else(|(_, message)| panic!("{message}"));
    // SAFETY: a live context of this library, destroyed once.
    unsafe { (library.destroy)(context) };
    let unknown = precision(2);
    let (result, message) =
        create_with(PATCHEX_PRESET_NETWORKS, &unknown as *const _ as _).expect_err("refused");
    assert_eq!(result, PatchexResult::ErrorInvalidArgument);
    assert!(
        message.contains("PatchexNetworkPrecision.tensors 2"),
        "{message}"
    );
    let (result, message) =
        create_with(PATCHEX_PRESET_WARP_AND_SHADOWS, &fp32 as *const _ as _).expect_err("refused");
    assert_eq!(result, PatchexResult::ErrorInvalidArgument);
    assert!(message.contains("PatchexNetworkPrecision"), "{message}");

    // A patch side that is not a multiple of 32 from 32 to 4096, or one without networks, is
    // refused.
    let memory = |max_patch_side| PatchexNetworkMemory {
        header: PatchexStructHeader::of::<PatchexNetworkMemory>(PATCHEX_STRUCT_TYPE_NETWORK_MEMORY),
        max_patch_side,
    };
    for side in [0, 16, 48, 8192] {
        let memory = memory(side);
        let (result, message) =
            create_with(PATCHEX_PRESET_NETWORKS, &memory as *const _ as _).expect_err("refused");
        assert_eq!(result, PatchexResult::ErrorInvalidArgument);
        assert!(
            message.contains(&format!("PatchexNetworkMemory.max_patch_side {side}")),
            "{message}"
        );
    }
    let memory = memory(256);
    let (result, message) =
        create_with(PATCHEX_PRESET_WARP_ONLY, &memory as *const _ as _).expect_err("refused");
    assert_eq!(result, PatchexResult::ErrorInvalidArgument);
    assert!(message.contains("PatchexNetworkMemory"), "{message}");
    engine.assert_validation_clean();
}
