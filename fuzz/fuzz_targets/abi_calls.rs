//! Fuzzes patchex's C entry points on a lavapipe device with validation on.
//!
//! Each input is a short sequence of calls (create, submit, extrapolate, stats, and calls with
//! null arguments) whose descriptors are built from the fuzzer's bytes: struct types and sizes,
//! chains of extension structs (cycles included), wild extents, formats, layouts, usages,
//! alpha values, settings and cameras, and engine images picked for any role. The only lies
//! told are ones the API can check: a handle is real or null; a declared format, layout or
//! size is the image's own or one the plugin must refuse; a struct type is the struct's own or
//! one no version defines. The plugin cannot tell a live handle from a dangling one, read an
//! image's true format, or know a struct's true size (see the header's contract).
//!
//! A crash, a sanitizer report, a caught panic (PATCHEX_ERROR_INTERNAL), an error without a
//! message, or any validation message is a finding.

#![no_main]

use std::ffi::{c_void, CStr};
use std::ptr;
use std::sync::Mutex;

use arbitrary::{Result, Unstructured};
use ash::vk;
use libfuzzer_sys::fuzz_target;
use patchex::abi::*;
use patchex::error::PatchexResult;
use patchex::ffi::*;
use patchex_harness::{Engine, EngineImage, EngineOptions, FrameLoop};

const WIDTH: u32 = 16;
const HEIGHT: u32 = 12;
/// The persistent context accepts frames up to this size; the pool has a larger image too.
const MAX_WIDTH: u32 = 24;
const MAX_HEIGHT: u32 = 16;
const FRAMES_IN_FLIGHT: u32 = 2;
const MAX_CALLS_PER_INPUT: usize = 6;

/// Engine images the calls pick from: (format, usage, layout it sits in, width, height).
const POOL: &[(vk::Format, vk::ImageUsageFlags, vk::ImageLayout, u32, u32)] = {
    use vk::Format as F;
    use vk::ImageLayout as L;
    const SAMPLED: vk::ImageUsageFlags = vk::ImageUsageFlags::SAMPLED;
    const STORAGE: vk::ImageUsageFlags = vk::ImageUsageFlags::STORAGE;
    &[
        (
            F::R32G32B32A32_SFLOAT,
            SAMPLED,
            L::SHADER_READ_ONLY_OPTIMAL,
            WIDTH,
            HEIGHT,
        ), // colour
        (F::R16G16B16A16_SFLOAT, SAMPLED, L::GENERAL, WIDTH, HEIGHT),
        (
            F::R8G8B8A8_UNORM,
            SAMPLED,
            L::SHADER_READ_ONLY_OPTIMAL,
            WIDTH,
            HEIGHT,
        ), // base colour
        (F::R8G8B8A8_UNORM, SAMPLED, L::GENERAL, WIDTH, HEIGHT), // material
        (
            F::R32_SFLOAT,
            SAMPLED,
            L::TRANSFER_SRC_OPTIMAL,
            WIDTH,
            HEIGHT,
        ), // depth
        (
            F::R16G16B16A16_SFLOAT,
            SAMPLED,
            L::SHADER_READ_ONLY_OPTIMAL,
            WIDTH,
            HEIGHT,
        ), // normal
        (
            F::R8_UINT,
            SAMPLED,
            L::SHADER_READ_ONLY_OPTIMAL,
            WIDTH,
            HEIGHT,
        ), // stencil
        (F::R16G16_SFLOAT, SAMPLED, L::GENERAL, WIDTH, HEIGHT),  // motion
        (
            F::R32G32_SFLOAT,
            SAMPLED,
            L::SHADER_READ_ONLY_OPTIMAL,
            WIDTH,
            HEIGHT,
        ),
        (F::R16G16B16A16_SFLOAT, STORAGE, L::GENERAL, WIDTH, HEIGHT), // output
        (
            F::R16G16B16A16_SFLOAT,
            STORAGE,
            L::TRANSFER_SRC_OPTIMAL,
            WIDTH,
            HEIGHT,
        ), // diagnostics
        (
            F::R32G32B32A32_SFLOAT,
            SAMPLED,
            L::SHADER_READ_ONLY_OPTIMAL,
            MAX_WIDTH,
            MAX_HEIGHT,
        ),
        (
            F::R16G16B16A16_SFLOAT,
            STORAGE,
            L::GENERAL,
            WIDTH / 2,
            HEIGHT / 2,
        ),
    ]
};
const COLOR: usize = 0;
const BASE_COLOR: usize = 2;
const MATERIAL: usize = 3;
const DEPTH: usize = 4;
const NORMAL: usize = 5;
const STENCIL: usize = 6;
const MOTION: usize = 7;
const OUTPUT: usize = 9;
const DIAGNOSTICS: usize = 10;

