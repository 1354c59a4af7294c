//! `patchex demo`: the main job. Renders a real scene with the scene renderer at twice the
//! display rate, extrapolates every target instant from the rendered frame before it through
//! the plugin's C ABI, and writes what a person can look at: a picture strip per target
//! (frame t, extrapolated, ground truth, error) and a table of quality and GPU time.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::sync::Arc;

use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use patchex::abi::*;
use patchex::passes::STAGES;
use patchex_scene::dataset::{render_sequence, Dataset, FrameRole, SequenceOptions, FINAL_IMAGE};
use patchex_scene::{Gpu, GpuOptions, World};

use super::picture::{psnr, tone_map, write_strip};
use super::plugin_driver::{FrameExtras, NetworkChoice, PluginDriver, ShadowRun};
use super::render::parse_size;
use super::CommandResult;

#[derive(Args)]
pub struct DemoArgs {
    /// Scene file (TOML); by default the repository's crossing_street.
    #[arg(default_value_os_t = super::shipped_path("scenes/crossing_street.toml"))]
    scene: PathBuf,
    /// Frames of the doubled stream to render; every odd frame is extrapolated.
    #[arg(long, default_value_t = 16)]
    frames: usize,
    /// Resolution, WIDTHxHEIGHT.
    #[arg(long, default_value = "640x360", value_parser = parse_size)]
    size: (u32, u32),
    /// Output folder: dataset/, strips/, summary.md, summary.json.
    #[arg(long, default_value = "out/demo")]
    out: PathBuf,
    /// Assets folder; defaults to the `assets` folder beside the nearest folder above the scene
    /// file that has one.
    #[arg(long)]
    assets: Option<PathBuf>,
    /// Run renderer and plugin under the Vulkan validation layer; fail on any message.
    #[arg(long)]
    validation: bool,
    /// Hand the plugin each frame's shadow input, so the shadows of moving characters are
    /// tracked and moved (the shadow sub-task). Off by default: on crossing_street, whose short
    /// shadows creep and change shape, it costs more than it gains (docs/quality.md).
    #[arg(long)]
    shadows: bool,
    /// With --shadows, also hand the plugin each generated instant's shadow mask
    /// (PatchexTargetShadowInput) and switch the flow off: the shadows take the shape they have
    /// at that instant, as an engine's extra depth-only pass of its moving casters gives them.
    #[arg(long, requires = "shadows")]
    target_shadows: bool,
    /// Hand the plugin the scene's sun and sky with each frame (PatchexSunLight,
    /// PatchexSkyLight), so that their reflections in glossy surfaces move with the view
    /// instead of sticking to the surface.
    #[arg(long)]
    highlights: bool,
    /// Hand the plugin each frame's translucency mask and motion (PatchexTranslucencyInput), in
    /// scenes with particles, so that smoke and sparks move by their own motion.
    #[arg(long)]
    translucency: bool,
    /// Run the inpainting networks on the FI and near-BE patches (with --shadows,
    /// PATCHEX_PRESET_FULL; the built-in weights). Off by default: the shipped weights barely change the frame yet
    /// (docs/quality.md).
    #[arg(long)]
    networks: bool,
}

struct Row {
    target: usize,
    psnr_extrapolated: f64,
    psnr_frame_t: f64,
    hole_fraction: f32,
    gpu_ms: [f32; PATCHEX_STAGE_SLOTS],
}

