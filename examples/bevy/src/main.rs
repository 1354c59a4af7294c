//! patchex generating every other displayed frame inside Bevy, headless.
//!
//! Bevy renders a scene of animated glTF characters under a sun with shadows, seen by a moving
//! camera, at twice the rate it shades: even displayed instants are Bevy's frames, odd ones are
//! extrapolated by patchex from the frame before and the instant's own G-buffer (Bevy's
//! prepasses), recorded into Bevy's frame through wgpu's Vulkan interop. `--check` also has Bevy
//! shade the generated instants, and scores patchex's frames against them beside repeating
//! frame t. docs/integration-bevy.md explains the integration.

mod check;
mod frame_generation;
mod gbuffer;
mod interop;
mod scene;
mod validation;

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use bevy::app::PluginsState;
use bevy::log::LogPlugin;
use bevy::prelude::*;
use bevy::render::renderer::RenderDevice;
use bevy::render::settings::{Backends, InstanceFlags, RenderCreation, WgpuSettings};
use bevy::render::{RenderApp, RenderPlugin};
use bevy::time::TimeUpdateStrategy;
use bevy::window::ExitCondition;

use check::{Check, Image};
use frame_generation::{DisplayedInstant, FrameGenerationPlugin, FrameGenerator};
use scene::ScenePlugin;

const USAGE: &str = "usage: patchex-bevy [--check] [--frames N] [--size WIDTHxHEIGHT] [--out DIR] \
                     [--min-gain DB]

  --check        Bevy also shades the generated instants; each generated frame is scored
                 against it beside repeating frame t, and the strip and scores are written
  --frames N     displayed instants after loading, half of them generated (default 24)
  --size WxH     the frame's size (default 480x270)
  --out DIR      where --check writes bevy_strip.png and bevy_scores.md (default: out/bevy
                 at the repository's root)
  --min-gain DB  with --check, fail unless the pooled PSNR gain over repeating frame t is at
                 least DB";

/// Displayed instants per second: Bevy shades half of them.
const DISPLAY_RATE: f64 = 60.0;

struct Args {
    check: bool,
    frames: u64,
    width: u32,
    height: u32,
    out: PathBuf,
    min_gain: Option<f64>,
}

impl Args {
    fn parse(mut args: impl Iterator<Item = String>) -> Result<Self, String> {
        let mut parsed = Self {
            check: false,
            frames: 24,
            width: 480,
            height: 270,
            out: PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../out/bevy")),
            min_gain: None,
        };
        while let Some(arg) = args.next() {
            let mut value = || args.next().ok_or_else(|| format!("{arg} needs a value"));
            match arg.as_str() {
                "--check" => parsed.check = true,
                "--frames" => parsed.frames = number(&value()?)?,
                "--size" => {
                    let size = value()?;
                    let (width, height) = size
                        .split_once('x')
                        .ok_or_else(|| format!("--size {size}: not WxH"))?;
                    (parsed.width, parsed.height) = (number(width)?, number(height)?);
                }
                "--out" => parsed.out = PathBuf::from(value()?),
                "--min-gain" => parsed.min_gain = Some(number(&value()?)?),
                "--help" | "-h" => return Err(USAGE.to_owned()),
                _ => return Err(format!("unknown argument {arg}\n\n{USAGE}")),
            }
        }
        if parsed.frames < 2 || parsed.width == 0 || parsed.height == 0 {
            return Err("--frames must be at least 2 and the size not empty".to_owned());
        }
        Ok(parsed)
    }
}

fn number<T: std::str::FromStr>(text: &str) -> Result<T, String> {
    text.parse().map_err(|_| format!("{text}: not a number"))
}

fn main() -> ExitCode {
    match Args::parse(std::env::args().skip(1)).and_then(run) {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("patchex-bevy: {message}");
            ExitCode::FAILURE
        }
    }
}

