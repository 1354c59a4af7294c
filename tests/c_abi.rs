//! The whole C ABI from plain C11 (tests/c/abi_test.c): compiled against the installed header
//! with -std=c11 -Wall -Wextra -pedantic -Werror and `near`/`far` defined as empty macros (as
//! <windows.h> defines them), linked through pkg-config, run on rendered frames under validation
//! with synchronization validation. It uses every chained struct; its outputs and statistics
//! must equal, bit for bit, those of the same calls made through the Rust path.

mod support;

use std::ffi::{c_void, CString};
use std::path::{Path, PathBuf};
use std::process::Command;

use ash::vk;
use patchex::abi::*;
use patchex::error::PatchexResult;
use patchex::passes::warp::WarpSettings;
use patchex::reference::Image;
use patchex_harness::texel::decode;
use patchex_harness::EngineImage;
use support::rendered::render;
use support::scene::Frame;
use support::*;

const WIDTH: u32 = 96;
const HEIGHT: u32 = 54;
/// Texels a side of the sky's octahedral map: another size than the frame's.
const SKY_SIDE: usize = 24;

fn bytes_of<T: Copy>(value: &T) -> &[u8] {
    // SAFETY: a plain-old-data value viewed as its bytes.
    unsafe { std::slice::from_raw_parts((value as *const T).cast(), size_of::<T>()) }
}

/// One frame as abi_test.c reads it (see its header comment).
fn write_frame(frame: &Frame, path: &Path) {
    let mut bytes = bytes_of(&frame.camera).to_vec();
    let floats = [
        &frame.color,
        &frame.base_color,
        &frame.material,
        &frame.normal,
        &frame.color_without_dynamic_shadows,
        &frame.depth,
        &frame.shadow_mask,
        &frame.static_visibility,
        &frame.motion,
    ];
    for image in floats {
        bytes.extend(image.data.iter().flat_map(|v| v.to_ne_bytes()));
    }
    bytes.extend(frame.stencil.data.iter().map(|v| *v as u8));
    std::fs::write(path, bytes).expect("frame file writes");
}

fn header_of<T>(struct_type: PatchexStructType, next: *const c_void) -> PatchexStructHeader {
    PatchexStructHeader {
        next,
        ..PatchexStructHeader::of::<T>(struct_type)
    }
}

fn link<T>(value: &T) -> *const c_void {
    (value as *const T).cast()
}

/// The C program's images, as it wrote them.
fn c_output(dir: &Path, name: &str, format: vk::Format) -> Vec<f32> {
    let bytes = std::fs::read(dir.join(format!("{name}.bin"))).expect("the C test wrote it");
    decode(format, &bytes)
}

fn c_stats(dir: &Path, name: &str) -> PatchexFrameStats {
    let bytes = std::fs::read(dir.join(format!("{name}.bin"))).expect("the C test wrote it");
    assert_eq!(bytes.len(), size_of::<PatchexFrameStats>());
    // SAFETY: the C program wrote a PatchexFrameStats of this very layout.
    unsafe { std::ptr::read_unaligned(bytes.as_ptr().cast()) }
}

/// Everything in the stats but the GPU times, which vary from run to run.
fn assert_same_stats(c: &PatchexFrameStats, rust: &PatchexFrameStats) {
    let frame = |s: &PatchexFrameStats| {
        format!(
            "{} {} {} {} {} {} {} {} {} {} {:?} {:?}",
            s.frame_index,
            s.width,
            s.height,
            s.reset_reason,
            s.source_sanitized_pixels,
            s.source_invalid_geometry_pixels,
            s.extrapolation_count,
            s.device_memory_bytes,
            s.submit_stages_run,
            s.shadow_history,
            s.submit_traffic,
            s.extrapolation_traffic
        )
    };
    assert_eq!(frame(c), frame(rust), "frame {}", rust.frame_index);
    for (i, (from_c, from_rust)) in c
        .extrapolations
        .iter()
        .zip(&rust.extrapolations)
        .enumerate()
    {
        let untimed = |s: &PatchexExtrapolationStats| PatchexExtrapolationStats {
            gpu_ms: [0.0; PATCHEX_STAGE_SLOTS],
            ..*s
        };
        assert_eq!(
            format!("{:?}", untimed(from_c)),
            format!("{:?}", untimed(from_rust)),
            "frame {} extrapolation {i}",
            rust.frame_index
        );
    }
}

