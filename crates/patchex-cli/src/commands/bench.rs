//! `patchex bench`: the speed-against-accuracy trade, measured. Renders the test scenes at each
//! resolution, runs every configuration of this build on the same targets through the plugin's
//! C ABI (validation off), and writes:
//! - bench.md and bench.json: quality (PSNR, SSIM, FLIP against the rendered target) beside GPU
//!   time per stage, grouped as the PatchEX paper's runtime table does (G-buffer, warping,
//!   preprocessing, inference, blending), and how the time grows with resolution;
//! - trade.png: quality against GPU time, one line per configuration through the resolutions;
//! - the costs of each stage: device memory per configuration, bytes read and written and
//!   arithmetic per pixel, dispatches and barriers, and a lower bound on three GPUs (`costs`);
//!   and what a dispatch and a barrier cost on the device however little they do
//!   (`fixed_costs`).
//!
//! GPU times come from the plugin's timestamp queries. Each configuration runs once on every
//! size before it is measured, so no measurement pays for the driver's lazy compilation, and
//! each measured call first repeats back to back (`--warm-up-ms`), so that a GPU runs it at its
//! full clock. Times
//! on a shared machine move between runs: compare the ratios of one run.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Duration;

use clap::{Args, ValueEnum};
use patchex::abi::*;
use patchex::passes::warp::WarpSettings;
use patchex::passes::{RuntimeGroup, STAGES};
use patchex_harness::{Engine, EngineOptions};
use patchex_scene::dataset::{render_sequence, Dataset, FrameLayers, SequenceOptions, FINAL_IMAGE};
use patchex_scene::{Gpu, GpuOptions, World};
use plotters::prelude::*;
use serde_json::json;

use super::costs::{self, Costs};
use super::fixed_costs::{self, FixedCosts};
use super::metrics::{error_maps, Pooled};
use super::picture::tone_map;
use super::plugin_driver::{FrameExtras, InputFormats, NetworkChoice, PluginDriver, ShadowRun};
use super::render::parse_size;
use super::CommandResult;

/// What the engine can choose in this build: a preset with its knobs, cheapest first.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, ValueEnum)]
pub enum Configuration {
    MotionVector,
    OcclusionMotion,
    Gbuffer,
    /// The G-buffer-guided warp resampling bilinearly everywhere (PATCHEX_RESAMPLE_BILINEAR).
    GbufferBilinear,
    /// The G-buffer-guided warp given the scene's sun (PatchexSunLight): its highlights moved
    /// with the view.
    GbufferHighlights,
    /// The same given the scene's sky as well (PatchexSkyLight): its reflection moved with the
    /// view too.
    GbufferSkyHighlights,
    GbufferShadows,
    /// The shadow sub-task given the target's shadow mask (PatchexTargetShadowInput), its flow
    /// off.
    GbufferTargetShadows,
    /// The networks without the shadow sub-task (PATCHEX_PRESET_NETWORKS).
    PatchexNoShadows,
    /// The full method: G-buffer warp, shadows and the networks on their patches.
    Patchex,
    /// The same networks over the whole frame (the ablation of foveated segmentation).
    PatchexWholeFrame,
    /// The full method with the networks' tensors in FP32 instead of FP16.
    PatchexFp32,
    /// The full method with the networks at half the frame's resolution.
    PatchexHalfResolution,
}