struct World {
    /// Lives as long as the process, so that the frame loop may borrow it.
    engine: &'static Engine,
    frames: Option<FrameLoop<'static>>,
    /// Inputs run so far: the frame loop's frame index.
    inputs: u64,
    pool: Vec<EngineImage>,
    context: *mut PatchexContext,
    /// Index of the next frame to submit in order.
    next_frame: u64,
    camera: PatchexCamera,
}

// SAFETY: libFuzzer calls the target from one thread; the mutex only gives the world a home.
unsafe impl Send for World {}

static WORLD: Mutex<Option<World>> = Mutex::new(None);

/// Deterministic values in a plausible range for each pool image's role.
fn fill(index: usize, format: vk::Format, width: u32, height: u32) -> Vec<f32> {
    let channels = match format {
        vk::Format::R32_SFLOAT | vk::Format::R8_UINT => 1,
        vk::Format::R16G16_SFLOAT | vk::Format::R32G32_SFLOAT => 2,
        _ => 4,
    };
    (0..(width * height) as usize * channels)
        .map(|i| {
            let hash = (i as u32 ^ (index as u32) << 20).wrapping_mul(2_654_435_761);
            let unit = (hash >> 8) as f32 / (1 << 24) as f32;
            match index {
                DEPTH => 0.95 + 0.05 * unit,
                STENCIL => (hash >> 30) as f32,
                MOTION | 8 => 6.0 * unit - 3.0,
                NORMAL => 2.0 * unit - 1.0,
                COLOR | 1 | 11 => 4.0 * unit,
                _ => unit,
            }
        })
        .collect()
}

impl World {
    fn new() -> Self {
        let engine: &'static Engine = Box::leak(Box::new(
            Engine::new(&EngineOptions {
                validation: true,
                device_name: None,
            })
            .expect("a Vulkan device (lavapipe)"),
        ));
        let pool: Vec<EngineImage> = POOL
            .iter()
            .enumerate()
            .map(|(index, &(format, usage, layout, width, height))| {
                let image = EngineImage::new(engine, format, width, height, usage);
                image.upload(engine, &fill(index, format, width, height), layout);
                image
            })
            .collect();
        // A camera 5 units back looking down -z; Vulkan clip space (y down, depth 0 to 1).
        let (near, far, focal, aspect) = (0.1f32, 100.0f32, 1.8f32, 4.0f32 / 3.0);
        let view = glam::Mat4::from_translation(glam::Vec3::new(0.0, 0.0, -5.0));
        let projection = glam::Mat4::from_cols_array(&[
            focal / aspect,
            0.0,
            0.0,
            0.0,
            0.0,
            -focal,
            0.0,
            0.0,
            0.0,
            0.0,
            far / (near - far),
            -1.0,
            0.0,
            0.0,
            near * far / (near - far),
            0.0,
        ]);
        let camera = PatchexCamera {
            view: view.to_cols_array(),
            projection: projection.to_cols_array(),
            jitter: [0.0; 2],
            near_plane: near,
            far_plane: far,
            depth_convention: PATCHEX_DEPTH_HARDWARE,
        };
        let info = PatchexCreateInfo {
            frames_in_flight: FRAMES_IN_FLIGHT,
            ..engine.create_info(MAX_WIDTH, MAX_HEIGHT)
        };
        let mut context = ptr::null_mut();
        // SAFETY: valid create info and out pointer.
        let result = unsafe { patchex_create(&info, &mut context) };
        assert_eq!(
            result,
            PatchexResult::Success,
            "{}",
            last_error(ptr::null())
        );
        engine.assert_validation_clean();
        Self {
            engine,
            frames: Some(FrameLoop::new(engine, 1)),
            inputs: 0,
            pool,
            context,
            next_frame: 1,
            camera,
        }
    }

    /// The pool image `index` as the engine truthfully describes it.
    fn describe(&self, index: usize) -> PatchexImage {
        self.pool[index].describe(POOL[index].2)
    }
}