/// Installs the library into `scratch`/prefix and builds tests/c/`name`.c against it, as a C
/// engine builds: strict C11, `near` and `far` defined away as <windows.h> does, flags from
/// pkg-config, and an rpath so that it finds libpatchex.so.N outside the loader's paths.
fn build_c_test(root: &Path, scratch: &Path, name: &str) -> PathBuf {
    let prefix = scratch.join("prefix");
    install(root, &prefix);
    let flags = pkg_config_flags(&prefix);
    let program = scratch.join(name);
    run(
        Command::new("cc")
            .args(["-std=c11", "-Wall", "-Wextra", "-pedantic", "-Werror"])
            .args(["-Dnear=", "-Dfar="])
            .arg(root.join(format!("tests/c/{name}.c")))
            .arg("-o")
            .arg(&program)
            .args(flags.split_whitespace())
            .arg("-lm")
            .arg(format!("-Wl,-rpath,{}", prefix.join("lib").display())),
        "cc (strict C11)",
    );
    program
}

/// Values real frames hold, from C (tests/c/extremes_test.c): HDR colour over any albedo, black
/// base colour in frame t, a camera 1e7 from the origin, infinite and out-of-range depth,
/// negative colour and a near plane the projection disagrees with, each checked against what
/// the header says.
#[test]
fn c11_engine_meets_the_values_real_frames_hold() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let scratch = tempfile::tempdir().expect("a scratch directory");
    let program = build_c_test(&root, scratch.path(), "extremes_test");
    let printed = run(&mut Command::new(&program), "the C11 extremes test");
    println!("{printed}");
    assert!(printed.contains("ok (0 failures, 0 validation messages)"));
}

/// A puff of smoke over `frame`, drifting up and to the right: a translucency mask (a soft
/// disc), its motion to the previous instant, and the colour before it (the frame's colour,
/// which the puff brightens, dimmed).
fn smoke_over(frame: &Image) -> (Image, Image, Image) {
    let (width, height) = (frame.width, frame.height);
    let (centre_x, centre_y, radius) =
        (0.6 * width as f32, 0.4 * height as f32, 0.3 * height as f32);
    let mask = Image::from_fn(width, height, 1, |x, y| {
        let dx = (x as f32 + 0.5 - centre_x) / radius;
        let dy = (y as f32 + 0.5 - centre_y) / radius;
        let r2 = (dx * dx + dy * dy).min(1.0);
        vec![0.6 * (1.0 - r2) * (1.0 - r2)]
    });
    let motion = Image::from_fn(width, height, 2, |_, _| vec![-3.0, 2.0]);
    let mut opaque_color = frame.clone();
    opaque_color.data.iter_mut().for_each(|v| *v *= 0.8);
    (mask, motion, opaque_color)
}