impl Configuration {
    fn label(self) -> &'static str {
        match self {
            Configuration::MotionVector => "motion-vector warp (WARP_ONLY)",
            Configuration::OcclusionMotion => "occlusion-motion-vector warp (WARP_ONLY)",
            Configuration::Gbuffer => "G-buffer-guided warp (WARP_ONLY)",
            Configuration::GbufferBilinear => "G-buffer-guided warp, bilinear (WARP_ONLY)",
            Configuration::GbufferHighlights => "G-buffer-guided warp + sun highlights (WARP_ONLY)",
            Configuration::GbufferSkyHighlights => {
                "G-buffer-guided warp + sun and sky highlights (WARP_ONLY)"
            }
            Configuration::GbufferShadows => "G-buffer-guided warp + shadows (WARP_AND_SHADOWS)",
            Configuration::GbufferTargetShadows => {
                "G-buffer-guided warp + target shadow mask, no flow (WARP_AND_SHADOWS)"
            }
            Configuration::PatchexNoShadows => "warp + networks (NETWORKS)",
            Configuration::Patchex => "PatchEX: warp + shadows + networks (FULL)",
            Configuration::PatchexWholeFrame => "PatchEX, networks over the whole frame (FULL)",
            Configuration::PatchexFp32 => "PatchEX, FP32 tensors (FULL)",
            Configuration::PatchexHalfResolution => "PatchEX, networks at half resolution (FULL)",
        }
    }

    fn warp(self) -> PatchexWarpKind {
        match self {
            Configuration::MotionVector => PATCHEX_WARP_MOTION_VECTOR,
            Configuration::OcclusionMotion => PATCHEX_WARP_OCCLUSION_MOTION_VECTOR,
            _ => PATCHEX_WARP_GBUFFER_GUIDED,
        }
    }

    fn resample(self) -> PatchexResample {
        match self {
            Configuration::GbufferBilinear => PATCHEX_RESAMPLE_BILINEAR,
            _ => PATCHEX_RESAMPLE_CATMULL_ROM,
        }
    }

    fn with_shadows(self) -> bool {
        !matches!(
            self,
            Configuration::MotionVector
                | Configuration::OcclusionMotion
                | Configuration::Gbuffer
                | Configuration::GbufferBilinear
                | Configuration::GbufferHighlights
                | Configuration::GbufferSkyHighlights
                | Configuration::PatchexNoShadows
        )
    }

    fn networks(self) -> Option<NetworkChoice> {
        match self {
            Configuration::Patchex | Configuration::PatchexNoShadows => {
                Some(NetworkChoice::default())
            }
            Configuration::PatchexWholeFrame => Some(NetworkChoice::whole_frame()),
            Configuration::PatchexFp32 => Some(NetworkChoice {
                fp32_tensors: true,
                ..Default::default()
            }),
            Configuration::PatchexHalfResolution => Some(NetworkChoice {
                resolution_divisor: 2,
                ..Default::default()
            }),
            _ => None,
        }
    }

    fn colour(self) -> RGBColor {
        match self {
            Configuration::MotionVector => RGBColor(230, 159, 0),
            Configuration::OcclusionMotion => RGBColor(86, 180, 233),
            Configuration::Gbuffer => RGBColor(0, 158, 115),
            Configuration::GbufferBilinear => RGBColor(100, 200, 160),
            Configuration::GbufferHighlights => RGBColor(0, 110, 80),
            Configuration::GbufferSkyHighlights => RGBColor(0, 70, 50),
            Configuration::GbufferShadows => RGBColor(204, 121, 167),
            Configuration::GbufferTargetShadows => RGBColor(150, 60, 120),
            Configuration::PatchexNoShadows => RGBColor(0, 0, 0),
            Configuration::Patchex => RGBColor(213, 94, 0),
            Configuration::PatchexWholeFrame => RGBColor(0, 114, 178),
            Configuration::PatchexFp32 => RGBColor(120, 60, 20),
            Configuration::PatchexHalfResolution => RGBColor(240, 228, 66),
        }
    }
}