fn run(args: Args) -> Result<(), String> {
    let mut app = App::new();
    app.add_plugins(
        DefaultPlugins
            .set(WindowPlugin {
                primary_window: None,
                exit_condition: ExitCondition::DontExit,
                ..default()
            })
            .set(AssetPlugin {
                file_path: concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets").to_owned(),
                ..default()
            })
            .set(RenderPlugin {
                render_creation: RenderCreation::Automatic(Box::new(WgpuSettings {
                    backends: Some(Backends::VULKAN),
                    // Validation in every build, reported through wgpu's debug messenger (DEBUG).
                    instance_flags: InstanceFlags::VALIDATION | InstanceFlags::DEBUG,
                    ..default()
                })),
                // Every pipeline ready in the frame that first needs it: no frame drawn without
                // a mesh whose shader was still compiling.
                synchronous_pipeline_compilation: true,
                ..default()
            })
            .set(LogPlugin {
                custom_layer: validation::layer,
                ..default()
            }),
    )
    .insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_secs_f64(
        1.0 / DISPLAY_RATE,
    )))
    .add_plugins((
        ScenePlugin {
            width: args.width,
            height: args.height,
        },
        FrameGenerationPlugin { check: args.check },
    ));
    while app.plugins_state() == PluginsState::Adding {
        bevy::tasks::tick_global_task_pools_on_main_thread();
    }
    app.finish();
    app.cleanup();
    validation::require_layer(
        app.sub_app(RenderApp)
            .world()
            .resource::<RenderDevice>()
            .wgpu_device(),
    )?;

    load(&mut app)?;
    let mut check = Check::default();
    // The strip shows the last generated instant.
    let strip_instant = if args.frames.is_multiple_of(2) {
        args.frames - 1
    } else {
        args.frames - 2
    };
    for instant in 0..args.frames {
        app.world_mut()
            .insert_resource(DisplayedInstant(Some(instant)));
        app.update();
        let images = finish_frame(&mut app)?;
        if args.check {
            let stats = if instant % 2 == 1 {
                let render_world = app.sub_app(RenderApp).world();
                Some(
                    render_world
                        .resource::<FrameGenerator>()
                        .last_frame_stats()?,
                )
            } else {
                None
            };
            check.add(instant, images, stats.as_ref(), strip_instant)?;
        }
    }

    let (messages, unknown_source_language) = validation::reports();
    println!(
        "{} displayed instants at {}x{}, {} generated by patchex; {} Vulkan validation messages \
         ({} more only that this layer does not know WGSL as the source of Bevy's shaders)",
        args.frames,
        args.width,
        args.height,
        args.frames / 2,
        messages.len(),
        unknown_source_language,
    );
    for message in &messages {
        eprintln!("validation: {message}");
    }
    if args.check {
        let report = check.report();
        print!("{report}");
        std::fs::create_dir_all(&args.out).map_err(|e| format!("{}: {e}", args.out.display()))?;
        std::fs::write(args.out.join("bevy_scores.md"), &report).map_err(|e| e.to_string())?;
        check.write_strip(&args.out.join("bevy_strip.png"))?;
        let (generated, repeated) = check.pooled();
        let gain = generated - repeated;
        if let Some(min_gain) = args.min_gain.filter(|&min_gain| gain < min_gain) {
            return Err(format!(
                "patchex gains {gain:.2} dB over repeating frame t, less than {min_gain} dB"
            ));
        }
    }
    if !messages.is_empty() {
        return Err(format!("{} Vulkan validation messages", messages.len()));
    }
    Ok(())
}

/// Updates with time stopped until the characters are loaded and animating, and a few frames
/// more, so that instant 0 is the first frame of a fully loaded scene.
fn load(app: &mut App) -> Result<(), String> {
    const MAX_UPDATES: usize = 600;
    const SETTLING_UPDATES: usize = 3;
    app.world_mut().resource_mut::<Time<Virtual>>().pause();
    let mut loaded_for = 0;
    for _ in 0..MAX_UPDATES {
        app.update();
        finish_frame(app)?;
        let animating = app
            .world_mut()
            .query::<&AnimationGraphHandle>()
            .iter(app.world())
            .count();
        loaded_for = if animating >= scene::CHARACTERS {
            loaded_for + 1
        } else {
            0
        };
        if loaded_for > SETTLING_UPDATES {
            app.world_mut().resource_mut::<Time<Virtual>>().unpause();
            return Ok(());
        }
    }
    Err(format!("the scene did not load in {MAX_UPDATES} updates"))
}

/// Waits for the frame's GPU work, so no more than one frame is ever in flight, and returns
/// what it copied out.
fn finish_frame(app: &mut App) -> Result<Vec<(frame_generation::Readback, Image)>, String> {
    let render_world = app.sub_app_mut(RenderApp).world_mut();
    let device = render_world
        .resource::<RenderDevice>()
        .wgpu_device()
        .clone();
    let mut generator = render_world.resource_mut::<FrameGenerator>();
    if let Some(failure) = generator.failure.take() {
        return Err(failure);
    }
    let readbacks = std::mem::take(&mut generator.readbacks);
    for readback in &readbacks {
        readback
            .buffer
            .slice(..)
            .map_async(wgpu::MapMode::Read, |_| {});
    }
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| e.to_string())?;
    Ok(readbacks
        .into_iter()
        .map(|readback| {
            let bytes = readback.buffer.slice(..).get_mapped_range().to_vec();
            let image = Image {
                width: readback.width as usize,
                height: readback.height as usize,
                bytes_per_row: readback.bytes_per_row as usize,
                bytes,
            };
            (readback.what, image)
        })
        .collect())
}
