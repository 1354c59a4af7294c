//! GPU time per stage of the warp pipeline, without and with the shadow sub-task
//! (PATCHEX_PRESET_WARP_AND_SHADOWS), at 360p, 720p and 1080p, from Vulkan timestamp queries,
//! validation off. Run with `cargo bench --bench extrapolate` (set PATCHEX_DEVICE to pick a
//! device by name). Reports medians and, since the machine may be shared and noisy,
//! ratios between sizes measured in the same run.

#[path = "../tests/support/mod.rs"]
mod support;

use glam::Vec2;
use patchex::abi::{PatchexStage, PATCHEX_PRESET_WARP_AND_SHADOWS};
use patchex::error::PatchexResult;
use patchex::passes::{RuntimeGroup, STAGES};
use patchex_harness::EngineOptions;
use support::scene::Scene;
use support::*;

const SIZES: [(usize, usize); 3] = [(640, 360), (1280, 720), (1920, 1080)];
const WARM_UP: usize = 2;
const RUNS: usize = 10;

fn median(mut values: Vec<f32>) -> f32 {
    values.sort_by(f32::total_cmp);
    values[values.len() / 2]
}

/// Median GPU milliseconds per stage, and of the whole frame.
fn measure(width: usize, height: usize, shadows: bool) -> (Vec<f32>, f32, String) {
    let scene = Scene {
        casts_shadow: true,
        ..Scene::new(width, height)
    };
    let source = scene.render(0.0, Vec2::ZERO, -1.0 / 30.0);
    let target = scene.render(1.0 / 60.0, Vec2::ZERO, 0.0);
    let options = EngineOptions {
        validation: false,
        ..Default::default()
    };
    let rig = Rig::configured(width as u32, height as u32, &options, |info| {
        info.preset = PATCHEX_PRESET_WARP_AND_SHADOWS
    });
    let engine = &rig.engine;
    let family = engine.queue_family_index;
    let (gpu_source, gpu_target) = (
        GpuFrame::upload(engine, &source),
        GpuFrame::upload(engine, &target),
    );
    let output = output_image(engine, width as u32, height as u32);
    let mut per_stage: Vec<Vec<f32>> = vec![Vec::new(); timed_stages().len()];
    let mut totals = Vec::new();
    for run in 0..WARM_UP + RUNS {
        let frame_index = run as u64 + 1;
        let shadow_input = gpu_source.shadow_input();
        let mut frame = gpu_source.frame_desc(frame_index, family);
        if shadows {
            frame.header.next = &shadow_input as *const _ as *const std::ffi::c_void;
        }
        engine.run(|cmd| {
            assert_eq!(rig.submit(cmd, &frame), PatchexResult::Success);
            let desc = gpu_target.extrapolate_desc(&output, 0.5, family);
            assert_eq!(rig.extrapolate(cmd, &desc), PatchexResult::Success);
        });
        let (result, stats) = rig.stats(frame_index);
        assert_eq!(result, PatchexResult::Success);
        if run < WARM_UP {
            continue;
        }
        let mut total = 0.0;
        for (samples, (stage, _)) in per_stage.iter_mut().zip(timed_stages()) {
            let ms = stats.submit_gpu_ms[stage as usize]
                + stats.extrapolations[0].gpu_ms[stage as usize];
            samples.push(ms);
            total += ms;
        }
        totals.push(total);
    }
    (
        per_stage.into_iter().map(median).collect(),
        median(totals),
        engine.device_name.clone(),
    )
}

/// Every stage the benchmark's frames run: all but the diagnostics copy, which it does not ask
/// for, and the packing of an output format other than its RGBA16F.
fn timed_stages() -> Vec<(PatchexStage, &'static str)> {
    STAGES
        .into_iter()
        .filter(|stage| stage.group != RuntimeGroup::Output)
        .map(|stage| (stage.id, stage.name))
        .collect()
}

fn main() {
    let mut rows = Vec::new();
    let mut device = String::new();
    for shadows in [false, true] {
        for (width, height) in SIZES {
            let (stages, total, name) = measure(width, height, shadows);
            device = name;
            rows.push((shadows, width, height, stages, total));
        }
    }
    println!("GPU time per stage, warp-only pipeline, median of {RUNS} runs after {WARM_UP} warm-up, on {device}\n");
    print!("| shadow sub-task | size |");
    for (_, name) in timed_stages() {
        print!(" {name} ms |");
    }
    println!(" total ms | total vs 360p without shadows | pixels vs 360p |");
    println!("|{}", "---|".repeat(timed_stages().len() + 5));
    let (base_pixels, base_total) = ((rows[0].1 * rows[0].2) as f32, rows[0].4);
    for (shadows, width, height, stages, total) in &rows {
        print!(
            "| {} | {width}x{height} |",
            if *shadows { "on" } else { "off" }
        );
        for ms in stages {
            print!(" {ms:.2} |");
        }
        println!(
            " {total:.2} | {:.2}x | {:.2}x |",
            total / base_total,
            (width * height) as f32 / base_pixels
        );
    }
}