#[derive(Args)]
pub struct BenchArgs {
    /// Scene files (TOML) to render and measure; by default the test scenes, which the shipped
    /// networks never saw in training.
    #[arg(
        long,
        value_delimiter = ',',
        default_values_os_t = ["scenes/crossing_street.toml", "scenes/fast_run.toml"]
            .map(super::shipped_path)
    )]
    scenes: Vec<PathBuf>,
    /// Resolutions, WIDTHxHEIGHT.
    #[arg(
        long,
        value_delimiter = ',',
        value_parser = parse_size,
        default_value = "640x360,854x480,1280x720,1920x1080"
    )]
    sizes: Vec<(u32, u32)>,
    /// Configurations to compare.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "motion-vector,occlusion-motion,gbuffer-bilinear,gbuffer,gbuffer-highlights,gbuffer-shadows,gbuffer-target-shadows,patchex-no-shadows,patchex,patchex-half-resolution,patchex-whole-frame"
    )]
    configurations: Vec<Configuration>,
    /// Frames of the doubled stream rendered per scene and size; targets are the odd frames
    /// from 3 on (each needs frames t-1 and t).
    #[arg(long, default_value_t = 7)]
    frames: usize,
    /// Output folder: datasets/, bench.md, bench.json, trade.png.
    #[arg(long, default_value = "out/bench")]
    out: PathBuf,
    /// How the engine's images hold the G-buffer: float32 (the rendered values exactly, as eval
    /// uses) or engine (a deferred renderer's formats), which decides the bytes the inputs cost.
    #[arg(long, value_enum, default_value_t = InputFormats::Float32)]
    input_formats: InputFormats,
    /// Network texels a patch may span per axis (`PatchexNetworkMemory.max_patch_side`) for the
    /// configurations on patches; the library's default (256) without it. The whole-frame
    /// ablation always holds the whole frame.
    #[arg(long)]
    max_patch_side: Option<u32>,
    /// Milliseconds each measured call first repeats back to back. A GPU idle between calls
    /// (the bench scores each on the CPU) runs at its idle clock; a game's steady load keeps it
    /// at full clock, which the warm-up reproduces. 0 measures calls from idle.
    #[arg(long, default_value_t = 500)]
    warm_up_ms: u64,
    /// A TrueType font for the plot's text.
    #[arg(
        long,
        default_value = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"
    )]
    font: PathBuf,
}

/// The device the plugin ran on, and what a command costs there however little it does.
struct MeasuredDevice {
    name: String,
    fixed_costs: FixedCosts,
}

/// One configuration at one size, over every scene's targets.
#[derive(Clone, Default)]
struct Measured {
    quality: Pooled,
    /// GPU time, traffic and memory per stage.
    costs: Costs,
    /// Fraction of target pixels in FI and near-BE, summed over targets.
    dynamic_fraction: f64,
}

impl Measured {
    fn mean_group_ms(&self, group: RuntimeGroup) -> f64 {
        STAGES
            .iter()
            .filter(|stage| stage.group == group)
            .map(|stage| self.costs.mean(stage.id).gpu_ms)
            .sum()
    }

    fn mean_total_ms(&self) -> f64 {
        RuntimeGroup::TABLE
            .iter()
            .map(|&group| self.mean_group_ms(group))
            .sum()
    }
}

pub fn run(args: BenchArgs) -> CommandResult {
    let mut configurations = args.configurations.clone();
    configurations.sort();
    configurations.dedup();
    std::fs::create_dir_all(&args.out)?;
    let gpu = Arc::new(Gpu::new(GpuOptions { validation: false })?);
    // results[size][configuration]
    let mut results = vec![vec![Measured::default(); configurations.len()]; args.sizes.len()];
    for scene in &args.scenes {
        let world = World::load(scene, None)?;
        for (size_index, &(width, height)) in args.sizes.iter().enumerate() {
            let dir = args
                .out
                .join("datasets")
                .join(format!("{}_{width}x{height}", world.description.name));
            eprintln!("rendering {} at {width}x{height}", world.description.name);
            render_sequence(
                &gpu,
                &world,
                &SequenceOptions {
                    targets_between: 1,
                    frames: args.frames,
                    width,
                    height,
                    out_dir: dir.clone(),
                },
                &mut |_, _| {},
            )?;
            eprintln!("measuring");
            measure(
                &dir,
                args.input_formats,
                Duration::from_millis(args.warm_up_ms),
                args.max_patch_side,
                &configurations,
                &mut results[size_index],
            )?;
        }
    }
    eprintln!("measuring the fixed cost of a dispatch and of a barrier");
    // The device the driver picks for the plugin (validation off, as for the measurements).
    let engine = Engine::new(&EngineOptions {
        validation: false,
        ..EngineOptions::default()
    })?;
    let device = MeasuredDevice {
        fixed_costs: fixed_costs::measure(&engine, Duration::from_millis(args.warm_up_ms))?,
        name: engine.device_name.clone(),
    };
    let markdown = report(&args, &device, &configurations, &results);
    std::fs::write(args.out.join("bench.md"), &markdown)?;
    std::fs::write(
        args.out.join("bench.json"),
        serde_json::to_string_pretty(&report_json(&args, &device, &configurations, &results))?
            + "\n",
    )?;
    // The tables are the measurement; a machine without the plot's font still gets them.
    if let Err(error) = plot(
        &args.out.join("trade.png"),
        &args.font,
        &args.sizes,
        &configurations,
        &results,
    ) {
        eprintln!("warning: trade.png not written: {error}");
    }
    println!("{markdown}");
    println!("written: {}", args.out.display());
    Ok(())
}