pub fn run(args: DemoArgs) -> CommandResult {
    let world = World::load(&args.scene, args.assets.as_deref())?;
    let dataset_dir = args.out.join("dataset");
    let strips_dir = args.out.join("strips");
    std::fs::create_dir_all(&strips_dir)?;

    let gpu = Arc::new(Gpu::new(GpuOptions {
        validation: args.validation,
    })?);
    let bar = ProgressBar::new(args.frames as u64);
    bar.set_style(
        ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len}, {elapsed}")?
            .progress_chars("=> "),
    );
    bar.set_message(format!("rendering {}", world.description.name));
    let options = SequenceOptions {
        targets_between: 1,
        frames: args.frames,
        width: args.size.0,
        height: args.size.1,
        out_dir: dataset_dir.clone(),
    };
    render_sequence(&gpu, &world, &options, &mut |done, _| {
        bar.set_position(done as u64)
    })?;
    bar.finish();
    check_validation(
        args.validation,
        gpu.take_validation_messages(),
        "scene renderer",
    )?;

    let dataset = Dataset::open(&dataset_dir)?;
    let manifest = &dataset.manifest;
    let driver = PluginDriver::new(manifest, args.validation)?;
    let targets: Vec<usize> = manifest
        .frames
        .iter()
        .filter(|f| f.role == FrameRole::Target && f.index > 0)
        .map(|f| f.index)
        .collect();
    let bar = ProgressBar::new(targets.len() as u64);
    bar.set_style(
        ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len}, {elapsed}")?
            .progress_chars("=> "),
    );
    bar.set_message("extrapolating");
    let mut rows = Vec::new();
    for (n, &target) in targets.iter().enumerate() {
        let source_layers = dataset.read_frame(target - 1)?;
        let target_layers = dataset.read_frame(target)?;
        // With shadows, frame t-1 goes first with its shadow input, so the shadows' motion is
        // tracked.
        let earlier_layers = target
            .checked_sub(3)
            .filter(|_| args.shadows)
            .map(|earlier| dataset.read_frame(earlier))
            .transpose()?;
        let earlier = earlier_layers
            .as_ref()
            .map(|layers| (layers, &manifest.frames[target - 3]));
        let result = driver.extrapolate(
            2 * n as u64 + 2,
            (&source_layers, &manifest.frames[target - 1]),
            (&target_layers, &manifest.frames[target]),
            0.5,
            None,
            args.networks.then(NetworkChoice::default).as_ref(),
            false,
            args.shadows.then_some(ShadowRun {
                earlier,
                target_mask: args.target_shadows,
            }),
            FrameExtras {
                sun: args.highlights,
                sky: args.highlights,
                translucency: args.translucency,
                opaque_color: false,
            },
        )?;
        let (width, height) = (manifest.width, manifest.height);
        let frame_t = tone_map(&source_layers.layer(FINAL_IMAGE).data, 3);
        let truth = tone_map(&target_layers.layer(FINAL_IMAGE).data, 3);
        let extrapolated = tone_map(&result.color, 4);
        write_strip(
            &strips_dir.join(format!("target_{target:04}.png")),
            width,
            height,
            &frame_t,
            &extrapolated,
            &truth,
        )?;
        let stats = &result.stats.extrapolations[0];
        rows.push(Row {
            target,
            psnr_extrapolated: psnr(&extrapolated, &truth),
            psnr_frame_t: psnr(&frame_t, &truth),
            hole_fraction: stats.hole_fraction,
            gpu_ms: merged_stage_times(&result.stats),
        });
        bar.inc(1);
    }
    bar.finish();
    check_validation(args.validation, driver.validation_messages(), "plugin")?;

    // The preset whose passes ran: the driver's contexts can do more, and run what is asked.
    let preset = match (args.networks, args.shadows) {
        (false, false) => "warp_only",
        (true, false) => "networks",
        (false, true) => "warp_and_shadows",
        (true, true) => "full",
    };
    let summary = summary_markdown(
        &world.description.name,
        manifest.width,
        manifest.height,
        preset,
        &driver.engine.device_name,
        &rows,
    );
    std::fs::write(args.out.join("summary.md"), &summary)?;
    std::fs::write(
        args.out.join("summary.json"),
        summary_json(&world.description.name, preset, &rows),
    )?;
    println!("{summary}");
    println!("pictures: {}", strips_dir.display());
    Ok(())
}

fn check_validation(enabled: bool, messages: Vec<String>, what: &str) -> CommandResult {
    if enabled && !messages.is_empty() {
        return Err(format!(
            "{what}: {} validation messages, first: {}",
            messages.len(),
            messages[0]
        )
        .into());
    }
    Ok(())
}

