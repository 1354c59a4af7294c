//! `patchex selftest`: does patchex compute what it should on this machine's GPU and driver?
//!
//! Renders a few frames of a bundled scene, runs every configuration through the C ABI on the
//! named device (with the Khronos validation layers and synchronization validation where they
//! are installed), runs the plain-Rust reference on the same frames, and prints one line per
//! configuration: the share of pixels whose colour is off the reference by more than the
//! tolerance, against the share allowed, the holes against the reference's, and the validation
//! messages. The exit code is 0 only when every line passes.

use std::path::PathBuf;

use clap::Args;
use glam::Vec3;
use patchex::abi::*;
use patchex::network::{Network, SHIPPED_FI, SHIPPED_NEAR_BE};
use patchex::passes::highlights::Sun;
use patchex::passes::shadow_flow::{mask_step, FlowSettings};
use patchex::passes::warp::WarpSettings;
use patchex::reference::{self, inpaint::Networks, translucency, FrameInputs, Image, ShadowInputs};
use patchex_scene::dataset::{render_sequence, Dataset, Manifest, SequenceOptions};
use patchex_scene::scene::EmitterDescription;
use patchex_scene::{Gpu, GpuOptions, World};

use super::plugin_driver::{FrameExtras, NetworkChoice, PluginDriver, ShadowRun, SKY_SIDE};
use super::reference_frames::{from_layers, inputs, Frame};
use super::render::parse_size;
use super::{shipped_path, CommandResult};

#[derive(Args)]
pub struct SelftestArgs {
    /// Run on the first Vulkan device whose name contains this (case-insensitive); by default
    /// the first discrete or integrated GPU, else a CPU driver.
    #[arg(long)]
    device: Option<String>,
    /// The scene to render (TOML).
    #[arg(long, default_value_os_t = shipped_path("scenes/shadow_terrain.toml"))]
    scene: PathBuf,
    /// Frame size, WIDTHxHEIGHT.
    #[arg(long, value_parser = parse_size, default_value = "192x108")]
    size: (u32, u32),
    /// Folder for the rendered frames; a temporary one, removed after, by default.
    #[arg(long)]
    work: Option<PathBuf>,
}

/// A colour matches where every channel is within `RELATIVE * |reference| + ABSOLUTE` of the
/// reference's: f16 storage, the networks' half-float tensors and transcendental functions on
/// the GPU stay inside it.
const RELATIVE: f32 = 1e-2;
const ABSOLUTE: f32 = 2e-3;
/// Pixels allowed beyond that: a pixel whose warp decision sits at a threshold (an agreement
/// or a bilinear weight within rounding of its bound) may go the other way on a GPU.
const ALLOWED_SHARE: f64 = 0.005;

struct Configuration {
    name: &'static str,
    warp: PatchexWarpKind,
    shadows: bool,
    /// The target's shadow mask on the extrapolation, and the flow off.
    target_shadows: bool,
    networks: bool,
    /// Frame t goes with the scene's sun and sky (`PatchexSunLight`, `PatchexSkyLight`).
    sun: bool,
    /// What of its translucency frame t goes with (`PatchexTranslucencyInput`).
    translucency: TranslucencyGiven,
}

/// How much of the particles' `PatchexTranslucencyInput` frame t goes with.
#[derive(Clone, Copy, PartialEq, Eq)]
enum TranslucencyGiven {
    Nothing,
    MaskAndMotion,
    /// The mask, the motion and the colour before the translucency pass.
    Everything,
}

