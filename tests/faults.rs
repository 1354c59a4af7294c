//! Faults an engine meets in the field. The driver running out of memory inside the plugin
//! (injected through the function table the engine hands it), a frame larger than the
//! create-time maximum, a device lacking a format feature the plugin needs, and inputs destroyed
//! once their command buffer completed: each gives a result code and leaves the context usable,
//! or fails creation cleanly, with no Vulkan object left behind and no validation message.

mod support;

use ash::vk;
use patchex::error::PatchexResult;
use patchex_harness::intercept::{Intercept, ObjectKind};
use patchex_harness::{Engine, EngineImage, EngineOptions};
use support::*;

const WIDTH: u32 = 32;
const HEIGHT: u32 = 24;

/// Submits `source` as frame `index` and extrapolates `target` into `output` in one command
/// buffer; returns both results.
fn run_frame(
    rig: &Rig,
    index: u64,
    source: &GpuFrame,
    target: &GpuFrame,
    output: &EngineImage,
) -> (PatchexResult, PatchexResult) {
    let family = rig.engine.queue_family_index;
    let mut results = (PatchexResult::Success, PatchexResult::Success);
    rig.engine.run(|cmd| {
        results.0 = rig.submit(cmd, &source.frame_desc(index, family));
        if results.0 == PatchexResult::Success {
            results.1 = rig.extrapolate(cmd, &target.extrapolate_desc(output, 0.5, family));
        }
    });
    results
}

#[test]
fn create_fails_cleanly_whichever_allocation_fails() {
    let engine = Engine::new(&EngineOptions::default()).expect("a Vulkan device");
    let intercept = Intercept::install(&engine);
    let library = open_library();
    let info = Rig::create_info_through(&engine, &intercept, WIDTH, HEIGHT);

    let context = create(&library, &info).expect("a clean create succeeds");
    let calls = intercept.creation_calls();
    assert!(
        !intercept.live().counts.is_empty(),
        "the shim sees the plugin's objects"
    );
    // SAFETY: nothing was recorded with the context.
    unsafe { (library.destroy)(context) };
    assert_eq!(intercept.live().total(), 0, "destroy frees everything");

    println!(
        "{} creation calls at create, each failed in turn",
        calls.len()
    );
    for (index, kind) in calls.into_iter().enumerate() {
        intercept.fail_creation_call(Some(index));
        let (result, message) = create(&library, &info).expect_err("the injected failure");
        assert_eq!(
            result,
            PatchexResult::ErrorOutOfMemory,
            "failing creation call {index} ({kind:?}): {message}"
        );
        assert!(
            message.starts_with("creating the "),
            "the message says what was being made: {message}"
        );
        assert_eq!(
            intercept.live(),
            Default::default(),
            "objects left behind after failing creation call {index} ({kind:?})"
        );
    }
    intercept.fail_creation_call(None);
    assert_eq!(intercept.take_errors(), Vec::<String>::new());
    engine.assert_validation_clean();
}

#[test]
fn submit_recovers_from_an_allocation_failure_and_steady_frames_allocate_nothing() {
    // An undisturbed run gives the expected output and the creation calls of the first
    // submit, the one that allocates the working images.
    let clean = Rig::intercepted(WIDTH, HEIGHT);
    let clean_intercept = clean.intercept.as_ref().expect("intercepted");
    let (source, target) = frame_pair(&clean.engine, WIDTH, HEIGHT, 1);
    let clean_output = output_image(&clean.engine, WIDTH, HEIGHT);
    let created_by_create = clean_intercept.creation_calls().len();
    run_frame(&clean, 1, &source, &target, &clean_output);
    let submit_calls = clean_intercept.creation_calls()[created_by_create..].to_vec();
    assert!(
        submit_calls.contains(&ObjectKind::Image),
        "the first submit allocates the working images: {submit_calls:?}"
    );
    let want = clean_output.read(&clean.engine, OUTPUT_LAYOUT);

    // Fail each of those calls in turn on another context.
    let rig = Rig::intercepted(WIDTH, HEIGHT);
    let intercept = rig.intercept.as_ref().expect("intercepted");
    let (source, target) = frame_pair(&rig.engine, WIDTH, HEIGHT, 1);
    let output = output_image(&rig.engine, WIDTH, HEIGHT);
    let before = intercept.live();
    let calls_before = intercept.creation_calls().len();
    for (index, kind) in submit_calls.into_iter().enumerate() {
        intercept.fail_creation_call(Some(index));
        let (submitted, _) = run_frame(&rig, 1, &source, &target, &output);
        assert_eq!(
            submitted,
            PatchexResult::ErrorOutOfMemory,
            "failing creation call {index} ({kind:?}) of the first submit: {}",
            rig.last_error()
        );
        assert_eq!(
            intercept.live(),
            before,
            "objects left behind after failing call {index} ({kind:?})"
        );
    }
    intercept.fail_creation_call(None);

    let (submitted, extrapolated) = run_frame(&rig, 1, &source, &target, &output);
    assert_eq!(
        (submitted, extrapolated),
        (PatchexResult::Success, PatchexResult::Success),
        "{}",
        rig.last_error()
    );
    let got = output.read(&rig.engine, OUTPUT_LAYOUT);
    assert!(
        same_bits(&got, &want),
        "the recovered context's output equals an undisturbed context's"
    );

    // Once the working images exist, frames of the same size create nothing.
    let settled = intercept.creation_calls().len();
    for index in 2..=4 {
        let (source, target) = frame_pair(&rig.engine, WIDTH, HEIGHT, index);
        let results = run_frame(&rig, index, &source, &target, &output);
        assert_eq!(
            results,
            (PatchexResult::Success, PatchexResult::Success),
            "{}",
            rig.last_error()
        );
    }
    assert_eq!(
        intercept.creation_calls()[settled..],
        [],
        "steady frames allocate nothing"
    );
    assert!(settled > calls_before);
    assert_eq!(intercept.take_errors(), Vec::<String>::new());
}

