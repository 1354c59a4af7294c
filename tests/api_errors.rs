//! Every bad input the C ABI can be handed returns its own result code and a message, records
//! nothing, and leaves the context working: each test follows the rejected call with a valid
//! frame in the same command buffer, and the rig fails on any validation message.

mod support;

use std::ffi::{c_char, c_void, CStr};
use std::ptr;

use ash::vk;
use glam::Vec2;
use patchex::abi::*;
use patchex::error::PatchexResult;
use patchex::loader::PatchexLibrary;
use patchex_harness::{Engine, EngineOptions};
use support::scene::Scene;
use support::*;

const WIDTH: u32 = 32;
const HEIGHT: u32 = 24;

struct Case {
    source: GpuFrame,
    target: GpuFrame,
    output: patchex_harness::EngineImage,
    /// Last: its engine must outlive the images above.
    rig: Rig,
}

impl Case {
    fn new() -> Self {
        let scene = Scene::new(WIDTH as usize, HEIGHT as usize);
        let rig = Rig::new(WIDTH, HEIGHT);
        let source = GpuFrame::upload(&rig.engine, &scene.render(0.0, Vec2::ZERO, -0.03));
        let target = GpuFrame::upload(&rig.engine, &scene.render(0.015, Vec2::ZERO, 0.0));
        let output = output_image(&rig.engine, WIDTH, HEIGHT);
        Self {
            rig,
            source,
            target,
            output,
        }
    }

    fn family(&self) -> u32 {
        self.rig.engine.queue_family_index
    }

    fn frame(&self, index: u64) -> PatchexFrameDesc {
        self.source.frame_desc(index, self.family())
    }

    fn target(&self) -> PatchexExtrapolateDesc {
        self.target
            .extrapolate_desc(&self.output, 0.5, self.family())
    }

    fn expect(&self, got: PatchexResult, want: PatchexResult) {
        assert_eq!(got, want, "message: {}", self.rig.last_error());
        let message = self.rig.last_error();
        assert!(!message.is_empty(), "{want:?} comes with a message");
        println!("{want:?}: {message}");
    }

    /// A valid frame and extrapolation after the rejected call: the context still works.
    fn still_works(&self, cmd: vk::CommandBuffer, frame_index: u64) {
        assert_eq!(
            self.rig.submit(cmd, &self.frame(frame_index)),
            PatchexResult::Success,
            "{}",
            self.rig.last_error()
        );
        assert_eq!(
            self.rig.extrapolate(cmd, &self.target()),
            PatchexResult::Success,
            "{}",
            self.rig.last_error()
        );
        assert!(
            self.rig.last_error().is_empty(),
            "success clears the last error"
        );
    }
}

fn rejected_submit(want: PatchexResult, break_it: impl FnOnce(&mut PatchexFrameDesc)) {
    let case = Case::new();
    let mut desc = case.frame(1);
    break_it(&mut desc);
    case.rig.engine.run(|cmd| {
        case.expect(case.rig.submit(cmd, &desc), want);
        case.still_works(cmd, 1);
    });
    let (result, stats) = case.rig.stats(1);
    assert_eq!(result, PatchexResult::Success);
    assert_eq!(stats.extrapolation_count, 1);
}

fn rejected_extrapolate(want: PatchexResult, break_it: impl FnOnce(&mut PatchexExtrapolateDesc)) {
    let case = Case::new();
    let mut desc = case.target();
    break_it(&mut desc);
    case.rig.engine.run(|cmd| {
        assert_eq!(case.rig.submit(cmd, &case.frame(1)), PatchexResult::Success);
        case.expect(case.rig.extrapolate(cmd, &desc), want);
        assert_eq!(
            case.rig.extrapolate(cmd, &case.target()),
            PatchexResult::Success
        );
        case.still_works(cmd, 2);
    });
}

#[test]
fn submit_with_wrong_struct_type() {
    rejected_submit(PatchexResult::ErrorInvalidStructType, |d| {
        d.header.struct_type = PATCHEX_STRUCT_TYPE_CREATE_INFO
    });
}

#[test]
fn submit_with_struct_from_an_older_smaller_version() {
    rejected_submit(PatchexResult::ErrorStructVersion, |d| {
        d.header.struct_size = 16
    });
}