const CONFIGURATIONS: [Configuration; 10] = [
    Configuration {
        name: "G-buffer-guided warp (WARP_ONLY)",
        warp: PATCHEX_WARP_GBUFFER_GUIDED,
        shadows: false,
        target_shadows: false,
        networks: false,
        sun: false,
        translucency: TranslucencyGiven::Nothing,
    },
    Configuration {
        name: "motion-vector warp",
        warp: PATCHEX_WARP_MOTION_VECTOR,
        shadows: false,
        target_shadows: false,
        networks: false,
        sun: false,
        translucency: TranslucencyGiven::Nothing,
    },
    Configuration {
        name: "occlusion-motion-vector warp",
        warp: PATCHEX_WARP_OCCLUSION_MOTION_VECTOR,
        shadows: false,
        target_shadows: false,
        networks: false,
        sun: false,
        translucency: TranslucencyGiven::Nothing,
    },
    Configuration {
        name: "warp + shadows (WARP_AND_SHADOWS)",
        warp: PATCHEX_WARP_GBUFFER_GUIDED,
        shadows: true,
        target_shadows: false,
        networks: false,
        sun: false,
        translucency: TranslucencyGiven::Nothing,
    },
    Configuration {
        name: "warp + target shadow mask, no flow",
        warp: PATCHEX_WARP_GBUFFER_GUIDED,
        shadows: true,
        target_shadows: true,
        networks: false,
        sun: false,
        translucency: TranslucencyGiven::Nothing,
    },
    Configuration {
        name: "warp + sun and sky highlights",
        warp: PATCHEX_WARP_GBUFFER_GUIDED,
        shadows: false,
        target_shadows: false,
        networks: false,
        sun: true,
        translucency: TranslucencyGiven::Nothing,
    },
    Configuration {
        name: "warp + translucency mask and motion",
        warp: PATCHEX_WARP_GBUFFER_GUIDED,
        shadows: false,
        target_shadows: false,
        networks: false,
        sun: false,
        translucency: TranslucencyGiven::MaskAndMotion,
    },
    Configuration {
        name: "warp + translucency, opaque colour",
        warp: PATCHEX_WARP_GBUFFER_GUIDED,
        shadows: false,
        target_shadows: false,
        networks: false,
        sun: false,
        translucency: TranslucencyGiven::Everything,
    },
    Configuration {
        name: "warp + networks (NETWORKS)",
        warp: PATCHEX_WARP_GBUFFER_GUIDED,
        shadows: false,
        target_shadows: false,
        networks: true,
        sun: false,
        translucency: TranslucencyGiven::Nothing,
    },
    Configuration {
        name: "PatchEX (FULL)",
        warp: PATCHEX_WARP_GBUFFER_GUIDED,
        shadows: true,
        target_shadows: false,
        networks: true,
        sun: false,
        translucency: TranslucencyGiven::Nothing,
    },
];

/// The target the configurations extrapolate: frame 3 from frame 2, frame 0 its shadows'
/// frame t-1 (the first target with one).
const TARGET: usize = 3;

pub fn run(args: SelftestArgs) -> CommandResult {
    let (width, height) = args.size;
    let temporary = args.work.is_none();
    let work = args.work.clone().unwrap_or_else(|| {
        std::env::temp_dir().join(format!("patchex-selftest-{}", std::process::id()))
    });
    let mut world = World::load(&args.scene, None)?;
    if world.description.particles.is_empty() {
        // Smoke where the camera looks, for the translucency passes to take apart and move.
        world
            .description
            .particles
            .push(smoke_in_view(&world, width, height));
    }
    let renderer = std::sync::Arc::new(Gpu::new(GpuOptions { validation: false })?);
    render_sequence(
        &renderer,
        &world,
        &SequenceOptions {
            targets_between: 1,
            frames: TARGET + 1,
            width,
            height,
            out_dir: work.clone(),
        },
        &mut |_, _| {},
    )?;
    drop(renderer);
    let verdict = check(&args, &work);
    if temporary {
        let _ = std::fs::remove_dir_all(&work);
    }
    if verdict? {
        println!("selftest: PASS");
        Ok(())
    } else {
        println!("selftest: FAIL");
        std::process::exit(1);
    }
}

