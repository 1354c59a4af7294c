//! Every pass on frames rendered by the project's scene renderer (several skinned characters
//! crossing a textured street), through the C ABI under validation, against the plain-Rust
//! reference (tolerances in `support/pipeline.rs`); and the segmentation's contract.

mod support;

use std::collections::BTreeMap;

use patchex::abi::*;
use patchex::passes::segmentation::SegmentationSettings;
use patchex::passes::warp::WarpSettings;
use support::pipeline::{assert_matches_reference, run_plugin, Chained};
use support::rendered::{render, RenderedSequence};
use support::*;

const WIDTH: u32 = 128;
const HEIGHT: u32 = 72;

fn crossing_street() -> RenderedSequence {
    // Frame 0 is rendered, frame 1 is the target halfway to frame 2.
    render("crossing_street.toml", 2, WIDTH, HEIGHT)
}

#[test]
fn every_pass_matches_its_reference_on_rendered_frames() {
    let sequence = crossing_street();
    let (source, target) = (&sequence.frames[0], &sequence.frames[1]);
    let mut outputs = Vec::new();
    for (kind, resample) in [
        (PATCHEX_WARP_GBUFFER_GUIDED, PATCHEX_RESAMPLE_CATMULL_ROM),
        (PATCHEX_WARP_GBUFFER_GUIDED, PATCHEX_RESAMPLE_BILINEAR),
        (PATCHEX_WARP_MOTION_VECTOR, PATCHEX_RESAMPLE_CATMULL_ROM),
        (
            PATCHEX_WARP_OCCLUSION_MOTION_VECTOR,
            PATCHEX_RESAMPLE_CATMULL_ROM,
        ),
    ] {
        let chained = Chained {
            warp: Some(WarpSettings {
                kind,
                resample,
                ..WarpSettings::default()
            }),
            segmentation: Some(SegmentationSettings { growth: [3.0, 1.5] }),
            networks: None,
        };
        let rig = Rig::new(WIDTH, HEIGHT);
        let outcome = run_plugin(&rig, source, target, 0.5, &chained);
        outputs.push(outcome.output.data.clone());
        println!("warp kind {kind}, resample {resample}:");
        let (_, excused) = assert_matches_reference(source, target, &outcome, &chained);
        let pixels = (WIDTH * HEIGHT) as usize;
        assert!(
            excused * 200 < pixels,
            "{excused} of {pixels} pixels sit at a threshold: too many to be last-bit flips"
        );
        let stats = &outcome.stats.extrapolations[0];
        for stage in [
            PATCHEX_STAGE_WARP,
            PATCHEX_STAGE_SEGMENT,
            PATCHEX_STAGE_LBP,
            PATCHEX_STAGE_REMODULATE,
            PATCHEX_STAGE_DIAGNOSTICS,
        ] {
            assert!(stats.gpu_ms[stage as usize] > 0.0, "stage {stage} ran");
        }
    }
    // Catmull-Rom gives the static surfaces the camera's motion shifts by a fraction of a texel
    // other values than bilinear (1.5% of the values here), so the check above compared it.
    let changed = outputs[0]
        .iter()
        .zip(&outputs[1])
        .filter(|(a, b)| a != b)
        .count();
    assert!(
        changed * 200 > outputs[0].len(),
        "{changed} of {} values differ between the resampling filters",
        outputs[0].len()
    );
}

/// One rectangle per character on screen, holding every pixel of that character's stencil and
/// grown beyond its bounds by the motion it makes.
#[test]
fn segmentation_gives_each_character_its_own_rectangle() {
    let sequence = crossing_street();
    let (source, target) = (&sequence.frames[0], &sequence.frames[1]);
    let mut bounds: BTreeMap<u32, [u32; 4]> = BTreeMap::new();
    for y in 0..HEIGHT {
        for x in 0..WIDTH {
            let id = target.stencil.at(x as usize, y as usize)[0] as u32;
            if id != 0 {
                let b = bounds.entry(id).or_insert([x, y, x, y]);
                *b = [b[0].min(x), b[1].min(y), b[2].max(x), b[3].max(y)];
            }
        }
    }
    assert!(
        bounds.len() >= 2,
        "the scene shows several characters: {bounds:?}"
    );

    let rig = Rig::new(WIDTH, HEIGHT);
    let outcome = run_plugin(&rig, source, target, 0.5, &Chained::default());
    let stats = &outcome.stats.extrapolations[0];
    let rects = &stats.rects[..stats.object_count as usize];
    assert_eq!(
        rects.iter().map(|r| r.object_id).collect::<Vec<_>>(),
        bounds.keys().copied().collect::<Vec<_>>(),
        "one rectangle per character, by id"
    );
    let growth = SegmentationSettings::default().growth;
    for (rect, (id, [left, top, right, bottom])) in rects.iter().zip(&bounds) {
        println!("object {id}: bounds {left},{top}..{right},{bottom}, rectangle {rect:?}");
        assert!(
            rect.x <= *left
                && rect.y <= *top
                && rect.x + rect.width > *right
                && rect.y + rect.height > *bottom,
            "object {id}'s rectangle {rect:?} holds its pixels {left},{top}..{right},{bottom}"
        );
        // Grown by k * mean motion on each side, unless the image edge stops it.
        let expected_margin = growth[0] * rect.mean_motion_x;
        let grown_left = (*left - rect.x) as f32;
        let grown_right = (rect.x + rect.width - 1 - *right) as f32;
        assert!(
            (grown_left >= expected_margin.floor() || rect.x == 0)
                && (grown_right >= expected_margin.floor() || rect.x + rect.width == WIDTH),
            "object {id} grows by about {expected_margin} px: {rect:?}"
        );
        assert!(rect.mean_motion_x > 0.0, "the characters walk: {rect:?}");
    }
    assert!(stats.near_be_fraction > 0.0 && stats.fi_fraction > 0.0);
}