#[test]
fn c11_engine_reaches_every_feature_and_matches_the_rust_path() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let scratch = tempfile::tempdir().expect("a scratch directory");
    let (data, out) = (scratch.path().join("data"), scratch.path().join("out"));
    std::fs::create_dir_all(&data).unwrap();
    std::fs::create_dir_all(&out).unwrap();
    let program = build_c_test(&root, scratch.path(), "abi_test");

    // Frames t-1 and t (0 and 2) and the instants halfway to the next frame (1 and 3).
    let sequence = render("crossing_street.toml", 4, WIDTH, HEIGHT);
    for (index, frame) in sequence.frames.iter().enumerate() {
        write_frame(frame, &data.join(format!("frame{index}.bin")));
    }
    let sun = sequence.manifest.sun.expect("the renderer records its sun");
    let sun_floats: Vec<u8> = sun
        .direction
        .iter()
        .chain(&sun.illuminance)
        .flat_map(|v| v.to_ne_bytes())
        .collect();
    std::fs::write(data.join("sun.bin"), sun_floats).unwrap();
    let sky = sequence.manifest.sky.expect("the renderer records its sky");
    let sky = Image {
        width: SKY_SIDE,
        height: SKY_SIDE,
        channels: 4,
        data: sky.octahedral_map(SKY_SIDE),
    };
    let sky_bytes: Vec<u8> = (SKY_SIDE as u32)
        .to_ne_bytes()
        .into_iter()
        .chain(sky.data.iter().flat_map(|v| v.to_ne_bytes()))
        .collect();
    std::fs::write(data.join("sky.bin"), sky_bytes).unwrap();
    let (mask, motion, opaque_color) = smoke_over(&sequence.frames[2].color);
    let translucency: Vec<u8> = mask
        .data
        .iter()
        .chain(&motion.data)
        .chain(&opaque_color.data)
        .flat_map(|v| v.to_ne_bytes())
        .collect();
    std::fs::write(data.join("translucency.bin"), translucency).unwrap();
    // The shipped weights, read from their files (PatchexNetworkWeights).
    let fi = root.join("assets/networks/fi.safetensors");
    let near_be = root.join("assets/networks/near_be.safetensors");
    let printed = run(
        Command::new(&program)
            .arg(&data)
            .arg(&out)
            .arg(WIDTH.to_string())
            .arg(HEIGHT.to_string())
            .arg(&fi)
            .arg(&near_be),
        "the C11 ABI test",
    );
    println!("{printed}");
    assert!(printed.contains("ok (0 failures, 0 validation messages)"));

    // The same calls through the Rust path.
    let fi_path = CString::new(fi.to_str().unwrap()).unwrap();
    let near_be_path = CString::new(near_be.to_str().unwrap()).unwrap();
    let memory = PatchexNetworkMemory {
        header: header_of::<PatchexNetworkMemory>(
            PATCHEX_STRUCT_TYPE_NETWORK_MEMORY,
            std::ptr::null(),
        ),
        max_patch_side: 64,
    };
    let precision = PatchexNetworkPrecision {
        header: header_of::<PatchexNetworkPrecision>(
            PATCHEX_STRUCT_TYPE_NETWORK_PRECISION,
            link(&memory),
        ),
        tensors: PATCHEX_TENSOR_PRECISION_FP32,
    };
    let networks = PatchexNetworkSettings {
        header: header_of::<PatchexNetworkSettings>(
            PATCHEX_STRUCT_TYPE_NETWORK_SETTINGS,
            link(&precision),
        ),
        run_fi: 1,
        run_near_be: 1,
        whole_frame: 0,
        resolution_divisor: 1,
        correct_valid_pixels: 1,
    };
    let weights = PatchexNetworkWeights {
        header: header_of::<PatchexNetworkWeights>(
            PATCHEX_STRUCT_TYPE_NETWORK_WEIGHTS,
            link(&networks),
        ),
        fi_path: fi_path.as_ptr(),
        near_be_path: near_be_path.as_ptr(),
    };
    let flow = PatchexShadowFlowSettings {
        header: header_of::<PatchexShadowFlowSettings>(
            PATCHEX_STRUCT_TYPE_SHADOW_FLOW_SETTINGS,
            link(&weights),
        ),
        levels: PATCHEX_DEFAULT_FLOW_LEVELS,
        iterations: PATCHEX_DEFAULT_FLOW_ITERATIONS,
        window_radius: PATCHEX_DEFAULT_FLOW_WINDOW_RADIUS,
        poly_radius: PATCHEX_DEFAULT_FLOW_POLY_RADIUS,
        poly_sigma: PATCHEX_DEFAULT_FLOW_POLY_SIGMA,
    };
    let segmentation = PatchexSegmentationSettings {
        header: header_of::<PatchexSegmentationSettings>(
            PATCHEX_STRUCT_TYPE_SEGMENTATION_SETTINGS,
            link(&flow),
        ),
        growth_x: 2.5,
        growth_y: 3.5,
    };
    let warp = PatchexWarpSettings {
        header: header_of::<PatchexWarpSettings>(
            PATCHEX_STRUCT_TYPE_WARP_SETTINGS,
            link(&segmentation),
        ),
        ..WarpSettings::default().to_abi()
    };
    let rig = Rig::with_create_info(WIDTH, HEIGHT, |info| {
        info.preset = PATCHEX_PRESET_FULL;
        info.header.next = link(&warp);
    });
    let engine = &rig.engine;
    let family = engine.queue_family_index;
    let frames: Vec<GpuFrame> = sequence
        .frames
        .iter()
        .map(|frame| GpuFrame::upload(engine, frame))
        .collect();
    let half = vk::Format::R16G16B16A16_SFLOAT;
    let first = output_image(engine, WIDTH, HEIGHT);
    let first_diagnostics = output_image(engine, WIDTH, HEIGHT);
    let output_formats = [half, half, vk::Format::A2B10G10R10_UNORM_PACK32];
    let outputs = output_formats.map(|format| output_image_as(engine, format, WIDTH, HEIGHT));
    let diagnostics = output_image(engine, WIDTH, HEIGHT);
    let shadow_diagnostics = output_image(engine, WIDTH, HEIGHT);
    let target_shadows = output_image(engine, WIDTH, HEIGHT);
    let gpu_mask = upload(engine, &mask, vk::Format::R32_SFLOAT, GBUFFER_LAYOUT);
    let gpu_motion = upload(engine, &motion, vk::Format::R32G32_SFLOAT, GBUFFER_LAYOUT);
    let gpu_opaque = upload(
        engine,
        &opaque_color,
        vk::Format::R32G32B32A32_SFLOAT,
        GBUFFER_LAYOUT,
    );
    let gpu_sky = upload(
        engine,
        &sky,
        vk::Format::R32G32B32A32_SFLOAT,
        GBUFFER_LAYOUT,
    );
    // Frame t goes lit by the sun and the sky and with its translucency; frame t-1 with none.
    let submit = |cmd, frame: &GpuFrame, index, flow: Option<&PatchexShadowFlowSettings>, lit| {
        let mut shadow = frame.shadow_input();
        shadow.header.next = flow.map_or(std::ptr::null(), link);
        let reflected = PatchexSkyLight {
            header: header_of::<PatchexSkyLight>(PATCHEX_STRUCT_TYPE_SKY_LIGHT, link(&shadow)),
            radiance: gpu_sky.describe(GBUFFER_LAYOUT),
            mip_levels: 1,
        };
        let mut light = frame.sun_light(&sun, true);
        light.header.next = link(&reflected);
        let over = PatchexTranslucencyInput {
            header: header_of::<PatchexTranslucencyInput>(
                PATCHEX_STRUCT_TYPE_TRANSLUCENCY_INPUT,
                link(&light),
            ),
            mask: gpu_mask.describe(GBUFFER_LAYOUT),
            motion_vectors: gpu_motion.describe(GBUFFER_LAYOUT),
            motion_vector_scale: [1.0, 1.0],
            opaque_color: gpu_opaque.describe(GBUFFER_LAYOUT),
        };
        let mut desc = frame.frame_desc(index, family);
        desc.header.next = if lit { link(&over) } else { link(&shadow) };
        rig.submit_ok(cmd, &desc);
    };
    let extrapolate = |cmd, target: &GpuFrame, output: &EngineImage, chain: *const c_void| {
        let mut desc = target.extrapolate_desc(output, 0.5, family);
        desc.header.next = chain;
        rig.extrapolate_ok(cmd, &desc);
    };
    let frame_flow = PatchexShadowFlowSettings {
        header: header_of::<PatchexShadowFlowSettings>(
            PATCHEX_STRUCT_TYPE_SHADOW_FLOW_SETTINGS,
            std::ptr::null(),
        ),
        iterations: 2,
        ..flow
    };
    engine.run(|cmd| {
        submit(cmd, &frames[0], 1, Some(&frame_flow), false);
        let diag = PatchexDiagnostics {
            header: header_of::<PatchexDiagnostics>(
                PATCHEX_STRUCT_TYPE_DIAGNOSTICS,
                std::ptr::null(),
            ),
            image: first_diagnostics.describe(OUTPUT_LAYOUT),
        };
        extrapolate(cmd, &frames[1], &first, link(&diag));
    });
    engine.run(|cmd| {
        submit(cmd, &frames[2], 2, None, true);
        let kinds = [
            PATCHEX_WARP_GBUFFER_GUIDED,
            PATCHEX_WARP_MOTION_VECTOR,
            PATCHEX_WARP_OCCLUSION_MOTION_VECTOR,
        ];
        for (k, kind) in kinds.into_iter().enumerate() {
            let run_networks = PatchexNetworkSettings {
                header: header_of::<PatchexNetworkSettings>(
                    PATCHEX_STRUCT_TYPE_NETWORK_SETTINGS,
                    std::ptr::null(),
                ),
                run_fi: 1,
                run_near_be: (k == 0) as u32,
                whole_frame: (k == 2) as u32,
                resolution_divisor: if k == 1 { 2 } else { 1 },
                correct_valid_pixels: (k == 1) as u32,
            };
            let growth = PatchexSegmentationSettings {
                header: header_of::<PatchexSegmentationSettings>(
                    PATCHEX_STRUCT_TYPE_SEGMENTATION_SETTINGS,
                    link(&run_networks),
                ),
                growth_x: 3.0,
                growth_y: 1.5,
            };
            let warp_kind = PatchexWarpSettings {
                header: header_of::<PatchexWarpSettings>(
                    PATCHEX_STRUCT_TYPE_WARP_SETTINGS,
                    link(&growth),
                ),
                kind,
                ..warp
            };
            let shadow_diag = PatchexShadowDiagnostics {
                header: header_of::<PatchexShadowDiagnostics>(
                    PATCHEX_STRUCT_TYPE_SHADOW_DIAGNOSTICS,
                    link(&warp_kind),
                ),
                image: shadow_diagnostics.describe(OUTPUT_LAYOUT),
            };
            let diag = PatchexDiagnostics {
                header: header_of::<PatchexDiagnostics>(
                    PATCHEX_STRUCT_TYPE_DIAGNOSTICS,
                    link(&shadow_diag),
                ),
                image: diagnostics.describe(OUTPUT_LAYOUT),
            };
            let chain = if k == 0 {
                link(&diag)
            } else {
                link(&warp_kind)
            };
            extrapolate(cmd, &frames[3], &outputs[k], chain);
        }
        let target_mask = PatchexTargetShadowInput {
            header: header_of::<PatchexTargetShadowInput>(
                PATCHEX_STRUCT_TYPE_TARGET_SHADOW_INPUT,
                std::ptr::null(),
            ),
            mask: frames[3].shadow_input().mask,
        };
        extrapolate(cmd, &frames[3], &target_shadows, link(&target_mask));
    });

    let compare = |name: &str, image: &EngineImage, format: vk::Format| {
        let rust = image.read(engine, OUTPUT_LAYOUT);
        let c = c_output(&out, name, format);
        assert!(same_bits(&c, &rust), "{name}: the C and Rust paths differ");
        Image {
            width: WIDTH as usize,
            height: HEIGHT as usize,
            channels: 4,
            data: rust,
        }
    };
    compare("first", &first, half);
    compare("first_diagnostics", &first_diagnostics, half);
    for (name, (image, format)) in ["gbuffer_guided", "motion_vector", "occlusion_motion_vector"]
        .into_iter()
        .zip(outputs.iter().zip(output_formats))
    {
        compare(name, image, format);
    }
    let diagnostics = compare("diagnostics", &diagnostics, half);
    let shadow_diagnostics = compare("shadow_diagnostics", &shadow_diagnostics, half);
    compare("target_shadows", &target_shadows, half);

    let (result, second) = rig.stats(2);
    assert_eq!(result, PatchexResult::Success);
    assert_same_stats(&c_stats(&out, "stats1"), &rig.stats(1).1);
    assert_same_stats(&c_stats(&out, "stats2"), &second);

    // The calls did what their structs asked.
    assert_eq!(second.shadow_history, PATCHEX_SHADOW_HISTORY_TRACKED);
    let [guided, motion, occlusion, masked] = &second.extrapolations;
    let ran = |s: &PatchexExtrapolationStats, stage: PatchexStage| s.stages_run & 1 << stage != 0;
    assert!(
        ran(masked, PATCHEX_STAGE_TARGET_SHADOWS) && !ran(guided, PATCHEX_STAGE_TARGET_SHADOWS)
    );
    assert!(ran(guided, PATCHEX_STAGE_SHADOW_WARP) && ran(guided, PATCHEX_STAGE_DIAGNOSTICS));
    assert!(second
        .extrapolations
        .iter()
        .all(|s| ran(s, PATCHEX_STAGE_HIGHLIGHTS) && ran(s, PATCHEX_STAGE_TRANSLUCENCY)));
    assert!(ran(guided, PATCHEX_STAGE_INFERENCE) && guided.repaired_fraction > 0.0);
    assert!(!ran(motion, PATCHEX_STAGE_DIAGNOSTICS));
    assert!(ran(occlusion, PATCHEX_STAGE_PACK_OUTPUT) && occlusion.repaired_fraction == 1.0);
    // The whole 96-pixel-wide frame in tensors of 64 texels a side.
    assert_eq!(occlusion.network_divisors, [2, 0]);
    assert!(
        diagnostics.data.chunks(4).any(|p| p[1] == 1.0),
        "the diagnostics show an FI region"
    );
    assert!(
        shadow_diagnostics.data.chunks(4).any(|p| p[2] != 0.0),
        "the shadow diagnostics show a shadow layer"
    );
}
