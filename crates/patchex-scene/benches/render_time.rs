//! Render time per frame for every scene under `scenes/` at 360p and 720p.
//!
//! `cargo bench -p patchex-scene --bench render_time [-- FILTER]` prints a Markdown table.
//! A frame is everything `Renderer::render` does: posing and skinning the characters on the
//! CPU, the dynamic shadow map, the G-buffer and resolve passes, and reading all layers back
//! (EXR encoding is not included). Validation is off; the median of the timed frames is shown.

use patchex_scene::dataset::frame_time;
use patchex_scene::{FrameRequest, Gpu, GpuOptions, Renderer, World};
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

const SIZES: [(u32, u32); 2] = [(640, 360), (1280, 720)];
const WARM_UP_FRAMES: usize = 2;
const TIMED_FRAMES: usize = 8;

fn median_ms(mut samples: Vec<f64>) -> f64 {
    samples.sort_by(f64::total_cmp);
    samples[samples.len() / 2] * 1e3
}

fn time_scene(gpu: &Arc<Gpu>, world: &World, (width, height): (u32, u32)) -> f64 {
    let mut renderer = Renderer::new(gpu, world, width, height).expect("renderer");
    let aspect = width as f32 / height as f32;
    let mut samples = Vec::with_capacity(TIMED_FRAMES);
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
            samples.push(started.elapsed().as_secs_f64());
        }
    }
    median_ms(samples)
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
    println!("median of {TIMED_FRAMES} frames after {WARM_UP_FRAMES} warm-up frames\n");
    println!("| scene | triangles | 640x360 ms/frame | 1280x720 ms/frame | 720p / 360p |");
    println!("| --- | --- | --- | --- | --- |");
    for scene in scenes {
        let world = World::load(&scene, None).expect("scene loads");
        let triangles = (world.static_batch.indices.len() + world.dynamic_batch.indices.len()) / 3;
        let times: Vec<f64> = SIZES
            .iter()
            .map(|&size| time_scene(&gpu, &world, size))
            .collect();
        println!(
            "| {} | {triangles} | {:.1} | {:.1} | {:.2} |",
            world.description.name,
            times[0],
            times[1],
            times[1] / times[0]
        );
    }
}