fn last_error(context: *const PatchexContext) -> String {
    // SAFETY: context is null or live; the message is copied before any other call.
    unsafe { CStr::from_ptr(patchex_last_error(context)) }
        .to_string_lossy()
        .into_owned()
}

/// The findings every call is checked for.
fn check(result: PatchexResult, context: *const PatchexContext, call: &str) {
    assert_ne!(
        result,
        PatchexResult::ErrorInternal,
        "{call}: a panic was caught: {}",
        last_error(context)
    );
    if (result as i32) < 0 {
        assert!(
            !last_error(context).is_empty(),
            "{call} failed with {result:?} but gave no message"
        );
    }
}

/// Either `value` or, now and then, a fuzzed replacement.
fn mostly<T>(
    u: &mut Unstructured,
    value: T,
    fuzzed: impl FnOnce(&mut Unstructured) -> Result<T>,
) -> Result<T> {
    Ok(if u.ratio(1, 6)? { fuzzed(u)? } else { value })
}

/// A struct type no version of the ABI defines. A known type on the wrong struct would be an
/// uncheckable lie (it says how many bytes the plugin may read), as with Vulkan's sType.
fn unknown_struct_type(u: &mut Unstructured) -> Result<u32> {
    let struct_type: u32 = u.arbitrary()?;
    Ok(
        if (1..=PATCHEX_STRUCT_TYPE_SKY_LIGHT).contains(&struct_type) {
            0
        } else {
            struct_type
        },
    )
}

fn header(u: &mut Unstructured, struct_type: u32, size: usize) -> Result<PatchexStructHeader> {
    Ok(PatchexStructHeader {
        struct_type: mostly(u, struct_type, unknown_struct_type)?,
        struct_size: mostly(u, size as u32, |u| u.arbitrary())?,
        next: ptr::null(),
    })
}

/// A pool image for a role: usually the right one, sometimes another, null, or a described
/// field the plugin must refuse.
fn image(u: &mut Unstructured, world: &World, right: usize) -> Result<PatchexImage> {
    let mut image = match u.int_in_range(0..=9)? {
        0 => PatchexImage::default(),
        1 => world.describe(u.choose_index(POOL.len())?),
        _ => world.describe(right),
    };
    if u.ratio(1, 5)? {
        match u.int_in_range(0..=6)? {
            0 => image.view = vk::ImageView::null(),
            1 => image.image = vk::Image::null(),
            2 => image.width = u.int_in_range(0..=image.width)?,
            3 => image.height = u.int_in_range(0..=image.height)?,
            // No core format lies in this range: the plugin must refuse it.
            4 => image.format = vk::Format::from_raw(u.int_in_range(200..=1_000_000)?),
            5 => {
                image.layout = vk::ImageLayout::from_raw(
                    *u.choose(&[0, 8, 12345, -1, i32::MAX])?, // UNDEFINED, PREINITIALIZED, junk
                )
            }
            _ => image.usage &= vk::ImageUsageFlags::from_raw(u.arbitrary()?),
        }
    }
    Ok(image)
}

fn camera(u: &mut Unstructured, world: &World) -> Result<PatchexCamera> {
    let mut camera = world.camera;
    if u.ratio(1, 4)? {
        match u.int_in_range(0..=5)? {
            0 => camera.view[u.choose_index(16)?] = u.arbitrary()?,
            1 => camera.projection[u.choose_index(16)?] = u.arbitrary()?,
            2 => camera.jitter = u.arbitrary()?,
            3 => camera.near_plane = u.arbitrary()?,
            4 => camera.far_plane = u.arbitrary()?,
            _ => camera.depth_convention = u.int_in_range(0..=4)?,
        }
    }
    Ok(camera)
}