#[test]
fn submit_with_unknown_chained_struct() {
    let unknown = PatchexStructHeader {
        struct_type: 999,
        struct_size: 16,
        next: ptr::null(),
    };
    rejected_submit(PatchexResult::ErrorInvalidStructType, |d| {
        d.header.next = &unknown as *const PatchexStructHeader as *const c_void
    });
}

#[test]
fn submit_with_unsupported_color_format() {
    rejected_submit(PatchexResult::ErrorUnsupportedFormat, |d| {
        d.color.format = vk::Format::R8_UINT
    });
}

#[test]
fn submit_with_depth_lacking_sampled_usage() {
    rejected_submit(PatchexResult::ErrorMissingImageUsage, |d| {
        d.geometry.depth.usage = vk::ImageUsageFlags::TRANSFER_SRC
    });
}

#[test]
fn submit_with_image_in_undefined_layout() {
    rejected_submit(PatchexResult::ErrorInvalidLayout, |d| {
        d.base_color.layout = vk::ImageLayout::UNDEFINED
    });
}

#[test]
fn submit_with_a_depth_stencil_layout_for_a_colour_image() {
    rejected_submit(PatchexResult::ErrorInvalidLayout, |d| {
        d.color.layout = vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL
    });
}

#[test]
fn submit_with_a_colour_layout_for_an_image_without_colour_attachment_usage() {
    rejected_submit(PatchexResult::ErrorInvalidLayout, |d| {
        d.base_color.layout = vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL
    });
}

#[test]
fn submit_with_a_stencil_only_layout_for_a_colour_image() {
    rejected_submit(PatchexResult::ErrorInvalidLayout, |d| {
        d.geometry.depth.layout = vk::ImageLayout::STENCIL_READ_ONLY_OPTIMAL
    });
}

#[test]
fn submit_with_image_smaller_than_the_frame() {
    rejected_submit(PatchexResult::ErrorMismatchedExtent, |d| {
        d.geometry.normal.width = WIDTH - 1
    });
}

#[test]
fn submit_larger_than_the_maximum_extent() {
    rejected_submit(PatchexResult::ErrorExtentTooLarge, |d| d.width = WIDTH + 1);
}

#[test]
fn submit_with_empty_extent() {
    rejected_submit(PatchexResult::ErrorInvalidArgument, |d| d.height = 0);
}

#[test]
fn submit_on_another_queue_family() {
    rejected_submit(PatchexResult::ErrorWrongQueueFamily, |d| {
        d.queue_family_index += 1
    });
}

#[test]
fn submit_without_required_depth() {
    rejected_submit(PatchexResult::ErrorNullPointer, |d| {
        d.geometry.depth.image = vk::Image::null()
    });
}

#[test]
fn submit_with_image_but_no_view() {
    rejected_submit(PatchexResult::ErrorNullPointer, |d| {
        d.color.view = vk::ImageView::null()
    });
}

#[test]
fn submit_with_reset_flag_not_a_bool() {
    rejected_submit(PatchexResult::ErrorInvalidArgument, |d| d.reset = 2);
}

#[test]
fn submit_with_nan_in_the_camera() {
    rejected_submit(PatchexResult::ErrorInvalidArgument, |d| {
        d.geometry.camera.view[5] = f32::NAN
    });
}

#[test]
fn submit_with_singular_projection() {
    rejected_submit(PatchexResult::ErrorInvalidArgument, |d| {
        d.geometry.camera.projection = [0.0; 16]
    });
}

#[test]
fn submit_with_unknown_depth_convention() {
    rejected_submit(PatchexResult::ErrorInvalidArgument, |d| {
        d.geometry.camera.depth_convention = 7
    });
}

#[test]
fn submit_with_one_image_in_two_layouts() {
    rejected_submit(PatchexResult::ErrorInvalidLayout, |d| {
        d.base_color = d.color;
        d.base_color.layout = vk::ImageLayout::GENERAL;
    });
}

#[test]
fn extrapolate_with_alpha_outside_its_range() {
    rejected_extrapolate(PatchexResult::ErrorInvalidArgument, |d| d.alpha = 0.0);
    rejected_extrapolate(PatchexResult::ErrorInvalidArgument, |d| d.alpha = f32::NAN);
    rejected_extrapolate(PatchexResult::ErrorInvalidArgument, |d| d.alpha = 1.5);
}