/// Submit and extrapolation stages in one array (their indices do not overlap).
fn merged_stage_times(stats: &PatchexFrameStats) -> [f32; PATCHEX_STAGE_SLOTS] {
    let mut merged = stats.submit_gpu_ms;
    for (slot, ms) in merged.iter_mut().zip(stats.extrapolations[0].gpu_ms) {
        *slot += ms;
    }
    merged
}

/// The stages some target ran, in pipeline order.
fn stages_that_ran(rows: &[Row]) -> Vec<(PatchexStage, &'static str)> {
    STAGES
        .into_iter()
        .filter(|stage| rows.iter().any(|r| r.gpu_ms[stage.id as usize] > 0.0))
        .map(|stage| (stage.id, stage.name))
        .collect()
}

fn mean(values: impl Iterator<Item = f64>) -> f64 {
    let (sum, count) = values.fold((0.0, 0), |(s, c), v| (s + v, c + 1));
    sum / count.max(1) as f64
}

fn summary_markdown(
    scene: &str,
    width: usize,
    height: usize,
    preset: &str,
    device: &str,
    rows: &[Row],
) -> String {
    let mut out = String::new();
    writeln!(
        out,
        "## patchex demo: {scene}, {width}x{height}, preset {preset}, on {device}\n"
    )
    .unwrap();
    writeln!(
        out,
        "PSNR (dB) of tone-mapped frames against the rendered ground truth; GPU times from \
         timestamp queries. The mean GPU times leave out the first target, whose times include \
         the driver's lazy shader compilation.\n"
    )
    .unwrap();
    write!(
        out,
        "| target | extrapolated | frame t (no extrapolation) | holes |"
    )
    .unwrap();
    let stages = stages_that_ran(rows);
    for (_, name) in &stages {
        write!(out, " {name} ms |").unwrap();
    }
    writeln!(out).unwrap();
    writeln!(out, "|{}", "---|".repeat(4 + stages.len())).unwrap();
    for row in rows {
        write!(
            out,
            "| {} | {:.2} | {:.2} | {:.2}% |",
            row.target,
            row.psnr_extrapolated,
            row.psnr_frame_t,
            row.hole_fraction * 100.0
        )
        .unwrap();
        for &(stage, _) in &stages {
            write!(out, " {:.2} |", row.gpu_ms[stage as usize]).unwrap();
        }
        writeln!(out).unwrap();
    }
    write!(
        out,
        "| **mean** | **{:.2}** | **{:.2}** | {:.2}% |",
        mean(rows.iter().map(|r| r.psnr_extrapolated)),
        mean(rows.iter().map(|r| r.psnr_frame_t)),
        mean(rows.iter().map(|r| r.hole_fraction as f64)) * 100.0
    )
    .unwrap();
    let warm = if rows.len() > 1 { &rows[1..] } else { rows };
    for &(stage, _) in &stages {
        write!(
            out,
            " {:.2} |",
            mean(warm.iter().map(|r| r.gpu_ms[stage as usize] as f64))
        )
        .unwrap();
    }
    writeln!(out).unwrap();
    out
}

fn summary_json(scene: &str, preset: &str, rows: &[Row]) -> String {
    let rows: Vec<String> = rows
        .iter()
        .map(|r| {
            let stages: Vec<String> =
                stages_that_ran(rows).iter().map(|(s, name)| format!("\"{name}\": {:.4}", r.gpu_ms[*s as usize])).collect();
            format!(
                "    {{\"target\": {}, \"psnr_extrapolated\": {:.4}, \"psnr_frame_t\": {:.4}, \"hole_fraction\": {:.6}, \"gpu_ms\": {{{}}}}}",
                r.target,
                r.psnr_extrapolated,
                r.psnr_frame_t,
                r.hole_fraction,
                stages.join(", ")
            )
        })
        .collect();
    format!("{{\n  \"scene\": \"{scene}\",\n  \"preset\": \"{preset}\",\n  \"targets\": [\n{}\n  ]\n}}\n", rows.join(",\n"))
}