fn geometry(u: &mut Unstructured, world: &World) -> Result<PatchexGeometry> {
    Ok(PatchexGeometry {
        depth: image(u, world, DEPTH)?,
        normal: image(u, world, NORMAL)?,
        normal_encoding: mostly(u, PATCHEX_NORMAL_SIGNED, |u| u.int_in_range(0..=3))?,
        stencil: image(u, world, STENCIL)?,
        motion_vectors: image(u, world, MOTION)?,
        motion_vector_scale: mostly(u, [1.0, 1.0], |u| u.arbitrary())?,
        camera: camera(u, world)?,
    })
}

fn extent(u: &mut Unstructured) -> Result<(u32, u32)> {
    Ok(match u.int_in_range(0..=7)? {
        0 => (u.arbitrary()?, u.arbitrary()?),
        1 => (
            u.int_in_range(0..=MAX_WIDTH + 1)?,
            u.int_in_range(0..=MAX_HEIGHT + 1)?,
        ),
        _ => (WIDTH, HEIGHT),
    })
}

/// Extension structs the chain links point into; boxed so their addresses stay put.
enum Link {
    Warp(Box<PatchexWarpSettings>),
    Segmentation(Box<PatchexSegmentationSettings>),
    Diagnostics(Box<PatchexDiagnostics>),
    TargetShadows(Box<PatchexTargetShadowInput>),
    Sun(Box<PatchexSunLight>),
    Sky(Box<PatchexSkyLight>),
    Translucency(Box<PatchexTranslucencyInput>),
    Unknown(Box<PatchexStructHeader>),
}

impl Link {
    fn header(&mut self) -> &mut PatchexStructHeader {
        match self {
            Link::Warp(s) => &mut s.header,
            Link::Segmentation(s) => &mut s.header,
            Link::Diagnostics(s) => &mut s.header,
            Link::TargetShadows(s) => &mut s.header,
            Link::Sun(s) => &mut s.header,
            Link::Sky(s) => &mut s.header,
            Link::Translucency(s) => &mut s.header,
            Link::Unknown(h) => h,
        }
    }

    fn address(&self) -> *const c_void {
        match self {
            Link::Warp(s) => &**s as *const _ as *const c_void,
            Link::Segmentation(s) => &**s as *const _ as *const c_void,
            Link::Diagnostics(s) => &**s as *const _ as *const c_void,
            Link::TargetShadows(s) => &**s as *const _ as *const c_void,
            Link::Sun(s) => &**s as *const _ as *const c_void,
            Link::Sky(s) => &**s as *const _ as *const c_void,
            Link::Translucency(s) => &**s as *const _ as *const c_void,
            Link::Unknown(h) => &**h as *const _ as *const c_void,
        }
    }
}