#[test]
fn extrapolate_with_extent_other_than_the_submitted_frame() {
    rejected_extrapolate(PatchexResult::ErrorMismatchedExtent, |d| {
        d.width = WIDTH - 2
    });
}

#[test]
fn extrapolate_without_motion_vectors() {
    rejected_extrapolate(PatchexResult::ErrorNullPointer, |d| {
        d.geometry.motion_vectors.image = vk::Image::null()
    });
}

#[test]
fn extrapolate_into_output_without_storage_usage() {
    rejected_extrapolate(PatchexResult::ErrorMissingImageUsage, |d| {
        d.output.usage = vk::ImageUsageFlags::SAMPLED
    });
}

#[test]
fn extrapolate_into_unsupported_output_format() {
    rejected_extrapolate(PatchexResult::ErrorUnsupportedFormat, |d| {
        d.output.format = vk::Format::R16G16_SFLOAT
    });
}

/// Outputs in formats a shader cannot store are written by a blit, which needs TRANSFER_DST.
#[test]
fn extrapolate_into_blitted_output_without_transfer_usage() {
    rejected_extrapolate(PatchexResult::ErrorMissingImageUsage, |d| {
        d.output.format = vk::Format::B8G8R8A8_SRGB;
        d.output.usage = vk::ImageUsageFlags::STORAGE;
    });
}

#[test]
fn extrapolate_into_an_input() {
    rejected_extrapolate(PatchexResult::ErrorInvalidArgument, |d| {
        d.output.image = d.base_color.image;
    });
}

#[test]
fn extrapolate_on_another_queue_family() {
    rejected_extrapolate(PatchexResult::ErrorWrongQueueFamily, |d| {
        d.queue_family_index = 77
    });
}

#[test]
fn extrapolate_with_invalid_warp_settings() {
    let settings = PatchexWarpSettings {
        header: PatchexStructHeader::of::<PatchexWarpSettings>(PATCHEX_STRUCT_TYPE_WARP_SETTINGS),
        kind: PATCHEX_WARP_GBUFFER_GUIDED,
        kernel_radius: 9,
        sigma_spatial: 1.0,
        sigma_depth: 0.05,
        sigma_normal: 0.1,
        sigma_position: 0.02,
        occlusion_search_radius: 8,
        hole_fill: PATCHEX_HOLE_FILL_BACKGROUND,
        resample: PATCHEX_RESAMPLE_CATMULL_ROM,
    };
    rejected_extrapolate(PatchexResult::ErrorInvalidArgument, |d| {
        d.header.next = &settings as *const PatchexWarpSettings as *const c_void
    });
    let negative = PatchexWarpSettings {
        kernel_radius: 2,
        sigma_depth: -1.0,
        ..settings
    };
    rejected_extrapolate(PatchexResult::ErrorInvalidArgument, |d| {
        d.header.next = &negative as *const PatchexWarpSettings as *const c_void
    });
    for bad in [
        PatchexWarpSettings {
            kernel_radius: 1,
            kind: 9,
            ..settings
        },
        PatchexWarpSettings {
            kernel_radius: 1,
            occlusion_search_radius: 17,
            ..settings
        },
        PatchexWarpSettings {
            kernel_radius: 1,
            hole_fill: 2,
            ..settings
        },
        PatchexWarpSettings {
            kernel_radius: 1,
            resample: 2,
            ..settings
        },
    ] {
        rejected_extrapolate(PatchexResult::ErrorInvalidArgument, |d| {
            d.header.next = &bad as *const PatchexWarpSettings as *const c_void
        });
    }
}

#[test]
fn extrapolate_with_invalid_segmentation_settings() {
    for (growth_x, growth_y) in [(f32::NAN, 1.0), (1.0, -0.5), (1.0, 65.0)] {
        let settings = PatchexSegmentationSettings {
            header: PatchexStructHeader::of::<PatchexSegmentationSettings>(
                PATCHEX_STRUCT_TYPE_SEGMENTATION_SETTINGS,
            ),
            growth_x,
            growth_y,
        };
        rejected_extrapolate(PatchexResult::ErrorInvalidArgument, |d| {
            d.header.next = &settings as *const PatchexSegmentationSettings as *const c_void
        });
    }
}

