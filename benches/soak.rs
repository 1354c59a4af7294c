//! The soak: 10,000 frames through one context, as an engine's render thread drives it, with
//! resizes, requested resets and frame gaps along the way. At intervals it records the Vulkan
//! objects and device memory the plugin holds (counted by the function-table shim), the device
//! memory its statistics report, the process's heap in use and its resident set. After the
//! first pass through every size, none of them may grow: the run fails if one does.
//!
//! `cargo bench --bench soak [-- FRAMES] [--no-validation]`; writes out/soak/soak.csv and the
//! report, which it also publishes as docs/results/soak.md.

#[path = "../tests/support/mod.rs"]
mod support;

use std::fmt::Write as _;

use glam::Vec2;
use patchex::error::PatchexResult;
use patchex_harness::{EngineOptions, FrameLoop};
use support::scene::Scene;
use support::*;

/// Frame sizes visited in turn, each for RESIZE_EVERY frames; the largest is the maximum.
const SIZES: [(u32, u32); 3] = [(64, 48), (96, 64), (48, 32)];
const RESIZE_EVERY: u64 = 1000;
const RESET_EVERY: u64 = 700;
/// Every GAP_EVERY frames, one frame index is skipped (a frame the engine did not extrapolate).
const GAP_EVERY: u64 = 1500;
const SAMPLE_EVERY: u64 = 500;
/// As the plugin is created with (PatchexCreateInfo::new's default).
const FRAMES_IN_FLIGHT: usize = 2;
/// Distinct frames of the moving sphere cycled through at each size.
const FRAMES_PER_SIZE: usize = 4;
/// Heap growth tolerated over the second half of the run: 64 KiB, under 15 bytes a frame
/// over 5,000 frames, where a leak of one small allocation a frame would show.
const HEAP_SLACK_BYTES: i64 = 64 * 1024;

#[repr(C)]
#[derive(Default)]
struct Mallinfo2 {
    arena: usize,
    ordblks: usize,
    smblks: usize,
    hblks: usize,
    hblkhd: usize,
    usmblks: usize,
    fsmblks: usize,
    uordblks: usize,
    fordblks: usize,
    keepcost: usize,
}

extern "C" {
    /// glibc's heap statistics (2.33 and later).
    fn mallinfo2() -> Mallinfo2;
}

/// Bytes of heap in use in the whole process: the plugin, the driver and the harness.
fn heap_in_use() -> i64 {
    // SAFETY: a plain query of glibc's allocator.
    let info = unsafe { mallinfo2() };
    (info.uordblks + info.hblkhd) as i64
}

fn resident_bytes() -> i64 {
    let statm = std::fs::read_to_string("/proc/self/statm").unwrap_or_default();
    let pages: i64 = statm
        .split_whitespace()
        .nth(1)
        .and_then(|p| p.parse().ok())
        .unwrap_or(0);
    pages * 4096
}

#[derive(Clone, Debug)]
struct Sample {
    frame: u64,
    objects: usize,
    shim_memory_bytes: u64,
    reported_memory_bytes: u64,
    heap_bytes: i64,
    resident_bytes: i64,
}

struct SizedFrames {
    width: u32,
    height: u32,
    pairs: Vec<(GpuFrame, GpuFrame)>,
    outputs: [patchex_harness::EngineImage; 2],
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let frames: u64 = args.iter().find_map(|a| a.parse().ok()).unwrap_or(10_000);
    let validation = !args.iter().any(|a| a == "--no-validation");
    let (max_width, max_height) = (SIZES[1].0, SIZES[1].1);
    let rig = Rig::intercepted_with_options(
        max_width,
        max_height,
        &EngineOptions {
            validation,
            ..Default::default()
        },
    );
    let intercept = rig.intercept.as_ref().expect("intercepted");
    let engine = &rig.engine;
    let family = engine.queue_family_index;
    let sized: Vec<SizedFrames> = SIZES
        .iter()
        .map(|&(width, height)| {
            let scene = Scene::new(width as usize, height as usize);
            let pairs = (0..FRAMES_PER_SIZE)
                .map(|i| {
                    let time = i as f32 / 30.0;
                    let source = scene.render(time, Vec2::ZERO, time - 1.0 / 30.0);
                    let third = scene.render(time + 1.0 / 90.0, Vec2::ZERO, time);
                    (
                        GpuFrame::upload(engine, &source),
                        GpuFrame::upload(engine, &third),
                    )
                })
                .collect();
            let outputs = [
                output_image(engine, width, height),
                output_image(engine, width, height),
            ];
            SizedFrames {
                width,
                height,
                pairs,
                outputs,
            }
        })
        .collect();
    println!(
        "soak: {frames} frames on {}, validation {}",
        engine.device_name,
        if validation { "on" } else { "off" }
    );