/// A chain of 0 to 3 links (sometimes closed into a cycle); returns the links and its head.
fn chain(u: &mut Unstructured, world: &World) -> Result<(Vec<Link>, *const c_void)> {
    let mut links = Vec::new();
    for _ in 0..u.int_in_range(0..=3)? {
        let link = match u.int_in_range(0..=7)? {
            0 => Link::Warp(Box::new(PatchexWarpSettings {
                header: header(
                    u,
                    PATCHEX_STRUCT_TYPE_WARP_SETTINGS,
                    size_of::<PatchexWarpSettings>(),
                )?,
                kind: u.int_in_range(0..=3)?,
                kernel_radius: u.int_in_range(0..=4)?,
                sigma_spatial: u.arbitrary()?,
                sigma_depth: u.arbitrary()?,
                sigma_normal: u.arbitrary()?,
                sigma_position: u.arbitrary()?,
                occlusion_search_radius: u.int_in_range(0..=17)?,
                hole_fill: u.int_in_range(0..=2)?,
                resample: u.int_in_range(0..=2)?,
            })),
            1 => Link::Segmentation(Box::new(PatchexSegmentationSettings {
                header: header(
                    u,
                    PATCHEX_STRUCT_TYPE_SEGMENTATION_SETTINGS,
                    size_of::<PatchexSegmentationSettings>(),
                )?,
                growth_x: mostly(u, 2.0, |u| u.arbitrary())?,
                growth_y: mostly(u, 3.0, |u| u.arbitrary())?,
            })),
            2 => Link::Diagnostics(Box::new(PatchexDiagnostics {
                header: header(
                    u,
                    PATCHEX_STRUCT_TYPE_DIAGNOSTICS,
                    size_of::<PatchexDiagnostics>(),
                )?,
                image: image(u, world, DIAGNOSTICS)?,
            })),
            3 => Link::TargetShadows(Box::new(PatchexTargetShadowInput {
                header: header(
                    u,
                    PATCHEX_STRUCT_TYPE_TARGET_SHADOW_INPUT,
                    size_of::<PatchexTargetShadowInput>(),
                )?,
                // A depth image: R32_SFLOAT, a mask's format.
                mask: image(u, world, DEPTH)?,
            })),
            4 => Link::Sun(Box::new(PatchexSunLight {
                header: header(
                    u,
                    PATCHEX_STRUCT_TYPE_SUN_LIGHT,
                    size_of::<PatchexSunLight>(),
                )?,
                direction: mostly(u, [0.3, 0.8, 0.5], |u| u.arbitrary())?,
                illuminance: mostly(u, [3.0, 3.0, 2.8], |u| u.arbitrary())?,
                // A depth image: R32_SFLOAT, a visibility's format.
                visibility: image(u, world, DEPTH)?,
            })),
            5 => Link::Translucency(Box::new(PatchexTranslucencyInput {
                header: header(
                    u,
                    PATCHEX_STRUCT_TYPE_TRANSLUCENCY_INPUT,
                    size_of::<PatchexTranslucencyInput>(),
                )?,
                // A depth image: R32_SFLOAT, a mask's format.
                mask: image(u, world, DEPTH)?,
                motion_vectors: image(u, world, MOTION)?,
                motion_vector_scale: mostly(u, [1.0, 1.0], |u| u.arbitrary())?,
                opaque_color: image(u, world, COLOR)?,
            })),
            6 => Link::Sky(Box::new(PatchexSkyLight {
                header: header(
                    u,
                    PATCHEX_STRUCT_TYPE_SKY_LIGHT,
                    size_of::<PatchexSkyLight>(),
                )?,
                // A colour image: square or not, as the frame is.
                radiance: image(u, world, COLOR)?,
                mip_levels: u.int_in_range(0..=9)?,
            })),
            _ => Link::Unknown(Box::new(PatchexStructHeader {
                struct_type: unknown_struct_type(u)?,
                struct_size: u.arbitrary()?,
                next: ptr::null(),
            })),
        };
        links.push(link);
    }
    for i in 1..links.len() {
        let next = links[i].address();
        links[i - 1].header().next = next;
    }
    if links.len() > 1 && u.ratio(1, 8)? {
        let first = links[0].address();
        links.last_mut().unwrap().header().next = first;
    }
    let head = links.first().map_or(ptr::null(), Link::address);
    Ok((links, head))
}