#[test]
fn extrapolate_with_bad_diagnostics_image() {
    let diagnostics = |d: &PatchexExtrapolateDesc, format| PatchexDiagnostics {
        header: PatchexStructHeader::of::<PatchexDiagnostics>(PATCHEX_STRUCT_TYPE_DIAGNOSTICS),
        image: PatchexImage { format, ..d.output },
    };
    // The output image itself: one image cannot take both results.
    let mut aliased = None;
    rejected_extrapolate(PatchexResult::ErrorInvalidArgument, |d| {
        let chained = aliased.insert(diagnostics(d, d.output.format));
        d.header.next = chained as *const PatchexDiagnostics as *const c_void
    });
    let mut wrong_format = None;
    rejected_extrapolate(PatchexResult::ErrorUnsupportedFormat, |d| {
        let chained = wrong_format.insert(diagnostics(d, vk::Format::R8G8B8A8_UNORM));
        d.header.next = chained as *const PatchexDiagnostics as *const c_void
    });
}

#[test]
fn extrapolate_with_one_extension_chained_twice() {
    let second = PatchexSegmentationSettings {
        header: PatchexStructHeader::of::<PatchexSegmentationSettings>(
            PATCHEX_STRUCT_TYPE_SEGMENTATION_SETTINGS,
        ),
        growth_x: 1.0,
        growth_y: 1.0,
    };
    let mut first = second;
    first.header.next = &second as *const PatchexSegmentationSettings as *const c_void;
    rejected_extrapolate(PatchexResult::ErrorInvalidStructType, |d| {
        d.header.next = &first as *const PatchexSegmentationSettings as *const c_void
    });
}

#[test]
fn extrapolate_before_any_submit() {
    let case = Case::new();
    case.rig.engine.run(|cmd| {
        case.expect(
            case.rig.extrapolate(cmd, &case.target()),
            PatchexResult::ErrorNoSourceFrame,
        );
        case.still_works(cmd, 1);
    });
}

#[test]
fn too_many_extrapolations_from_one_frame() {
    let case = Case::new();
    case.rig.engine.run(|cmd| {
        assert_eq!(case.rig.submit(cmd, &case.frame(1)), PatchexResult::Success);
        for _ in 0..PATCHEX_MAX_EXTRAPOLATIONS_PER_FRAME {
            assert_eq!(
                case.rig.extrapolate(cmd, &case.target()),
                PatchexResult::Success
            );
        }
        case.expect(
            case.rig.extrapolate(cmd, &case.target()),
            PatchexResult::ErrorTooManyExtrapolations,
        );
        case.still_works(cmd, 2);
    });
}

#[test]
fn frame_index_that_does_not_increase() {
    let case = Case::new();
    case.rig.engine.run(|cmd| {
        assert_eq!(case.rig.submit(cmd, &case.frame(5)), PatchexResult::Success);
        case.expect(
            case.rig.submit(cmd, &case.frame(5)),
            PatchexResult::ErrorOutOfOrder,
        );
        case.expect(
            case.rig.submit(cmd, &case.frame(4)),
            PatchexResult::ErrorOutOfOrder,
        );
        case.still_works(cmd, 6);
    });
}

#[test]
fn frame_gaps_and_reset_flags_are_reported() {
    let case = Case::new();
    // One submission per frame, waited on, as the frames-in-flight contract requires.
    for (index, reset) in [(1, 0), (2, 0), (4, 0), (5, 1)] {
        let mut desc = case.frame(index);
        desc.reset = reset;
        case.rig
            .engine
            .run(|cmd| assert_eq!(case.rig.submit(cmd, &desc), PatchexResult::Success));
    }
    // frames_in_flight is 2: frames 4 and 5 are held, earlier ones have left the ring.
    assert_eq!(case.rig.stats(4).1.reset_reason, PATCHEX_RESET_FRAME_GAP);
    assert_eq!(case.rig.stats(5).1.reset_reason, PATCHEX_RESET_REQUESTED);
    case.expect(case.rig.stats(2).0, PatchexResult::ErrorFrameNotFound);
}