    let mut frame_loop = FrameLoop::new(engine, FRAMES_IN_FLIGHT);
    let started = std::time::Instant::now();
    let mut samples: Vec<Sample> = Vec::new();
    let mut frame_index = 0u64;
    let mut resets = 0;
    for frame in 0..frames {
        frame_index += if frame > 0 && frame % GAP_EVERY == 0 {
            2
        } else {
            1
        };
        let size = &sized[(frame / RESIZE_EVERY) as usize % SIZES.len()];
        let (source, target) = &size.pairs[frame as usize % FRAMES_PER_SIZE];
        let mut desc = source.frame_desc(frame_index, family);
        if frame > 0 && frame % RESET_EVERY == 0 {
            desc.reset = 1;
            resets += 1;
        }
        frame_loop.frame(frame_index, |cmd| {
            check(&rig, rig.submit(cmd, &desc), frame);
            // Two extrapolations, as for a 3x frame rate: t + 1/3 and t + 2/3.
            for (output, alpha) in size.outputs.iter().zip([1.0 / 3.0, 2.0 / 3.0]) {
                let target_desc = target.extrapolate_desc(output, alpha, family);
                check(&rig, rig.extrapolate(cmd, &target_desc), frame);
            }
        });
        frame_loop.wait(frame_index);
        let (result, stats) = rig.stats(frame_index);
        check(&rig, result, frame);
        assert_eq!((stats.width, stats.height), (size.width, size.height));
        assert_eq!(stats.extrapolation_count, 2);
        if (frame + 1) % SAMPLE_EVERY == 0 {
            let live = intercept.live();
            samples.push(Sample {
                frame: frame + 1,
                objects: live.total(),
                shim_memory_bytes: live.memory_bytes,
                reported_memory_bytes: stats.device_memory_bytes,
                heap_bytes: heap_in_use(),
                resident_bytes: resident_bytes(),
            });
            let s = samples.last().unwrap();
            println!(
                "frame {:>6}: {} objects, {} B device memory (stats {} B), heap {:.1} MiB, resident {:.1} MiB",
                s.frame,
                s.objects,
                s.shim_memory_bytes,
                s.reported_memory_bytes,
                s.heap_bytes as f64 / 1048576.0,
                s.resident_bytes as f64 / 1048576.0
            );
        }
    }
    let seconds = started.elapsed().as_secs_f64();
    let messages = engine.take_validation_messages();

    // Every size has been visited once by the end of the first cycle: the baseline.
    let baseline_frame = RESIZE_EVERY * SIZES.len() as u64;
    let steady: Vec<&Sample> = samples
        .iter()
        .filter(|s| s.frame >= baseline_frame)
        .collect();
    let mut failures = Vec::new();
    if let (Some(first), Some(last)) = (steady.first(), steady.last()) {
        for s in &steady {
            if s.objects != first.objects {
                failures.push(format!(
                    "live objects {} at frame {} (baseline {})",
                    s.objects, s.frame, first.objects
                ));
            }
            if s.shim_memory_bytes != first.shim_memory_bytes
                || s.reported_memory_bytes != first.reported_memory_bytes
            {
                failures.push(format!("device memory changed at frame {}", s.frame));
            }
        }
        // The heap may take a one-off step (a driver or layer cache filling): what must not
        // happen is a trend, so its growth is judged over the second half of the run.
        let middle = steady[steady.len() / 2];
        let heap_growth = last.heap_bytes - middle.heap_bytes;
        if heap_growth > HEAP_SLACK_BYTES {
            failures.push(format!(
                "heap grew by {heap_growth} B from frame {} to {}",
                middle.frame, last.frame
            ));
        }
    } else {
        failures.push(format!(
            "too few frames for a baseline: run at least {}",
            baseline_frame + SAMPLE_EVERY
        ));
    }
    if !messages.is_empty() {
        failures.push(format!(
            "{} validation message(s), first: {}",
            messages.len(),
            messages[0]
        ));
    }

    let mut report = String::new();
    let _ = writeln!(report, "# Soak: {frames} frames through one context\n");
    let _ = writeln!(
        report,
        "{} with validation {}; sizes {:?} in turn every {RESIZE_EVERY} frames, a requested reset every \
         {RESET_EVERY} frames ({resets} in all), a frame-index gap every {GAP_EVERY}, two extrapolations \
         per frame; {seconds:.0} s ({:.2} ms a frame).\n",
        engine.device_name,
        if validation { "on" } else { "off" },
        SIZES,
        1000.0 * seconds / frames as f64,
    );
    let _ = writeln!(report, "| frame | live Vulkan objects | device memory (shim) | device memory (stats) | heap in use | resident |");
    let _ = writeln!(report, "|---|---|---|---|---|---|");
    let mut csv = String::from(
        "frame,objects,shim_memory_bytes,reported_memory_bytes,heap_bytes,resident_bytes\n",
    );
    for s in &samples {
        let _ = writeln!(
            report,
            "| {} | {} | {:.2} MiB | {:.2} MiB | {:.2} MiB | {:.1} MiB |",
            s.frame,
            s.objects,
            s.shim_memory_bytes as f64 / 1048576.0,
            s.reported_memory_bytes as f64 / 1048576.0,
            s.heap_bytes as f64 / 1048576.0,
            s.resident_bytes as f64 / 1048576.0
        );
        let _ = writeln!(
            csv,
            "{},{},{},{},{},{}",
            s.frame,
            s.objects,
            s.shim_memory_bytes,
            s.reported_memory_bytes,
            s.heap_bytes,
            s.resident_bytes
        );
    }
    let verdict = if failures.is_empty() {
        format!(
            "\nFlat: live objects and device memory identical at every sample from frame \
             {baseline_frame} on; heap growth over the second half within {} KiB.\n",
            HEAP_SLACK_BYTES / 1024
        )
    } else {
        format!("\nFAILED:\n- {}\n", failures.join("\n- "))
    };
    report.push_str(&verdict);
    let out = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("out/soak");
    std::fs::create_dir_all(&out).expect("out/soak");
    std::fs::write(out.join("soak.md"), &report).expect("soak.md");
    std::fs::write(out.join("soak.csv"), &csv).expect("soak.csv");
    let results = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/results");
    std::fs::write(results.join("soak.md"), &report).expect("docs/results/soak.md");
    println!("\n{report}");
    if !failures.is_empty() {
        std::process::exit(1);
    }
}

fn check(rig: &Rig, result: PatchexResult, frame: u64) {
    assert!(
        result == PatchexResult::Success,
        "frame {frame}: {result:?}: {}",
        rig.last_error()
    );
}