fn fuzz_create(u: &mut Unstructured, world: &World) -> Result<()> {
    let mut info = world.engine.create_info(MAX_WIDTH, MAX_HEIGHT);
    info.header = header(
        u,
        PATCHEX_STRUCT_TYPE_CREATE_INFO,
        size_of::<PatchexCreateInfo>(),
    )?;
    if u.ratio(1, 4)? {
        match u.int_in_range(0..=9)? {
            0 => info.instance = vk::Instance::null(),
            1 => info.physical_device = vk::PhysicalDevice::null(),
            2 => info.device = vk::Device::null(),
            3 => info.get_instance_proc_addr = None,
            4 => info.queue_family_index = u.arbitrary()?,
            5 => info.max_width = u.arbitrary()?,
            6 => info.max_height = u.arbitrary()?,
            7 => info.frames_in_flight = u.arbitrary()?,
            8 => info.preset = u.arbitrary()?,
            _ => {
                info.get_device_proc_addr =
                    Some(world.engine.instance.fp_v1_0().get_device_proc_addr)
            }
        }
    }
    let (_links, head) = chain(u, world)?;
    info.header.next = head;
    let mut context = ptr::null_mut();
    let out: *mut *mut PatchexContext = if u.ratio(1, 16)? {
        ptr::null_mut()
    } else {
        &mut context
    };
    // SAFETY: every pointer in `info` is null or points to a live struct; handles are real or null.
    let result = unsafe { patchex_create(&info, out) };
    check(result, ptr::null(), "patchex_create");
    if result == PatchexResult::Success {
        // SAFETY: nothing was recorded with the new context.
        unsafe { patchex_destroy(context) };
    }
    Ok(())
}

/// `oldest`: the oldest frame this command buffer already holds work for, if any. The engine's
/// side of the frames-in-flight contract is that when it records frame F, everything recorded
/// for frame F - FRAMES_IN_FLIGHT has finished; within one command buffer that allows only the
/// next frame, and only while it is within FRAMES_IN_FLIGHT of `oldest`. (Runs that broke this,
/// with frames 5 and 7, or an extrapolation from 5 followed by frame 7, in one command buffer,
/// had the validation layer catch the harness, not the plugin.) Returns the submitted index.
fn fuzz_submit(
    u: &mut Unstructured,
    world: &mut World,
    cmd: vk::CommandBuffer,
    oldest: Option<u64>,
) -> Result<Option<u64>> {
    let frame_index = match oldest {
        Some(oldest) if world.next_frame >= oldest.saturating_add(u64::from(FRAMES_IN_FLIGHT)) => {
            return Ok(None)
        }
        Some(_) => world.next_frame,
        None => mostly(u, world.next_frame, |u| u.arbitrary())?,
    };
    let (width, height) = extent(u)?;
    let desc = PatchexFrameDesc {
        header: header(
            u,
            PATCHEX_STRUCT_TYPE_FRAME_DESC,
            size_of::<PatchexFrameDesc>(),
        )?,
        frame_index,
        reset: mostly(u, 0, |u| u.int_in_range(0..=2))?,
        queue_family_index: mostly(u, world.engine.queue_family_index, |u| u.arbitrary())?,
        width,
        height,
        color: image(u, world, COLOR)?,
        base_color: image(u, world, BASE_COLOR)?,
        material: image(u, world, MATERIAL)?,
        geometry: geometry(u, world)?,
    };
    let (_links, head) = chain(u, world)?;
    let desc = PatchexFrameDesc {
        header: PatchexStructHeader {
            next: head,
            ..desc.header
        },
        ..desc
    };
    // SAFETY: the context is live, cmd is recording, and every image in desc is a live pool image.
    let result = unsafe { patchex_submit_gbuffers(world.context, cmd, &desc) };
    check(result, world.context, "patchex_submit_gbuffers");
    if result != PatchexResult::Success {
        return Ok(None);
    }
    world.next_frame = frame_index.saturating_add(1);
    Ok(Some(frame_index))
}

/// Returns the frame extrapolated from, when the call recorded something.
fn fuzz_extrapolate(
    u: &mut Unstructured,
    world: &World,
    cmd: vk::CommandBuffer,
) -> Result<Option<u64>> {
    let (width, height) = extent(u)?;
    let (_links, head) = chain(u, world)?;
    let mut header = header(
        u,
        PATCHEX_STRUCT_TYPE_EXTRAPOLATE_DESC,
        size_of::<PatchexExtrapolateDesc>(),
    )?;
    header.next = head;
    let desc = PatchexExtrapolateDesc {
        header,
        queue_family_index: mostly(u, world.engine.queue_family_index, |u| u.arbitrary())?,
        alpha: mostly(u, 0.5, |u| u.arbitrary())?,
        width,
        height,
        base_color: image(u, world, BASE_COLOR)?,
        material: image(u, world, MATERIAL)?,
        geometry: geometry(u, world)?,
        output: image(u, world, OUTPUT)?,
    };
    // SAFETY: as for the submit.
    let result = unsafe { patchex_extrapolate(world.context, cmd, &desc) };
    check(result, world.context, "patchex_extrapolate");
    Ok(((result as i32) >= 0).then(|| world.next_frame - 1))
}