/// A reset starts a new history, so it may restart the numbering (a lower or equal index); the
/// stats of a repeated index are the newest frame's.
#[test]
fn reset_restarts_the_frame_numbering() {
    let case = Case::new();
    for (index, reset) in [(10, 0), (11, 0), (3, 1), (4, 0), (4, 1)] {
        let mut desc = case.frame(index);
        desc.reset = reset;
        case.rig.engine.run(|cmd| {
            assert_eq!(
                case.rig.submit(cmd, &desc),
                PatchexResult::Success,
                "{}",
                case.rig.last_error()
            );
            assert_eq!(
                case.rig.extrapolate(cmd, &case.target()),
                PatchexResult::Success
            );
        });
    }
    let (result, stats) = case.rig.stats(4);
    assert_eq!(result, PatchexResult::Success);
    assert_eq!(
        stats.reset_reason, PATCHEX_RESET_REQUESTED,
        "the newest frame 4"
    );
    assert_eq!(stats.extrapolation_count, 1);
    // Two frames in flight: the ring holds both frames 4, and frame 3 has left it.
    case.expect(case.rig.stats(3).0, PatchexResult::ErrorFrameNotFound);
}

/// The largest index is a frame like any other; only a reset may follow it.
#[test]
fn largest_frame_index_is_followed_by_a_reset() {
    let case = Case::new();
    case.rig.engine.run(|cmd| {
        assert_eq!(
            case.rig.submit(cmd, &case.frame(u64::MAX)),
            PatchexResult::Success
        );
        assert_eq!(
            case.rig.extrapolate(cmd, &case.target()),
            PatchexResult::Success
        );
    });
    assert_eq!(case.rig.stats(u64::MAX).0, PatchexResult::Success);
    case.rig.engine.run(|cmd| {
        case.expect(
            case.rig.submit(cmd, &case.frame(0)),
            PatchexResult::ErrorOutOfOrder,
        );
        let mut restart = case.frame(0);
        restart.reset = 1;
        assert_eq!(case.rig.submit(cmd, &restart), PatchexResult::Success);
        assert_eq!(
            case.rig.extrapolate(cmd, &case.target()),
            PatchexResult::Success
        );
    });
    let (result, stats) = case.rig.stats(0);
    assert_eq!(result, PatchexResult::Success);
    assert_eq!(stats.reset_reason, PATCHEX_RESET_REQUESTED);
}

#[test]
fn stats_with_wrong_struct_type() {
    let case = Case::new();
    // SAFETY: zeroed stats are a valid bit pattern; the header is deliberately wrong.
    let mut stats: PatchexFrameStats = unsafe { std::mem::zeroed() };
    stats.header = PatchexStructHeader::of::<PatchexFrameStats>(PATCHEX_STRUCT_TYPE_FRAME_DESC);
    // SAFETY: live context and writable stats.
    let result = unsafe { (case.rig.library.get_frame_stats)(case.rig.context, 1, &mut stats) };
    case.expect(result, PatchexResult::ErrorInvalidStructType);
}

#[test]
fn null_pointers_on_every_call() {
    let case = Case::new();
    let library = &case.rig.library;
    let desc = case.frame(1);
    let target = case.target();
    // SAFETY: every call is given a null where the ABI promises to check for one.
    unsafe {
        assert_eq!(
            (library.submit_gbuffers)(ptr::null_mut(), vk::CommandBuffer::null(), &desc),
            PatchexResult::ErrorNullPointer
        );
        assert!(!library.last_error_message(ptr::null()).is_empty());
        case.rig.engine.run(|cmd| {
            case.expect(
                (library.submit_gbuffers)(case.rig.context, vk::CommandBuffer::null(), &desc),
                PatchexResult::ErrorNullPointer,
            );
            case.expect(
                (library.submit_gbuffers)(case.rig.context, cmd, ptr::null()),
                PatchexResult::ErrorNullPointer,
            );
            case.expect(
                (library.extrapolate)(case.rig.context, cmd, ptr::null()),
                PatchexResult::ErrorNullPointer,
            );
            case.expect(
                (library.extrapolate)(case.rig.context, vk::CommandBuffer::null(), &target),
                PatchexResult::ErrorNullPointer,
            );
            case.expect(
                (library.get_frame_stats)(case.rig.context, 1, ptr::null_mut()),
                PatchexResult::ErrorNullPointer,
            );
            case.still_works(cmd, 1);
        });
        (library.destroy)(ptr::null_mut());
    }
}