/// Runs every configuration on every target of one dataset.
fn measure(
    dir: &Path,
    input_formats: InputFormats,
    warm_up: Duration,
    max_patch_side: Option<u32>,
    configurations: &[Configuration],
    results: &mut [Measured],
) -> CommandResult {
    let dataset = Dataset::open(dir)?;
    let manifest = &dataset.manifest;
    let targets: Vec<usize> = (3..manifest.frames.len()).step_by(2).collect();
    if targets.is_empty() {
        return Err(format!("{}: fewer than 4 frames", dir.display()).into());
    }
    let driver = PluginDriver::new(manifest, false)?
        .with_input_formats(input_formats)
        .with_warm_up(warm_up);
    let read = |index: usize| dataset.read_frame(index);
    let mut frame_index = 0;
    let mut run = |configuration: Configuration,
                   earlier: &FrameLayers,
                   source: &FrameLayers,
                   target: &FrameLayers,
                   index: usize| {
        frame_index += 2;
        let shadows = configuration.with_shadows();
        let networks = configuration
            .networks()
            .map(|networks| networks.or_max_patch_side(max_patch_side));
        driver.extrapolate(
            frame_index,
            (source, &manifest.frames[index - 1]),
            (target, &manifest.frames[index]),
            0.5,
            Some(WarpSettings {
                kind: configuration.warp(),
                resample: configuration.resample(),
                ..WarpSettings::default()
            }),
            networks.as_ref(),
            false,
            shadows.then_some(ShadowRun {
                earlier: Some((earlier, &manifest.frames[index - 3])),
                target_mask: configuration == Configuration::GbufferTargetShadows,
            }),
            FrameExtras {
                sun: matches!(
                    configuration,
                    Configuration::GbufferHighlights | Configuration::GbufferSkyHighlights
                ),
                sky: configuration == Configuration::GbufferSkyHighlights,
                translucency: false,
                opaque_color: false,
            },
        )
    };
    // One unmeasured run of each configuration: the driver compiles shaders lazily.
    let (earlier, source, target) = (read(0)?, read(2)?, read(3)?);
    for &configuration in configurations {
        run(configuration, &earlier, &source, &target, 3)?;
    }
    let (width, height) = (manifest.width, manifest.height);
    for &index in &targets {
        let (earlier, source, target) = (read(index - 3)?, read(index - 1)?, read(index)?);
        let truth = tone_map(&target.layer(FINAL_IMAGE).data, 3);
        for (&configuration, measured) in configurations.iter().zip(results.iter_mut()) {
            let result = run(configuration, &earlier, &source, &target, index)?;
            let maps = error_maps(&truth, &tone_map(&result.color, 4), width, height);
            for pixel in 0..width * height {
                measured.quality.add(&maps, pixel);
            }
            measured.costs.add(&result.stats);
            let extrapolation = &result.stats.extrapolations[0];
            measured.dynamic_fraction +=
                (extrapolation.fi_fraction + extrapolation.near_be_fraction) as f64;
        }
    }
    Ok(())
}

fn size_label(size: (u32, u32)) -> String {
    format!("{}p", size.1)
}