fn fuzz_stats(u: &mut Unstructured, world: &World) -> Result<()> {
    // SAFETY: a zeroed PatchexFrameStats is a valid bit pattern.
    let mut stats: PatchexFrameStats = unsafe { std::mem::zeroed() };
    stats.header = header(
        u,
        PATCHEX_STRUCT_TYPE_FRAME_STATS,
        size_of::<PatchexFrameStats>(),
    )?;
    let frame_index = mostly(u, world.next_frame.saturating_sub(1), |u| u.arbitrary())?;
    // SAFETY: live context, writable stats.
    let result = unsafe { patchex_get_frame_stats(world.context, frame_index, &mut stats) };
    check(result, world.context, "patchex_get_frame_stats");
    Ok(())
}

/// Calls with a null context or descriptor: each must fail cleanly.
fn fuzz_nulls(u: &mut Unstructured, world: &World, cmd: vk::CommandBuffer) -> Result<()> {
    let context = if u.arbitrary()? {
        ptr::null_mut()
    } else {
        world.context
    };
    let cmd = if u.arbitrary()? {
        vk::CommandBuffer::null()
    } else {
        cmd
    };
    // SAFETY: null descriptors are checked before anything is read or recorded.
    let result = unsafe {
        match u.int_in_range(0..=2)? {
            0 => patchex_submit_gbuffers(context, cmd, ptr::null()),
            1 => patchex_extrapolate(context, cmd, ptr::null()),
            _ => patchex_get_frame_stats(context, 0, ptr::null_mut()),
        }
    };
    assert!((result as i32) < 0, "a null argument was accepted");
    check(result, context, "a call with null arguments");
    Ok(())
}

fn run(u: &mut Unstructured, world: &mut World) -> Result<()> {
    // The oldest frame this command buffer holds work for (see fuzz_submit).
    let mut oldest: Option<u64> = None;
    let mut outcome = Ok(());
    // One reused command buffer and fence, as a render loop has: allocating them per input
    // grows the validation layer's bookkeeping without end.
    let mut frames = world.frames.take().expect("the world's frame loop");
    world.inputs += 1;
    frames.frame(world.inputs, |cmd| {
        outcome = (|| -> Result<()> {
            for _ in 0..MAX_CALLS_PER_INPUT {
                if u.is_empty() {
                    break;
                }
                match u.int_in_range(0..=5)? {
                    0 => fuzz_create(u, world)?,
                    1 | 2 => {
                        if let Some(frame) = fuzz_submit(u, world, cmd, oldest)? {
                            oldest.get_or_insert(frame);
                        }
                    }
                    3 => {
                        if let Some(frame) = fuzz_extrapolate(u, world, cmd)? {
                            oldest.get_or_insert(frame);
                        }
                    }
                    4 => fuzz_stats(u, world)?,
                    _ => fuzz_nulls(u, world, cmd)?,
                }
            }
            Ok(())
        })();
    });
    // Executing what was recorded lets validation check the GPU side too.
    frames.wait(world.inputs);
    world.frames = Some(frames);
    let messages = world.engine.take_validation_messages();
    assert!(messages.is_empty(), "validation:\n{}", messages.join("\n"));
    outcome
}

fuzz_target!(
    init: {
        // Made before the first input, so that the driver's start-up is not taken for a leak.
        *WORLD.lock().unwrap() = Some(World::new());
    },
    |data: &[u8]| {
        let mut guard = WORLD.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
        let world = guard.as_mut().expect("made at init");
        let _ = run(&mut Unstructured::new(data), world);
    }
);