#[test]
fn frames_beyond_the_maximum_are_refused_and_resizing_within_it_frees_the_old_images() {
    let rig = Rig::intercepted(WIDTH, HEIGHT);
    let intercept = rig.intercept.as_ref().expect("intercepted");
    let images = || intercept.live().counts.get(&ObjectKind::Image).copied();
    let images_after_create = images();

    let (source, target) = frame_pair(&rig.engine, WIDTH + 8, HEIGHT, 1);
    let output = output_image(&rig.engine, WIDTH + 8, HEIGHT);
    let (submitted, _) = run_frame(&rig, 1, &source, &target, &output);
    assert_eq!(submitted, PatchexResult::ErrorExtentTooLarge);
    assert!(
        rig.last_error().contains(&format!("{WIDTH}")),
        "{}",
        rig.last_error()
    );
    assert_eq!(
        images(),
        images_after_create,
        "a refused frame allocates nothing"
    );

    // Half size, then full size (the working images grow), then half again (they stay).
    let mut frame_index = 1;
    let mut one_working_set = None;
    for (width, height) in [
        (WIDTH / 2, HEIGHT / 2),
        (WIDTH, HEIGHT),
        (WIDTH / 2, HEIGHT / 2),
    ] {
        let (source, target) = frame_pair(&rig.engine, width, height, frame_index);
        let output = output_image(&rig.engine, width, height);
        for _ in 0..3 {
            let results = run_frame(&rig, frame_index, &source, &target, &output);
            assert_eq!(
                results,
                (PatchexResult::Success, PatchexResult::Success),
                "{width}x{height}: {}",
                rig.last_error()
            );
            frame_index += 1;
        }
        one_working_set.get_or_insert(images());
    }
    // The images outgrown at the resize were freed once their frames left the ring.
    assert_eq!(images(), one_working_set.flatten());
    assert_eq!(intercept.take_errors(), Vec::<String>::new());
}

#[test]
fn a_device_without_storage_for_half_floats_is_refused_at_create() {
    let engine = Engine::new(&EngineOptions::default()).expect("a Vulkan device");
    let intercept = Intercept::install(&engine);
    intercept.hide_format_features(
        vk::Format::R16G16B16A16_SFLOAT,
        vk::FormatFeatureFlags::STORAGE_IMAGE,
    );
    let library = open_library();
    let info = Rig::create_info_through(&engine, &intercept, WIDTH, HEIGHT);
    let (result, message) = create(&library, &info).expect_err("refused");
    assert_eq!(
        result,
        PatchexResult::ErrorMissingDeviceFeature,
        "{message}"
    );
    assert!(message.contains("R16G16B16A16_SFLOAT"), "{message}");
    assert_eq!(intercept.live(), Default::default());
    engine.assert_validation_clean();
}

#[test]
fn inputs_may_be_destroyed_once_their_command_buffer_completed() {
    let rig = Rig::new(WIDTH, HEIGHT);
    let family = rig.engine.queue_family_index;
    let output = output_image(&rig.engine, WIDTH, HEIGHT);
    let (source, target) = frame_pair(&rig.engine, WIDTH, HEIGHT, 1);
    run_frame(&rig, 1, &source, &target, &output);
    let want = output.read(&rig.engine, OUTPUT_LAYOUT);

    // Submit frame t in one command buffer, destroy its images, extrapolate in another.
    let (source, _) = frame_pair(&rig.engine, WIDTH, HEIGHT, 1);
    rig.engine.run(|cmd| {
        assert_eq!(
            rig.submit(cmd, &source.frame_desc(2, family)),
            PatchexResult::Success
        );
    });
    drop(source);
    rig.engine.run(|cmd| {
        assert_eq!(
            rig.extrapolate(cmd, &target.extrapolate_desc(&output, 0.5, family)),
            PatchexResult::Success
        );
    });
    let got = output.read(&rig.engine, OUTPUT_LAYOUT);
    assert!(
        same_bits(&got, &want),
        "the extrapolation does not depend on the destroyed inputs"
    );
}