fn report(
    args: &BenchArgs,
    device: &MeasuredDevice,
    configurations: &[Configuration],
    results: &[Vec<Measured>],
) -> String {
    let mut out = String::new();
    let scenes: Vec<String> = args
        .scenes
        .iter()
        .map(|s| {
            s.file_stem()
                .unwrap_or_default()
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    writeln!(
        out,
        "Every configuration on {}, on the same targets of {} ({} frames each, targets from frame 3 \
         on, alpha 0.5, the G-buffer in {:?} formats, the networks' patches up to {} texels a \
         side, the whole-frame ablation's the whole frame), quality of the tone-mapped frame against the rendered \
         target; GPU ms per target from timestamp queries (submit plus extrapolation, each \
         call repeated back to back for {} ms first), grouped as the PatchEX runtime table.\n",
        device.name,
        scenes.join(" and "),
        args.frames,
        args.input_formats,
        args.max_patch_side
            .unwrap_or(PATCHEX_DEFAULT_NETWORK_MAX_PATCH_SIDE),
        args.warm_up_ms,
    )
    .unwrap();
    write!(out, "| size | configuration | PSNR dB | SSIM | FLIP |").unwrap();
    for group in RuntimeGroup::TABLE {
        write!(out, " {} ms |", group.name()).unwrap();
    }
    writeln!(
        out,
        " total ms |\n|{}",
        "---|".repeat(6 + RuntimeGroup::TABLE.len())
    )
    .unwrap();
    for (size, row) in args.sizes.iter().zip(results) {
        for (configuration, measured) in configurations.iter().zip(row) {
            let Some(scores) = measured.quality.scores() else {
                continue;
            };
            write!(
                out,
                "| {} | {} | {:.2} | {:.4} | {:.4} |",
                size_label(*size),
                configuration.label(),
                scores.psnr,
                scores.ssim,
                scores.flip
            )
            .unwrap();
            for group in RuntimeGroup::TABLE {
                write!(out, " {:.1} |", measured.mean_group_ms(group)).unwrap();
            }
            writeln!(out, " {:.1} |", measured.mean_total_ms()).unwrap();
        }
    }
    writeln!(
        out,
        "\nGrowth with resolution: total time at each size over the time at {}, against the \
         ratio of pixels.\n",
        size_label(args.sizes[0])
    )
    .unwrap();
    write!(out, "| configuration |").unwrap();
    for size in &args.sizes {
        write!(out, " {} |", size_label(*size)).unwrap();
    }
    writeln!(out, "\n|{}", "---|".repeat(1 + args.sizes.len())).unwrap();
    let base_pixels = (args.sizes[0].0 * args.sizes[0].1) as f64;
    write!(out, "| pixels |").unwrap();
    for size in &args.sizes {
        write!(out, " {:.2}x |", (size.0 * size.1) as f64 / base_pixels).unwrap();
    }
    writeln!(out).unwrap();
    for (c, configuration) in configurations.iter().enumerate() {
        let base = results[0][c].mean_total_ms();
        write!(out, "| {} |", configuration.label()).unwrap();
        for row in results {
            write!(out, " {:.2}x |", row[c].mean_total_ms() / base).unwrap();
        }
        writeln!(out).unwrap();
    }
    let dynamic = results[0]
        .first()
        .map_or(0.0, |m| m.dynamic_fraction / m.costs.targets.max(1) as f64);
    writeln!(
        out,
        "\nDynamic content (FI plus near-BE) covers {:.1}% of the target pixels on average. \
         Inference and the blend run over the patches around it; every other pass runs over the \
         whole frame.",
        100.0 * dynamic
    )
    .unwrap();
    fill_share_table(&mut out, args, configurations, results);
    resample_table(&mut out, args, configurations, results);
    patch_ratio_table(&mut out, args, configurations, results);
    let labels: Vec<&str> = configurations.iter().map(|c| c.label()).collect();
    let costs: Vec<Vec<Costs>> = results
        .iter()
        .map(|row| row.iter().map(|m| m.costs.clone()).collect())
        .collect();
    costs::report(&mut out, &args.sizes, &labels, &costs, args.sizes.len() - 1);
    let fixed = device.fixed_costs;
    let barrier = if fixed.barrier_us >= 0.0 {
        format!("{:.2} µs more for a barrier", fixed.barrier_us)
    } else {
        // Where a barrier costs next to nothing, the noise can take the difference below zero.
        format!(
            "no measurable cost for a barrier ({:.2} µs, within the noise)",
            fixed.barrier_us
        )
    };
    writeln!(
        out,
        "\nFixed costs on {}, measured: {:.2} µs per dispatch among independent one-workgroup \
         dispatches, and {barrier} on the dispatch before ({} of each, timestamp queries, the \
         median of {} runs after the warm-up). The bounds above take {:.0} µs for each.",
        device.name,
        fixed.dispatch_us,
        fixed_costs::CHAIN,
        fixed_costs::RUNS,
        costs::SECONDS_PER_DISPATCH * 1e6,
    )
    .unwrap();
    out
}

/// What the hole fill adds to the default warp-only preset, per size: its stage's time over the
/// rest of the preset's, in the same run.
fn fill_share_table(
    out: &mut String,
    args: &BenchArgs,
    configurations: &[Configuration],
    results: &[Vec<Measured>],
) {
    let Some(warp_only) = configurations
        .iter()
        .position(|c| *c == Configuration::Gbuffer)
    else {
        return;
    };
    writeln!(
        out,
        "\nThe hole fill (its own stage) against the rest of the G-buffer-guided warp-only \
         preset, GPU ms per target, measured in this run:\n\n\
         | size | hole fill ms | rest of the preset ms | fill / rest |\n|---|---|---|---|"
    )
    .unwrap();
    for (size, row) in args.sizes.iter().zip(results) {
        let measured = &row[warp_only];
        let fill = measured.costs.mean(PATCHEX_STAGE_FILL_HOLES).gpu_ms;
        let rest = measured.mean_total_ms() - fill;
        writeln!(
            out,
            "| {} | {fill:.1} | {rest:.1} | {:.1}% |",
            size_label(*size),
            100.0 * fill / rest
        )
        .unwrap();
    }
}

/// Where both `wanted` configurations sit among those measured, if both were.
fn positions(configurations: &[Configuration], wanted: [Configuration; 2]) -> Option<[usize; 2]> {
    let find = |wanted| configurations.iter().position(|c| *c == wanted);
    Some([find(wanted[0])?, find(wanted[1])?])
}

/// The warp stage with Catmull-Rom on static surfaces (the default) against bilinear
/// everywhere, per size: the resampling's price and what it buys.
fn resample_table(
    out: &mut String,
    args: &BenchArgs,
    configurations: &[Configuration],
    results: &[Vec<Measured>],
) {
    let Some([sharp, bilinear]) = positions(
        configurations,
        [Configuration::Gbuffer, Configuration::GbufferBilinear],
    ) else {
        return;
    };
    writeln!(
        out,
        "\nThe warp stage with Catmull-Rom on static surfaces (the default) against bilinear \
         everywhere, GPU ms per target, measured in this run, and the change in quality:\n\n\
         | size | Catmull-Rom ms | bilinear ms | Catmull-Rom / bilinear | PSNR change dB | FLIP change |\n\
         |---|---|---|---|---|---|"
    )
    .unwrap();
    for (size, row) in args.sizes.iter().zip(results) {
        let warp_ms = |measured: &Measured| measured.costs.mean(PATCHEX_STAGE_WARP).gpu_ms;
        let (Some(with), Some(without)) =
            (row[sharp].quality.scores(), row[bilinear].quality.scores())
        else {
            continue;
        };
        writeln!(
            out,
            "| {} | {:.1} | {:.1} | {:.2} | {:+.2} | {:+.4} |",
            size_label(*size),
            warp_ms(&row[sharp]),
            warp_ms(&row[bilinear]),
            warp_ms(&row[sharp]) / warp_ms(&row[bilinear]),
            with.psnr - without.psnr,
            with.flip - without.flip,
        )
        .unwrap();
    }
}

/// Inference time of the networks over the whole frame against on their patches, per size:
/// what foveated segmentation saves.
fn patch_ratio_table(
    out: &mut String,
    args: &BenchArgs,
    configurations: &[Configuration],
    results: &[Vec<Measured>],
) {
    let Some([patches, whole]) = positions(
        configurations,
        [Configuration::Patchex, Configuration::PatchexWholeFrame],
    ) else {
        return;
    };
    let inference = RuntimeGroup::Inference;
    writeln!(
        out,
        "\nNetwork inference on the patches against the same networks over the whole frame, \
         GPU ms per target, measured in this run:\n\n\
         | size | patches ms | whole frame ms | whole frame / patches |\n|---|---|---|---|"
    )
    .unwrap();
    for (size, row) in args.sizes.iter().zip(results) {
        let (on_patches, on_frame) = (
            row[patches].mean_group_ms(inference),
            row[whole].mean_group_ms(inference),
        );
        writeln!(
            out,
            "| {} | {on_patches:.1} | {on_frame:.1} | {:.1}x |",
            size_label(*size),
            on_frame / on_patches
        )
        .unwrap();
    }
}

fn report_json(
    args: &BenchArgs,
    device: &MeasuredDevice,
    configurations: &[Configuration],
    results: &[Vec<Measured>],
) -> serde_json::Value {
    let rows: Vec<_> = args
        .sizes
        .iter()
        .zip(results)
        .flat_map(|(size, row)| {
            configurations
                .iter()
                .zip(row)
                .map(move |(configuration, measured)| {
                    let scores = measured.quality.scores();
                    json!({
                        "width": size.0,
                        "height": size.1,
                        "configuration": format!("{configuration:?}"),
                        "label": configuration.label(),
                        "psnr": scores.map(|s| s.psnr),
                        "ssim": scores.map(|s| s.ssim),
                        "flip": scores.map(|s| s.flip),
                        "targets": measured.costs.targets,
                        "gpu_ms": RuntimeGroup::TABLE
                            .iter()
                            .map(|&g| (g.name().to_string(), json!(measured.mean_group_ms(g))))
                            .collect::<serde_json::Map<_, _>>(),
                        "total_gpu_ms": measured.mean_total_ms(),
                        "costs": costs::json(&measured.costs, (size.0 * size.1) as f64),
                    })
                })
        })
        .collect();
    json!({
        "device": device.name,
        "fixed_costs_us": {
            "dispatch": device.fixed_costs.dispatch_us,
            "barrier": device.fixed_costs.barrier_us,
        },
        "frames": args.frames,
        "warm_up_ms": args.warm_up_ms,
        "rows": rows,
    })
}

/// PSNR against total GPU time; one line per configuration through the sizes, each point
/// labelled with its size.
fn plot(
    path: &Path,
    font: &Path,
    sizes: &[(u32, u32)],
    configurations: &[Configuration],
    results: &[Vec<Measured>],
) -> CommandResult {
    let font_bytes = std::fs::read(font).map_err(|e| {
        format!(
            "{}: {e} (install fonts-dejavu-core or pass --font)",
            font.display()
        )
    })?;
    let font_bytes: &'static [u8] = Box::leak(font_bytes.into_boxed_slice());
    plotters::style::register_font("sans-serif", FontStyle::Normal, font_bytes)
        .map_err(|_| format!("{}: not a usable TrueType font", font.display()))?;
    let points: Vec<(f64, f64)> = results
        .iter()
        .flatten()
        .filter_map(|m| m.quality.scores().map(|s| (m.mean_total_ms(), s.psnr)))
        .collect();
    let max_ms = points.iter().fold(0.0f64, |hi, p| hi.max(p.0));
    let (min_db, max_db) = points.iter().fold((f64::MAX, f64::MIN), |(lo, hi), p| {
        (lo.min(p.1), hi.max(p.1))
    });

    let root = BitMapBackend::new(path, (1200, 720)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "Quality against GPU time (lavapipe), per configuration and resolution",
            ("sans-serif", 26),
        )
        .margin(20)
        .x_label_area_size(50)
        .y_label_area_size(70)
        .build_cartesian_2d(0.0..(max_ms * 1.1), (min_db - 1.0)..(max_db + 1.0))?;
    chart
        .configure_mesh()
        .x_label_formatter(&|ms| format!("{ms:.0}"))
        .light_line_style(WHITE)
        .x_desc("GPU ms per extrapolated frame (submit + extrapolation)")
        .y_desc("PSNR dB against the rendered target")
        .label_style(("sans-serif", 16))
        .draw()?;
    for (c, configuration) in configurations.iter().enumerate() {
        let colour = configuration.colour();
        let series: Vec<(f64, f64, String)> = sizes
            .iter()
            .zip(results)
            .filter_map(|(size, row)| {
                row[c]
                    .quality
                    .scores()
                    .map(|s| (row[c].mean_total_ms(), s.psnr, size_label(*size)))
            })
            .collect();
        chart
            .draw_series(LineSeries::new(
                series.iter().map(|(x, y, _)| (*x, *y)),
                colour.stroke_width(3),
            ))?
            .label(configuration.label())
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 24, y)], colour.stroke_width(3))
            });
        chart.draw_series(series.iter().map(|(x, y, label)| {
            EmptyElement::at((*x, *y))
                + Circle::new((0, 0), 5, colour.filled())
                + Text::new(label.clone(), (6, -18), ("sans-serif", 15))
        }))?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerRight)
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .label_font(("sans-serif", 18))
        .draw()?;
    root.present()?;
    Ok(())
}