#[test]
fn every_result_code_has_its_own_description() {
    let case = Case::new();
    let describe = |code: i32| {
        // SAFETY: result_string returns a static string for any value.
        unsafe { CStr::from_ptr((case.rig.library.result_string)(code)) }
            .to_string_lossy()
            .into_owned()
    };
    let mut seen = std::collections::HashSet::new();
    for code in PatchexResult::ALL {
        assert!(
            seen.insert(describe(code as i32)),
            "{code:?} shares its description"
        );
    }
    assert_eq!(describe(12345), "unknown result code");
    // SAFETY: plain call.
    assert_eq!(
        unsafe { (case.rig.library.abi_version)() },
        PATCHEX_ABI_VERSION
    );
}

// --- creation ---

unsafe extern "C" fn collect_log(
    user_data: *mut c_void,
    level: PatchexLogLevel,
    message: *const c_char,
) {
    let log = &mut *(user_data as *mut Vec<(PatchexLogLevel, String)>);
    log.push((
        level,
        CStr::from_ptr(message).to_string_lossy().into_owned(),
    ));
}

fn rejected_create(want: PatchexResult, break_it: impl FnOnce(&mut PatchexCreateInfo)) {
    let engine = Engine::new(&EngineOptions::default()).unwrap();
    // SAFETY: the library was built from this tree.
    let library =
        unsafe { PatchexLibrary::open(&PatchexLibrary::beside_current_exe().unwrap()) }.unwrap();
    let mut log: Vec<(PatchexLogLevel, String)> = Vec::new();
    let mut info = engine.create_info(WIDTH, HEIGHT);
    info.log_callback = Some(collect_log);
    info.log_user_data = &mut log as *mut _ as *mut c_void;
    break_it(&mut info);
    let mut context = ptr::null_mut();
    // SAFETY: info is readable; the case under test is what `break_it` changed.
    let result = unsafe { (library.create)(&info, &mut context) };
    // SAFETY: NULL asks for this thread's last error.
    let message = unsafe { library.last_error_message(ptr::null()) };
    assert_eq!(result, want, "{message}");
    assert!(context.is_null());
    assert!(!message.is_empty());
    if info.log_callback.is_some()
        && info.header.struct_type == PATCHEX_STRUCT_TYPE_CREATE_INFO
        && info.header.struct_size as usize >= size_of::<PatchexCreateInfo>()
    {
        assert_eq!(
            log,
            vec![(PATCHEX_LOG_ERROR, message.clone())],
            "the log callback hears the error"
        );
    }
    println!("{want:?}: {message}");
    // A good create on the same engine works afterwards.
    let good = engine.create_info(WIDTH, HEIGHT);
    // SAFETY: valid create info.
    unsafe {
        assert_eq!(
            (library.create)(&good, &mut context),
            PatchexResult::Success
        );
        (library.destroy)(context);
    }
    engine.assert_validation_clean();
}

#[test]
fn create_with_bad_arguments() {
    rejected_create(PatchexResult::ErrorInvalidStructType, |i| {
        i.header.struct_type = PATCHEX_STRUCT_TYPE_FRAME_DESC
    });
    rejected_create(PatchexResult::ErrorStructVersion, |i| {
        i.header.struct_size = 8
    });
    rejected_create(PatchexResult::ErrorNullPointer, |i| {
        i.get_instance_proc_addr = None
    });
    rejected_create(PatchexResult::ErrorNullPointer, |i| {
        i.device = vk::Device::null()
    });
    rejected_create(PatchexResult::ErrorInvalidArgument, |i| i.preset = 42);
    rejected_create(PatchexResult::ErrorInvalidArgument, |i| {
        i.frames_in_flight = 0
    });
    rejected_create(PatchexResult::ErrorInvalidArgument, |i| i.max_width = 0);
    rejected_create(PatchexResult::ErrorInvalidArgument, |i| {
        i.queue_family_index = 99
    });
}

#[test]
fn create_with_null_pointers() {
    // SAFETY: the library was built from this tree; nulls are what the ABI checks.
    unsafe {
        let library = PatchexLibrary::open(&PatchexLibrary::beside_current_exe().unwrap()).unwrap();
        let mut context = ptr::null_mut();
        assert_eq!(
            (library.create)(ptr::null(), &mut context),
            PatchexResult::ErrorNullPointer
        );
        let engine = Engine::new(&EngineOptions::default()).unwrap();
        let info = engine.create_info(WIDTH, HEIGHT);
        assert_eq!(
            (library.create)(&info, ptr::null_mut()),
            PatchexResult::ErrorNullPointer
        );
        assert!(!library.last_error_message(ptr::null()).is_empty());
    }
}
