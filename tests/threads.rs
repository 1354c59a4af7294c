//! Several contexts on several threads at once: each thread plays its own engine (instance,
//! device, queue, command buffers, fences) with its own patchex context, all extrapolating the
//! same frames concurrently under validation. Every output must equal a single-threaded run's,
//! bit for bit: contexts share nothing but the library's code.

mod support;

use glam::Vec2;
use patchex::error::PatchexResult;
use support::scene::Scene;
use support::*;

const WIDTH: usize = 64;
const HEIGHT: usize = 48;
const THREADS: usize = 3;
const FRAMES: u64 = 4;

/// Extrapolates FRAMES frames of the moving sphere on a fresh engine and context; returns each
/// output image's values.
fn run_sequence() -> Vec<Vec<f32>> {
    let scene = Scene::new(WIDTH, HEIGHT);
    let rig = Rig::new(WIDTH as u32, HEIGHT as u32);
    let engine = &rig.engine;
    let family = engine.queue_family_index;
    let output = output_image(engine, WIDTH as u32, HEIGHT as u32);
    (1..=FRAMES)
        .map(|frame_index| {
            let time = frame_index as f32 / 30.0;
            let source =
                GpuFrame::upload(engine, &scene.render(time, Vec2::ZERO, time - 1.0 / 30.0));
            let target =
                GpuFrame::upload(engine, &scene.render(time + 1.0 / 60.0, Vec2::ZERO, time));
            engine.run(|cmd| {
                assert_eq!(
                    rig.submit(cmd, &source.frame_desc(frame_index, family)),
                    PatchexResult::Success,
                    "{}",
                    rig.last_error()
                );
                assert_eq!(
                    rig.extrapolate(cmd, &target.extrapolate_desc(&output, 0.5, family)),
                    PatchexResult::Success,
                    "{}",
                    rig.last_error()
                );
            });
            output.read(engine, OUTPUT_LAYOUT)
        })
        .collect()
}

#[test]
fn contexts_on_several_threads_match_a_single_threaded_run() {
    let alone = run_sequence();
    assert_ne!(
        alone[0], alone[1],
        "the sphere moves: each frame has its own output"
    );
    let together: Vec<Vec<Vec<f32>>> = std::thread::scope(|scope| {
        let runs: Vec<_> = (0..THREADS).map(|_| scope.spawn(run_sequence)).collect();
        runs.into_iter()
            .map(|run| run.join().expect("the thread's run succeeds"))
            .collect()
    });
    for (thread, outputs) in together.iter().enumerate() {
        for (frame, (got, want)) in outputs.iter().zip(&alone).enumerate() {
            let same_bits = got
                .iter()
                .zip(want)
                .all(|(a, b)| a.to_bits() == b.to_bits());
            assert!(same_bits, "thread {thread}, frame {frame}: output differs");
        }
    }
}