/// Runs every configuration on the rendered frames; true when all pass.
fn check(args: &SelftestArgs, work: &std::path::Path) -> Result<bool, Box<dyn std::error::Error>> {
    let dataset = Dataset::open(work)?;
    let manifest = &dataset.manifest;
    let device = args.device.as_deref();
    // Validation where the layers are installed; without them the checks still run.
    let (driver, validated) = match PluginDriver::on_device(manifest, true, device) {
        Ok(driver) => (driver, true),
        Err(with_layers) => match PluginDriver::on_device(manifest, false, device) {
            Ok(driver) => (driver, false),
            Err(_) => return Err(with_layers.into()),
        },
    };
    println!(
        "patchex selftest on {} ({}x{}, {}): colour within {RELATIVE} x |reference| + \
         {ABSOLUTE} on all but {:.1}% of the pixels",
        driver.engine.device_name,
        manifest.width,
        manifest.height,
        if validated {
            "validation and synchronization validation on"
        } else {
            "validation layers not installed: unvalidated"
        },
        100.0 * ALLOWED_SHARE
    );

    let (source_index, alpha) = manifest.source_of(TARGET);
    let earlier_index = source_index - 2;
    let layers = [
        dataset.read_frame(earlier_index)?,
        dataset.read_frame(source_index)?,
        dataset.read_frame(TARGET)?,
    ];
    let frames = [
        from_layers(&layers[0], &dataset, earlier_index)?,
        from_layers(&layers[1], &dataset, source_index)?,
        from_layers(&layers[2], &dataset, TARGET)?,
    ];
    let shipped = [
        Network::from_safetensors(SHIPPED_FI, "built-in FI network")?,
        Network::from_safetensors(SHIPPED_NEAR_BE, "built-in near-BE network")?,
    ];
    let mut all_pass = true;
    for (n, configuration) in CONFIGURATIONS.iter().enumerate() {
        let warp = WarpSettings {
            kind: configuration.warp,
            ..WarpSettings::default()
        };
        let networks = configuration.networks.then(NetworkChoice::default);
        let got = driver.extrapolate(
            4 * (n as u64 + 1),
            (&layers[1], &manifest.frames[source_index]),
            (&layers[2], &manifest.frames[TARGET]),
            alpha,
            Some(warp),
            networks.as_ref(),
            false,
            configuration.shadows.then_some(ShadowRun {
                earlier: Some((&layers[0], &manifest.frames[earlier_index])),
                target_mask: configuration.target_shadows,
            }),
            FrameExtras {
                sun: configuration.sun,
                sky: configuration.sun,
                translucency: configuration.translucency != TranslucencyGiven::Nothing,
                opaque_color: configuration.translucency == TranslucencyGiven::Everything,
            },
        )?;
        let want = expected(&frames, configuration, alpha, &warp, &shipped, manifest);
        let messages = driver.validation_messages();

        let pixels = (manifest.width * manifest.height) as f64;
        let beyond = got
            .color
            .chunks_exact(4)
            .zip(want.output.data.chunks_exact(4))
            .filter(|(got, want)| {
                (0..3).any(|c| (got[c] - want[c]).abs() > RELATIVE * want[c].abs() + ABSOLUTE)
            })
            .count() as f64;
        let holes = (got.stats.extrapolations[0].hole_fraction as f64 * pixels).round();
        let hole_difference = (holes - want.warped.hole_pixels as f64).abs();
        // A configuration only checks its sub-tasks if they ran on these frames.
        let stats = &got.stats;
        let ran = |stage: PatchexStage| stats.extrapolations[0].stages_run & (1 << stage) != 0;
        let shadows_exercised = if configuration.target_shadows {
            stats.shadow_history == PATCHEX_SHADOW_HISTORY_SEPARATED
                && ran(PATCHEX_STAGE_TARGET_SHADOWS)
        } else {
            stats.shadow_history == PATCHEX_SHADOW_HISTORY_TRACKED && ran(PATCHEX_STAGE_SHADOW_WARP)
        };
        let exercised = (!configuration.shadows || shadows_exercised)
            && (!configuration.networks || ran(PATCHEX_STAGE_INFERENCE))
            && configuration.sun == ran(PATCHEX_STAGE_HIGHLIGHTS);
        let pass = exercised
            && beyond <= ALLOWED_SHARE * pixels
            && hole_difference <= ALLOWED_SHARE * pixels
            && messages.is_empty();
        all_pass &= pass;
        println!(
            "{} {:<36} colour off on {:.2}% of pixels (allowed {:.1}%), holes {} against {}, \
             {} validation messages",
            if pass { "PASS" } else { "FAIL" },
            configuration.name,
            100.0 * beyond / pixels,
            100.0 * ALLOWED_SHARE,
            holes,
            want.warped.hole_pixels,
            messages.len()
        );
        if !exercised {
            println!("     its shadow, network or highlight stages did not run on these frames");
        }
        for message in messages.iter().take(3) {
            println!("     {message}");
        }
    }
    Ok(all_pass)
}

