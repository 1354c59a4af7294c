//! Render time per frame for every scene under `scenes/` at 360p and 720p.
//!
//! `cargo bench -p patchex-scene --bench render_time [-- FILTER]` prints a Markdown table.
//! A frame is everything `Renderer::render` does: posing and skinning the characters on the
//! CPU, the dynamic shadow map, the G-buffer and resolve passes, and reading all layers back
//! (EXR encoding is not included). Validation is off. Shown are medians over the timed
//! frames: wall time per frame, and GPU time (timestamp queries) of the G-buffer stage
//! (dynamic shadow map + G-buffer pass) and of the resolve pass. The dynamic shadow map is also
//! shown apart, as a share of the frame's GPU time: it is the depth-only pass of the moving
//! casters that an engine runs once more, at the target's pose, for patchex's target shadow
//! input (`PatchexTargetShadowInput`).

use patchex_scene::dataset::frame_time;
use patchex_scene::render::PassTimings;
use patchex_scene::{FrameRequest, Gpu, GpuOptions, Renderer, World};
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

const SIZES: [(u32, u32); 2] = [(640, 360), (1280, 720)];
const WARM_UP_FRAMES: usize = 2;
const TIMED_FRAMES: usize = 8;

fn median(mut samples: Vec<f64>) -> f64 {
    samples.sort_by(f64::total_cmp);
    samples[samples.len() / 2]
}

/// Medians in milliseconds.
struct SceneTimes {
    frame_ms: f64,
    gbuffer_ms: f64,
    resolve_ms: f64,
    /// The dynamic shadow map over the frame's GPU time (all three passes).
    shadow_share: f64,
}

fn time_scene(gpu: &Arc<Gpu>, world: &World, (width, height): (u32, u32)) -> SceneTimes {
    let mut renderer = Renderer::new(gpu, world, width, height).expect("renderer");
    let aspect = width as f32 / height as f32;
    let mut frame_ms = Vec::with_capacity(TIMED_FRAMES);
    let mut passes: Vec<PassTimings> = Vec::with_capacity(TIMED_FRAMES);
    for index in 1..=WARM_UP_FRAMES + TIMED_FRAMES {
        let request = FrameRequest::at(
            world,
            frame_time(world, index),
            frame_time(world, index - 1),
            aspect,
            true,
        );
        let started = Instant::now();
        renderer.render(world, &request).expect("frame renders");
        if index > WARM_UP_FRAMES {
            frame_ms.push(started.elapsed().as_secs_f64() * 1e3);
            passes.extend(renderer.last_timings());
        }
    }
    let gpu_ms = |pick: fn(&PassTimings) -> f64| {
        if passes.is_empty() {
            f64::NAN
        } else {
            median(passes.iter().map(pick).collect())
        }
    };
    SceneTimes {
        frame_ms: median(frame_ms),
        gbuffer_ms: gpu_ms(|p| p.shadow_ms + p.gbuffer_ms),
        resolve_ms: gpu_ms(|p| p.resolve_ms),
        shadow_share: gpu_ms(|p| p.shadow_ms / (p.shadow_ms + p.gbuffer_ms + p.resolve_ms)),
    }
}

fn main() {
    // `cargo bench` passes `--bench`; any other argument filters scenes by name.
    let filter: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .collect();
    let scenes_dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let mut scenes: Vec<_> = std::fs::read_dir(&scenes_dir)
        .expect("scenes folder")
        .filter_map(|entry| entry.ok().map(|e| e.path()))
        .filter(|path| path.extension().is_some_and(|ext| ext == "toml"))
        .filter(|path| {
            filter.is_empty()
                || filter
                    .iter()
                    .any(|f| path.to_string_lossy().contains(f.as_str()))
        })
        .collect();
    scenes.sort();
    let gpu = Arc::new(Gpu::new(GpuOptions::default()).expect("Vulkan device"));
    println!("device: {}", gpu.device_name());
    println!(
        "medians of {TIMED_FRAMES} frames after {WARM_UP_FRAMES} warm-up frames, milliseconds\n"
    );
    println!("| scene | triangles | 360p frame | 360p G-buffer GPU | 360p resolve GPU | 720p frame | 720p G-buffer GPU | 720p resolve GPU | 720p / 360p frame | dynamic shadow map / GPU frame, 360p / 720p |");
    println!("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |");
    for scene in scenes {
        let world = World::load(&scene, None).expect("scene loads");
        let triangles = (world.static_batch.indices.len() + world.dynamic_batch.indices.len()) / 3;
        let [low, high] = SIZES.map(|size| time_scene(&gpu, &world, size));
        println!(
            "| {} | {triangles} | {:.1} | {:.1} | {:.1} | {:.1} | {:.1} | {:.1} | {:.2} | {:.1}% / {:.1}% |",
            world.description.name,
            low.frame_ms,
            low.gbuffer_ms,
            low.resolve_ms,
            high.frame_ms,
            high.gbuffer_ms,
            high.resolve_ms,
            high.frame_ms / low.frame_ms,
            100.0 * low.shadow_share,
            100.0 * high.shadow_share
        );
    }
}
