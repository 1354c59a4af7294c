//! Several contexts on several threads at once, under validation, in the two ways an engine
//! runs them: each thread with its own instance and device, or every thread with its own
//! context and command pool on one shared device and queue. Every output must equal a
//! single-threaded run's, bit for bit: contexts share nothing but the library's code and, on
//! one device, its compiled pipelines.

mod support;

use patchex::error::PatchexResult;
use patchex_harness::intercept::{Intercept, ObjectKind};
use patchex_harness::{Engine, EngineImage, EngineOptions};
use support::*;

const WIDTH: usize = 64;
const HEIGHT: usize = 48;
const THREADS: usize = 3;
const FRAMES: u64 = 4;

/// Extrapolates FRAMES frames of the moving sphere on a fresh engine and context; returns each
/// output image's values.
fn run_sequence() -> Vec<Vec<f32>> {
    let rig = Rig::new(WIDTH as u32, HEIGHT as u32);
    let engine = &rig.engine;
    let family = engine.queue_family_index;
    let output = output_image(engine, WIDTH as u32, HEIGHT as u32);
    (1..=FRAMES)
        .map(|frame_index| {
            let (source, target) = frame_pair(engine, WIDTH as u32, HEIGHT as u32, frame_index);
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
            assert!(
                same_bits(got, want),
                "thread {thread}, frame {frame}: output differs"
            );
        }
    }
}

#[test]
fn contexts_on_several_threads_of_one_device_match_a_single_threaded_run() {
    let alone = run_sequence();
    let engine = Engine::new(&EngineOptions::default()).expect("a Vulkan device");
    let intercept = Intercept::install(&engine);
    let library = open_library();
    let family = engine.queue_family_index;
    // The engine's thread uploads every frame and makes each thread's outputs.
    let frames: Vec<(GpuFrame, GpuFrame)> = (1..=FRAMES)
        .map(|index| frame_pair(&engine, WIDTH as u32, HEIGHT as u32, index))
        .collect();
    let outputs: Vec<Vec<EngineImage>> = (0..THREADS)
        .map(|_| {
            (0..FRAMES)
                .map(|_| output_image(&engine, WIDTH as u32, HEIGHT as u32))
                .collect()
        })
        .collect();

    // Pipelines are shared among the contexts alive at once; this one outlives the threads',
    // so a thread done before another starts cannot take them with it.
    let keeper = create(
        &library,
        &Rig::create_info_through(&engine, &intercept, WIDTH as u32, HEIGHT as u32),
    )
    .unwrap_or_else(|(_, message)| panic!("{message}"));
    std::thread::scope(|scope| {
        for thread_outputs in &outputs {
            let (engine, library, intercept, frames) = (&engine, &library, &intercept, &frames);
            scope.spawn(move || {
                let info = Rig::create_info_through(engine, intercept, WIDTH as u32, HEIGHT as u32);
                let context =
                    create(library, &info).unwrap_or_else(|(_, message)| panic!("{message}"));
                let pool = engine.thread_pool();
                for (frame, ((source, target), output)) in
                    frames.iter().zip(thread_outputs).enumerate()
                {
                    pool.run(|cmd| {
                        // SAFETY: live context, recording command buffer, live images.
                        let results = unsafe {
                            (
                                (library.submit_gbuffers)(
                                    context,
                                    cmd,
                                    &source.frame_desc(frame as u64 + 1, family),
                                ),
                                (library.extrapolate)(
                                    context,
                                    cmd,
                                    &target.extrapolate_desc(output, 0.5, family),
                                ),
                            )
                        };
                        assert_eq!(results, (PatchexResult::Success, PatchexResult::Success));
                    });
                }
                // SAFETY: every submission was waited on.
                unsafe { (library.destroy)(context) };
            });
        }
    });

    // SAFETY: the keeper recorded nothing.
    unsafe { (library.destroy)(keeper) };

    for (thread, thread_outputs) in outputs.iter().enumerate() {
        for (frame, output) in thread_outputs.iter().enumerate() {
            let got = output.read(&engine, OUTPUT_LAYOUT);
            assert!(
                same_bits(&got, &alone[frame]),
                "thread {thread}, frame {frame}: output differs"
            );
        }
    }
    let pipelines_compiled = intercept
        .creation_calls()
        .iter()
        .filter(|&&kind| kind == ObjectKind::Pipeline)
        .count();
    assert!(
        pipelines_compiled <= patchex::passes::Pipelines::COUNT,
        "the contexts of one device share one set of pipelines ({pipelines_compiled} compiled)"
    );
    assert_eq!(
        intercept.live(),
        Default::default(),
        "every context freed everything"
    );
    engine.assert_validation_clean();
}