/// The reference's extrapolation of `frames` (frame t-1, frame t, the target) in
/// `configuration`.
fn expected(
    frames: &[Frame; 3],
    configuration: &Configuration,
    alpha: f32,
    warp: &WarpSettings,
    shipped: &[Network; 2],
    manifest: &Manifest,
) -> reference::Extrapolation {
    let [earlier, source, target] = frames;
    let extent = ash::vk::Extent2D {
        width: source.color.width as u32,
        height: source.color.height as u32,
    };
    let shadows = ShadowInputs {
        color_without_dynamic_shadows: &source.color_without_dynamic_shadows,
        mask: &source.shadow_mask,
        previous: Some((&earlier.shadow_mask, &earlier.stencil, &earlier.camera)),
        flow: if configuration.target_shadows {
            FlowSettings::off()
        } else {
            FlowSettings::default()
        },
        mask_step: mask_step(extent),
        target_mask: configuration.target_shadows.then_some(&target.shadow_mask),
    };
    let networks = if configuration.networks {
        Networks {
            fi: Some(&shipped[0]),
            near_be: Some(&shipped[1]),
            ..Networks::default()
        }
    } else {
        Networks::default()
    };
    let sun = manifest.sun.filter(|_| configuration.sun).map(|sun| {
        let sun = Sun {
            direction: sun.direction.into(),
            illuminance: sun.illuminance.into(),
        };
        (sun, &source.sun_visibility)
    });
    // The map the driver gives the plugin.
    let sky = manifest.sky.filter(|_| configuration.sun).map(|sky| Image {
        width: SKY_SIDE,
        height: SKY_SIDE,
        channels: 4,
        data: sky.octahedral_map(SKY_SIDE),
    });
    let translucency = source
        .translucency
        .as_ref()
        .filter(|_| configuration.translucency != TranslucencyGiven::Nothing)
        .map(|given| translucency::Input {
            mask: &given.mask,
            motion: Some((&given.motion, [1.0, 1.0])),
            opaque: (configuration.translucency == TranslucencyGiven::Everything)
                .then_some(&given.opaque_color),
        });
    reference::extrapolate(
        &FrameInputs {
            sun,
            sky: sky.as_ref().map(std::slice::from_ref),
            translucency,
            ..inputs(source)
        },
        &inputs(target),
        configuration.shadows.then_some(&shadows),
        alpha,
        warp,
        &Default::default(),
        networks,
    )
}

/// A smoke column drifting through the view: five metres ahead of the camera at the scene's
/// start, a metre below its line of sight.
fn smoke_in_view(world: &World, width: u32, height: u32) -> EmitterDescription {
    let camera = world.camera(world.description.start_time, width as f32 / height as f32);
    let forward = camera
        .view
        .inverse()
        .transform_vector3(Vec3::NEG_Z)
        .normalize();
    let origin = camera.position + 5.0 * forward - Vec3::Y;
    EmitterDescription {
        origin: origin.into(),
        origin_spread: 0.3,
        rate: 14.0,
        lifetime: 2.5,
        velocity: [0.3, 0.9, 0.0],
        velocity_spread: 0.25,
        acceleration: [0.8, 0.1, 0.0],
        radius: [0.3, 0.9],
        color: [0.3, 0.3, 0.32],
        opacity: 0.6,
        seed: 1,
    }
}
