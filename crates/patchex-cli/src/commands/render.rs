//! `patchex render SCENE --frames N --size WxH --out DIR`

use super::CommandResult;
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use patchex_scene::dataset::{render_sequence, SequenceOptions};
use patchex_scene::{Gpu, GpuOptions, World};
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

#[derive(Args)]
pub struct RenderArgs {
    /// Scene file (TOML).
    scene: PathBuf,
    /// Number of frames of the stream (with one target between rendered frames, the doubled
    /// stream: even frames rendered, odd frames targets).
    #[arg(long, default_value_t = 16)]
    frames: usize,
    /// Target instants between two rendered frames: 1 for 2x frame generation, 2 for 3x
    /// (alpha 1/3 and 2/3).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=7))]
    targets_between: u32,
    /// Output resolution, WIDTHxHEIGHT.
    #[arg(long, default_value = "640x360", value_parser = parse_size)]
    size: (u32, u32),
    /// Output folder for manifest.json and frame_NNNN.exr.
    #[arg(long)]
    out: PathBuf,
    /// Assets folder; defaults to the `assets` folder beside the nearest folder above the scene
    /// file that has one.
    #[arg(long)]
    assets: Option<PathBuf>,
    /// Run with the Vulkan validation layer and fail on any message.
    #[arg(long)]
    validation: bool,
}

pub fn parse_size(text: &str) -> Result<(u32, u32), String> {
    let (w, h) = text
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("expected WIDTHxHEIGHT, got {text:?}"))?;
    let parse = |s: &str| s.parse::<u32>().map_err(|e| format!("{s:?}: {e}"));
    let (w, h) = (parse(w)?, parse(h)?);
    if w == 0 || h == 0 {
        return Err("width and height must be positive".into());
    }
    Ok((w, h))
}

pub fn run(args: RenderArgs) -> CommandResult {
    let world = World::load(&args.scene, args.assets.as_deref())?;
    let gpu = Arc::new(Gpu::new(GpuOptions {
        validation: args.validation,
    })?);
    let bar = ProgressBar::new(args.frames as u64);
    bar.set_style(
        ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} frames, {elapsed} (eta {eta})")?
            .progress_chars("=> "),
    );
    bar.set_message(world.description.name.clone());
    let started = Instant::now();
    let options = SequenceOptions {
        targets_between: args.targets_between as usize,
        frames: args.frames,
        width: args.size.0,
        height: args.size.1,
        out_dir: args.out.clone(),
    };
    render_sequence(&gpu, &world, &options, &mut |done, _| {
        bar.set_position(done as u64)
    })?;
    bar.finish();
    let messages = gpu.take_validation_messages();
    if !messages.is_empty() {
        return Err(format!(
            "{} validation messages, first: {}",
            messages.len(),
            messages[0]
        )
        .into());
    }
    eprintln!(
        "{} frames of {} on {} in {:.1} s -> {}",
        args.frames,
        world.description.name,
        gpu.device_name(),
        started.elapsed().as_secs_f64(),
        args.out.display()
    );
    Ok(())
}
