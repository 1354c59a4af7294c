//! `patchex eval DATASET... [--methods ...]`: extrapolates every target frame of each dataset
//! with each method and scores it against the rendered ground truth: PSNR, SSIM and FLIP on
//! the tone-mapped result, over the whole frame and over holes, FI and near-BE separately, plus
//! GPU time from timestamp queries. Writes eval.md, eval.json and a picture strip per dataset.
//!
//! Every method is scored over the same pixels: the regions are the plugin's (they depend only
//! on the target's G-buffers), and the holes are those of the default G-buffer-guided warp.
//!
//! The network methods (PatchEX and its ablations) are meant for the test scenes, which the
//! shipped networks never saw in training (assets/networks/manifest.json).

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use nv_flip::{magma_lut, FlipImageFloat};
use patchex::abi::*;
use patchex::passes::segmentation::{REGION_FI, REGION_NEAR_BE};
use patchex::passes::warp::WarpSettings;
use patchex::passes::{RuntimeGroup, STAGES};
use patchex_scene::dataset::{
    write_exr, Dataset, FrameLayers, FrameRole, LayerImage, FINAL_IMAGE,
    FINAL_IMAGE_NO_DYNAMIC_SHADOWS, FINAL_IMAGE_OPAQUE, FINAL_IMAGE_OPAQUE_NO_DYNAMIC_SHADOWS,
    ROUGHNESS, SHADOW_MASK, SPECULAR_LIGHT, TRANSLUCENCY_MASK,
};
use serde_json::json;

use super::interpolate::interpolate;
use super::metrics::{error_maps, luma, ErrorMaps, Pooled};
use super::picture::{to_rgb8, tone_map, write_grid};
use super::plugin_driver::{FrameExtras, NetworkChoice, PluginDriver, ShadowRun};
use super::{shipped_path, CommandResult};
use patchex_scene::render::post::post_process;

#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, ValueEnum)]
pub enum Method {
    /// Frame t shown again: no extrapolation.
    Copy,
    MotionVector,
    OcclusionMotion,
    Gbuffer,
    /// The default warp with its holes filled by the nearest source texel
    /// (`PATCHEX_HOLE_FILL_NEAREST`), for comparison.
    GbufferNearestFill,
    /// The default warp resampling frame t bilinearly everywhere (`PATCHEX_RESAMPLE_BILINEAR`).
    GbufferBilinear,
    /// The default warp with the shadow sub-task: shadows of dynamic objects separated, tracked
    /// by optical flow and moved.
    GbufferShadows,
    /// The default warp with the shadow sub-task given the target's shadow mask
    /// (`PatchexTargetShadowInput`): the shadows placed where they are at the target.
    GbufferTargetShadows,
    /// The default warp given the scene's sun (`PatchexSunLight`): its highlights taken out of
    /// frame t and evaluated for the target's view.
    GbufferSunHighlights,
    /// The default warp given the scene's sun and sky (`PatchexSunLight`, `PatchexSkyLight`):
    /// the sun's highlights and the sky's reflection taken out of frame t and evaluated for the
    /// target's view.
    GbufferHighlights,
    /// The default warp given each frame's translucency mask and motion
    /// (`PatchexTranslucencyInput`): what is drawn over the surfaces moved by its own motion.
    GbufferTranslucency,
    /// The translucency mask and motion with frame t's colour before the translucency pass
    /// (`PatchexTranslucencyInput.opaque_color`): the layer taken apart exactly.
    GbufferTranslucencyOpaque,
    /// The default warp called before the engine's translucency pass: given frame t's lit colour
    /// before translucency, its output gets the target's translucency drawn over it, as the
    /// engine draws it over a rendered frame.
    GbufferBeforeTranslucency,
    /// The shadow sub-task and the sun's and sky's highlights: every input an engine has
    /// without an extra pass.
    GbufferShadowsHighlights,
    /// The target shadow mask and the sun's and sky's highlights.
    GbufferTargetShadowsHighlights,
    /// The shadow sub-task and the sun's and sky's highlights, called before the engine's
    /// translucency pass: every input an engine has without an extra pass, where the
    /// integration guide places the call.
    GbufferShadowsHighlightsBeforeTranslucency,
    /// PatchEX: the G-buffer-guided warp, the shadow sub-task and the inpainting networks on
    /// the FI and near-BE patches (PATCHEX_PRESET_FULL).
    Patchex,
    /// PatchEX with the paper's blend: the networks' corrections over every pixel of their
    /// regions, not only the warp's holes.
    PatchexEveryPixel,
    /// Ablation: PatchEX without shadow separation.
    PatchexNoShadows,
    /// Ablation: PatchEX without foveated segmentation (the FI network over the whole frame).
    PatchexWholeFrame,
    /// Ablation: PatchEX with networks trained without the perceptual and style terms
    /// (`--no-perceptual-weights`).
    PatchexNoPerceptual,
    /// Bidirectional interpolation with frame t+1, a frame of latency: what the future frame adds.
    Interpolation,
}

impl Method {
    /// The method's name on the command line, which also names its folder of frames.
    fn name(self) -> String {
        self.to_possible_value()
            .expect("every method has a name")
            .get_name()
            .to_string()
    }

    fn label(self) -> &'static str {
        match self {
            Method::Copy => "copy of frame t",
            Method::MotionVector => "motion-vector warp",
            Method::OcclusionMotion => "occlusion-motion-vector warp",
            Method::Gbuffer => "G-buffer-guided warp (default)",
            Method::GbufferNearestFill => "G-buffer-guided warp, holes from the nearest texel",
            Method::GbufferBilinear => "G-buffer-guided warp, bilinear resampling",
            Method::GbufferShadows => "G-buffer-guided warp + shadow sub-task",
            Method::GbufferTargetShadows => "G-buffer-guided warp + target shadow mask",
            Method::GbufferSunHighlights => "G-buffer-guided warp + sun highlights",
            Method::GbufferHighlights => "G-buffer-guided warp + sun and sky highlights",
            Method::GbufferTranslucency => "G-buffer-guided warp + translucency mask",
            Method::GbufferTranslucencyOpaque => {
                "G-buffer-guided warp + translucency mask and opaque colour"
            }
            Method::GbufferBeforeTranslucency => {
                "G-buffer-guided warp before the translucency pass"
            }
            Method::GbufferShadowsHighlights => {
                "G-buffer-guided warp + shadow sub-task + sun and sky highlights"
            }
            Method::GbufferTargetShadowsHighlights => {
                "G-buffer-guided warp + target shadow mask + sun and sky highlights"
            }
            Method::GbufferShadowsHighlightsBeforeTranslucency => {
                "G-buffer-guided warp + shadow sub-task + sun and sky highlights, before the translucency pass"
            }
            Method::Patchex => "PatchEX (warp + shadows + networks on patches)",
            Method::PatchexEveryPixel => {
                "PatchEX, corrections over every pixel (the paper's blend)"
            }
            Method::PatchexNoShadows => "PatchEX without shadow separation",
            Method::PatchexWholeFrame => "PatchEX without foveated segmentation",
            Method::PatchexNoPerceptual => "PatchEX without the perceptual term",
            Method::Interpolation => "interpolation (uses frame t+1)",
        }
    }

    fn warp(self) -> Option<WarpSettings> {
        let kind = match self {
            Method::MotionVector => PATCHEX_WARP_MOTION_VECTOR,
            Method::OcclusionMotion => PATCHEX_WARP_OCCLUSION_MOTION_VECTOR,
            Method::GbufferNearestFill => {
                return Some(WarpSettings {
                    hole_fill: PATCHEX_HOLE_FILL_NEAREST,
                    ..WarpSettings::default()
                })
            }
            Method::GbufferBilinear => {
                return Some(WarpSettings {
                    resample: PATCHEX_RESAMPLE_BILINEAR,
                    ..WarpSettings::default()
                })
            }
            Method::Gbuffer
            | Method::GbufferShadows
            | Method::GbufferTargetShadows
            | Method::GbufferSunHighlights
            | Method::GbufferHighlights
            | Method::GbufferTranslucency
            | Method::GbufferTranslucencyOpaque
            | Method::GbufferBeforeTranslucency
            | Method::GbufferShadowsHighlights
            | Method::GbufferTargetShadowsHighlights
            | Method::GbufferShadowsHighlightsBeforeTranslucency
            | Method::Patchex
            | Method::PatchexEveryPixel
            | Method::PatchexNoShadows
            | Method::PatchexWholeFrame
            | Method::PatchexNoPerceptual => PATCHEX_WARP_GBUFFER_GUIDED,
            Method::Copy | Method::Interpolation => return None,
        };
        Some(WarpSettings {
            kind,
            ..WarpSettings::default()
        })
    }

    /// With the shadow sub-task: whether the target's shadow mask goes with it.
    fn shadows(self) -> Option<bool> {
        match self {
            Method::GbufferShadows
            | Method::GbufferShadowsHighlights
            | Method::GbufferShadowsHighlightsBeforeTranslucency
            | Method::Patchex
            | Method::PatchexEveryPixel
            | Method::PatchexWholeFrame
            | Method::PatchexNoPerceptual => Some(false),
            Method::GbufferTargetShadows | Method::GbufferTargetShadowsHighlights => Some(true),
            _ => None,
        }
    }

    /// What frame t goes with besides the shadow sub-task's inputs.
    fn extras(self) -> FrameExtras {
        let sky = matches!(
            self,
            Method::GbufferHighlights
                | Method::GbufferShadowsHighlights
                | Method::GbufferTargetShadowsHighlights
                | Method::GbufferShadowsHighlightsBeforeTranslucency
        );
        FrameExtras {
            sun: sky || self == Method::GbufferSunHighlights,
            sky,
            translucency: matches!(
                self,
                Method::GbufferTranslucency | Method::GbufferTranslucencyOpaque
            ),
            opaque_color: self == Method::GbufferTranslucencyOpaque,
        }
    }

    /// Whether the method is given frame t's colour before the engine's translucency pass, and
    /// its output gets the target's translucency drawn over it.
    fn before_translucency(self) -> bool {
        matches!(
            self,
            Method::GbufferBeforeTranslucency | Method::GbufferShadowsHighlightsBeforeTranslucency
        )
    }

    /// The inpainting networks the method runs, if any.
    fn networks(self, args: &EvalArgs) -> Option<NetworkChoice> {
        let choice = match self {
            Method::Patchex | Method::PatchexNoShadows => Some(NetworkChoice::default()),
            Method::PatchexEveryPixel => Some(NetworkChoice {
                correct_valid_pixels: true,
                ..Default::default()
            }),
            Method::PatchexWholeFrame => Some(NetworkChoice::whole_frame()),
            Method::PatchexNoPerceptual => Some(NetworkChoice {
                weights: Some(args.no_perceptual_weights.clone()),
                ..Default::default()
            }),
            _ => None,
        };
        choice.map(|choice| choice.or_max_patch_side(args.max_patch_side))
    }
}

#[derive(Args)]
pub struct EvalArgs {
    /// Dataset folders written by `patchex render`.
    #[arg(required = true)]
    datasets: Vec<PathBuf>,
    /// Methods to compare.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "copy,motion-vector,occlusion-motion,gbuffer,gbuffer-shadows,interpolation"
    )]
    methods: Vec<Method>,
    /// Output folder: eval.md, eval.json, strips/.
    #[arg(long, default_value = "out/eval")]
    out: PathBuf,
    /// Dataset frame shown in each strip; the middle target by default.
    #[arg(long)]
    strip_frame: Option<usize>,
    /// Run the plugin under the Vulkan validation layer; fail on any message.
    #[arg(long)]
    validation: bool,
    /// Weights of the ablation without the perceptual term (fi.safetensors, near_be.safetensors);
    /// by default the repository's, wherever the tool runs from.
    #[arg(long, default_value_os_t = shipped_path("assets/networks/ablations/no_perceptual"))]
    no_perceptual_weights: PathBuf,
    /// Network texels a patch may span per axis (`PatchexNetworkMemory.max_patch_side`) for the
    /// methods on patches; the library's default without it.
    #[arg(long)]
    max_patch_side: Option<u32>,
    /// The engine's post-processing (bloom, then tone mapping), and where patchex sits in it:
    /// every frame is scored as the player sees it after post.
    #[arg(long, value_enum, default_value_t)]
    post: PostPlacement,
    /// Also write every method's output, linear as scored, to
    /// OUT/frames/SCENE/METHOD/TARGET.exr (one "FinalImage" layer, R G B), so that other tools
    /// can score them.
    #[arg(long)]
    write_frames: bool,
}

/// Where patchex sits relative to the engine's post-processing (`patchex_scene::render::post`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum PostPlacement {
    /// No post-processing: frames are scored after the eval's own tone mapping.
    #[default]
    None,
    /// On HDR colour before post, as the header asks: the engine runs its post-processing on the
    /// generated frame.
    Before,
    /// On the colour after post-processing, display values: the engine hands over what it
    /// would show.
    After,
}

/// Replaces a frame's colours by what the engine's post-processing makes of them.
fn post_process_colour(layers: &mut FrameLayers) {
    let (width, height) = (layers.width, layers.height);
    for name in [FINAL_IMAGE, FINAL_IMAGE_NO_DYNAMIC_SHADOWS] {
        if let Some(layer) = layers.get_mut(name) {
            layer.data = post_process(&layer.data, 3, width, height);
        }
    }
}

/// A pixel is in a dynamic object's shadow where the mask is below this.
const SHADOWED: f32 = 0.95;

/// A highlight: a target pixel of roughness below HIGHLIGHT_ROUGHNESS whose colour takes at
/// least HIGHLIGHT_SHARE of its luminance from specular reflection.
const HIGHLIGHT_ROUGHNESS: f32 = 0.5;
const HIGHLIGHT_SHARE: f32 = 0.3;

/// A pixel is covered by translucency where its mask is above this.
const TRANSLUCENT: f32 = 0.02;

/// Regions every score is pooled over. "shadows": where frame t or the target has a shadow of
/// a dynamic object (mask below 0.95), the pixels the shadow sub-task is for. "highlights": the
/// target's highlights, where the shading depends on the view (none in a dataset without the
/// SpecularLight layer).
const REGIONS: [&str; 7] = [
    "frame",
    "holes",
    "FI",
    "near-BE",
    "shadows",
    "highlights",
    "translucency",
];
/// The regions after FI and near-BE: each a mask of its own (`RegionMasks`).
const MASKED_REGIONS: std::ops::Range<usize> = 4..REGION_COUNT;
const REGION_COUNT: usize = REGIONS.len();

/// Scores and times of one method on one dataset (or on all).
#[derive(Clone, Default)]
struct MethodResult {
    pooled: [Pooled; REGION_COUNT],
    /// The whole frame, by target instant: (numerator, denominator) of alpha.
    by_alpha: BTreeMap<(usize, usize), Pooled>,
    /// GPU ms per stage (submit and extrapolation), summed over the timed targets.
    gpu_ms: [f64; PATCHEX_STAGE_SLOTS],
    timed_targets: usize,
}

impl MethodResult {
    fn add(
        &mut self,
        maps: &ErrorMaps,
        holes: &[bool],
        regions: &[u32],
        masks: &RegionMasks,
        alpha: (usize, usize),
    ) {
        let by_alpha = self.by_alpha.entry(alpha).or_default();
        for pixel in 0..holes.len() {
            self.pooled[0].add(maps, pixel);
            by_alpha.add(maps, pixel);
            if holes[pixel] {
                self.pooled[1].add(maps, pixel);
            }
            for (region, mask) in MASKED_REGIONS.zip(masks) {
                if mask[pixel] {
                    self.pooled[region].add(maps, pixel);
                }
            }
            match regions[pixel] {
                REGION_FI => self.pooled[2].add(maps, pixel),
                REGION_NEAR_BE => self.pooled[3].add(maps, pixel),
                _ => {}
            }
        }
    }

    /// Adds a frame's GPU times, leaving out the diagnostics copy an engine would not run.
    fn add_time(&mut self, stats: &PatchexFrameStats) {
        let stages = stats
            .submit_gpu_ms
            .iter()
            .zip(stats.extrapolations[0].gpu_ms);
        for (stage, (total, (submit, extrapolate))) in
            self.gpu_ms.iter_mut().zip(stages).enumerate()
        {
            if stage != PATCHEX_STAGE_DIAGNOSTICS as usize {
                *total += (submit + extrapolate) as f64;
            }
        }
        self.timed_targets += 1;
    }

    fn merge(&mut self, other: &MethodResult) {
        for (mine, theirs) in self.pooled.iter_mut().zip(&other.pooled) {
            mine.merge(theirs);
        }
        for (alpha, theirs) in &other.by_alpha {
            self.by_alpha.entry(*alpha).or_default().merge(theirs);
        }
        for (mine, theirs) in self.gpu_ms.iter_mut().zip(&other.gpu_ms) {
            *mine += theirs;
        }
        self.timed_targets += other.timed_targets;
    }

    fn mean_gpu_ms(&self) -> Option<f64> {
        (self.timed_targets > 0)
            .then(|| self.gpu_ms.iter().sum::<f64>() / self.timed_targets as f64)
    }

    fn mean_stage_ms(&self, stage: PatchexStage) -> f64 {
        self.gpu_ms[stage as usize] / self.timed_targets.max(1) as f64
    }
}

/// The stages an engine runs, in pipeline order: all but the diagnostics copy, and the output's
/// packing, which eval's RGBA16F output never needs.
fn timed_stages() -> impl Iterator<Item = (PatchexStage, &'static str)> {
    STAGES
        .into_iter()
        .filter(|stage| stage.group != RuntimeGroup::Output)
        .map(|stage| (stage.id, stage.name))
}

struct DatasetResult {
    scene: String,
    width: usize,
    height: usize,
    targets: usize,
    methods: BTreeMap<Method, MethodResult>,
    /// Pixels per region, over all targets.
    region_pixels: [u64; REGION_COUNT],
}

pub fn run(args: EvalArgs) -> CommandResult {
    if args.post == PostPlacement::After {
        if let Some(method) = args.methods.iter().find(|m| m.before_translucency()) {
            return Err(format!(
                "{} runs before the translucency pass, so before post: it cannot be scored \
                 with --post after",
                method.name()
            )
            .into());
        }
    }
    let mut methods = args.methods.clone();
    methods.sort();
    methods.dedup();
    std::fs::create_dir_all(args.out.join("strips"))?;
    let mut results = Vec::new();
    for dataset_dir in &args.datasets {
        results.push(evaluate(dataset_dir, &methods, &args)?);
    }
    let markdown = report_markdown(&results, &methods);
    std::fs::write(args.out.join("eval.md"), &markdown)?;
    std::fs::write(
        args.out.join("eval.json"),
        serde_json::to_string_pretty(&report_json(&results, &methods))? + "\n",
    )?;
    println!("{markdown}");
    println!("written: {}", args.out.display());
    Ok(())
}

fn evaluate(
    dir: &Path,
    methods: &[Method],
    args: &EvalArgs,
) -> Result<DatasetResult, Box<dyn std::error::Error>> {
    let dataset = Dataset::open(dir)?;
    let manifest = &dataset.manifest;
    let (width, height) = (manifest.width, manifest.height);
    // Targets with a rendered frame on both sides, so interpolation has its future frame.
    // 2x streams: targets with a rendered frame on both sides, so interpolation has its future
    // frame. Streams with more targets between rendered frames: every target (interpolation,
    // written for the midpoint, is left out there).
    let stride = manifest.targets_between + 1;
    let targets: Vec<usize> = manifest
        .frames
        .iter()
        .filter(|f| f.role == FrameRole::Target)
        .filter(|f| stride > 2 || f.index + 1 < manifest.frames.len())
        .map(|f| f.index)
        .collect();
    if targets.is_empty() {
        return Err(format!(
            "{}: no target frame between two rendered frames",
            dir.display()
        )
        .into());
    }
    let strip_frame = args.strip_frame.unwrap_or(targets[targets.len() / 2]);
    let driver = PluginDriver::new(manifest, args.validation)?;
    let started = std::time::Instant::now();
    // Without a terminal the bar draws nothing: a line per scene says where the run is.
    let on_terminal = std::io::stderr().is_terminal();
    if !on_terminal {
        eprintln!("evaluating {}: {} targets", manifest.scene, targets.len());
    }
    let bar = ProgressBar::new(targets.len() as u64);
    bar.set_style(
        ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len}, {elapsed}")?
            .progress_chars("=> "),
    );
    bar.set_message(format!("evaluating {}", manifest.scene));

    let mut result = DatasetResult {
        scene: manifest.scene.clone(),
        width,
        height,
        targets: targets.len(),
        methods: methods
            .iter()
            .map(|m| (*m, MethodResult::default()))
            .collect(),
        region_pixels: [0; REGION_COUNT],
    };
    let mut frame_index = 0;
    for (n, &target) in targets.iter().enumerate() {
        // Frame t, the rendered frame the target is extrapolated from (named `previous` as the
        // frame before the target), and the target's instant between it and the next.
        let (source, alpha) = manifest.source_of(target);
        // The frames the methods are given: after the engine's post-processing, when patchex
        // sits there.
        let given = |index| {
            dataset.read_frame(index).map(|mut layers| {
                if args.post == PostPlacement::After {
                    post_process_colour(&mut layers);
                }
                layers
            })
        };
        let previous = given(source)?;
        let current = dataset.read_frame(target)?;
        let next = if stride == 2 {
            Some(given(target + 1)?)
        } else {
            None
        };
        // Frame t-1, whose shadow mask the shadow sub-task tracks from.
        let earlier = source
            .checked_sub(stride)
            .map(|index| given(index).map(|layers| (layers, index)))
            .transpose()?;
        // What the player sees of a frame of linear colour (or, after post, of display values).
        let display = |colour: &[f32], channels: usize| match args.post {
            PostPlacement::None => tone_map(colour, channels),
            PostPlacement::Before => post_process(colour, channels, width, height),
            // Display values: the screen shows what passes 1 as 1.
            PostPlacement::After => colour
                .chunks(channels)
                .flat_map(|pixel| pixel[..3].iter().map(|v| v.clamp(0.0, 1.0)))
                .collect(),
        };
        let truth = match args.post {
            PostPlacement::None => tone_map(&current.layer(FINAL_IMAGE).data, 3),
            _ => post_process(&current.layer(FINAL_IMAGE).data, 3, width, height),
        };
        let shadows: Vec<bool> = previous
            .layer(SHADOW_MASK)
            .data
            .iter()
            .zip(&current.layer(SHADOW_MASK).data)
            .map(|(before, after)| *before < SHADOWED || *after < SHADOWED)
            .collect();
        let masks: RegionMasks = [
            shadows,
            highlights(&current),
            translucency(&previous, &current),
        ];
        // Frames t and t-1 as the engine's scene colour holds them before the translucency pass.
        let opaque = methods.iter().any(|m| m.before_translucency()).then(|| {
            let earlier = earlier
                .as_ref()
                .map(|(layers, index)| (before_translucency(layers), *index));
            (before_translucency(&previous), earlier)
        });
        let mut run_plugin =
            |(previous, earlier): (&FrameLayers, &Option<(FrameLayers, usize)>),
             warp,
             networks: Option<NetworkChoice>,
             with_diagnostics,
             shadows: Option<bool>,
             extras| {
                // Two indices a run: frame t-1 and frame t when shadows are tracked.
                frame_index += 2;
                driver.extrapolate(
                    frame_index,
                    (previous, &manifest.frames[source]),
                    (&current, &manifest.frames[target]),
                    alpha,
                    Some(warp),
                    networks.as_ref(),
                    with_diagnostics,
                    shadows.map(|target_mask| ShadowRun {
                        earlier: earlier
                            .as_ref()
                            .map(|(layers, index)| (layers, &manifest.frames[*index])),
                        target_mask,
                    }),
                    extras,
                )
            };
        // The default warp's diagnostics give every method's regions and holes.
        let reference = run_plugin(
            (&previous, &earlier),
            WarpSettings::default(),
            None,
            true,
            None,
            FrameExtras::default(),
        )?;
        let diagnostics = reference.diagnostics.as_ref().expect("asked for");
        let holes: Vec<bool> = diagnostics.chunks(4).map(|d| d[0] > 0.5).collect();
        let regions: Vec<u32> = diagnostics
            .chunks(4)
            .map(|d| (d[1] * 2.0).round() as u32)
            .collect();
        result.region_pixels[0] += holes.len() as u64;
        result.region_pixels[1] += holes.iter().filter(|h| **h).count() as u64;
        result.region_pixels[2] += regions.iter().filter(|r| **r == REGION_FI).count() as u64;
        result.region_pixels[3] += regions.iter().filter(|r| **r == REGION_NEAR_BE).count() as u64;
        for (region, mask) in MASKED_REGIONS.zip(&masks) {
            result.region_pixels[region] += mask.iter().filter(|m| **m).count() as u64;
        }

        let mut strip_outputs = Vec::new();
        for &method in methods {
            // The method's linear RGB(A) output and its channel count.
            let (linear, channels, stats) = match method.warp() {
                Some(_) if method == Method::Gbuffer => {
                    (reference.color.clone(), 4, Some(reference.stats))
                }
                Some(warp) if method.before_translucency() => {
                    let (previous, earlier) = opaque.as_ref().expect("made for these methods");
                    let mut run = run_plugin(
                        (previous, earlier),
                        warp,
                        None,
                        false,
                        method.shadows(),
                        method.extras(),
                    )?;
                    draw_translucency(&mut run.color, &current);
                    (run.color, 4, Some(run.stats))
                }
                Some(warp) => {
                    let networks = method.networks(args);
                    let run = run_plugin(
                        (&previous, &earlier),
                        warp,
                        networks,
                        false,
                        method.shadows(),
                        method.extras(),
                    )?;
                    (run.color, 4, Some(run.stats))
                }
                None if method == Method::Copy => {
                    (previous.layer(FINAL_IMAGE).data.clone(), 3, None)
                }
                None => match &next {
                    Some(next) => (interpolate(&previous, &current, next), 3, None),
                    None => continue,
                },
            };
            if args.write_frames {
                let path = args
                    .out
                    .join("frames")
                    .join(&manifest.scene)
                    .join(method.name())
                    .join(format!("{target:04}.exr"));
                write_frame_exr(&path, &linear, channels, width, height)?;
            }
            let output = display(&linear, channels);
            let maps = error_maps(&truth, &output, width, height);
            let method_result = result
                .methods
                .get_mut(&method)
                .expect("every method has a result");
            method_result.add(&maps, &holes, &regions, &masks, (target - source, stride));
            // The first target's times include the driver's lazy shader compilation.
            if let (Some(stats), true) = (stats, n > 0) {
                method_result.add_time(&stats);
            }
            if target == strip_frame {
                strip_outputs.push((method, output, maps.flip));
            }
        }
        if target == strip_frame {
            write_shadow_strip(
                &args.out,
                &manifest.scene,
                width,
                &truth,
                &masks[0],
                &strip_outputs,
            )?;
            let strip_outputs: Vec<_> = strip_outputs
                .into_iter()
                .map(|(_, output, flip)| (output, flip))
                .collect();
            let path = args
                .out
                .join("strips")
                .join(format!("{}.png", manifest.scene));
            write_method_strip(
                &path,
                width,
                height,
                &truth,
                &holes,
                &regions,
                &strip_outputs,
            )?;
        }
        bar.inc(1);
    }
    bar.finish();
    if !on_terminal {
        eprintln!(
            "evaluated {} in {:.0} s",
            manifest.scene,
            started.elapsed().as_secs_f64()
        );
    }
    let messages = driver.validation_messages();
    if args.validation && !messages.is_empty() {
        return Err(format!(
            "plugin: {} validation messages, first: {}",
            messages.len(),
            messages[0]
        )
        .into());
    }
    Ok(result)
}

/// `frame` with its lit colour as it was before the translucency pass (FinalImageOpaque); as it
/// is in a scene that draws no translucency.
fn before_translucency(frame: &FrameLayers) -> FrameLayers {
    let mut frame = frame.clone();
    for (lit, opaque) in [
        (FINAL_IMAGE, FINAL_IMAGE_OPAQUE),
        (
            FINAL_IMAGE_NO_DYNAMIC_SHADOWS,
            FINAL_IMAGE_OPAQUE_NO_DYNAMIC_SHADOWS,
        ),
    ] {
        if let Some(opaque) = frame.get(opaque).map(|l| l.data.clone()) {
            frame.get_mut(lit).expect("a lit frame").data = opaque;
        }
    }
    frame
}

/// Draws the target's translucency over `output` (RGBA) as the engine draws it over its lit
/// colour: the layer's own light plus what it lets through, `(1 - mask) * output`. The layer's
/// light is what the target's colour holds beyond its lit opaque colour seen through the mask.
fn draw_translucency(output: &mut [f32], target: &FrameLayers) {
    let (Some(mask), Some(opaque)) = (
        target.get(TRANSLUCENCY_MASK),
        target.get(FINAL_IMAGE_OPAQUE),
    ) else {
        return;
    };
    let colour = target.layer(FINAL_IMAGE).data.chunks(3);
    for (((out, colour), opaque), coverage) in output
        .chunks_mut(4)
        .zip(colour)
        .zip(opaque.data.chunks(3))
        .zip(&mask.data)
    {
        let through = 1.0 - coverage;
        for ((out, colour), opaque) in out.iter_mut().zip(colour).zip(opaque) {
            *out = colour - through * opaque + through * *out;
        }
    }
}

/// One method's output as an EXR of one "FinalImage" layer (R, G, B), as the datasets hold the
/// rendered frames.
fn write_frame_exr(
    path: &Path,
    linear: &[f32],
    channels: usize,
    width: usize,
    height: usize,
) -> CommandResult {
    let rgb: Vec<f32> = linear
        .chunks(channels)
        .flat_map(|pixel| pixel[..3].to_vec())
        .collect();
    let frame = FrameLayers {
        width,
        height,
        layers: vec![LayerImage {
            name: FINAL_IMAGE.to_string(),
            channels: ["R", "G", "B"].map(String::from).to_vec(),
            width,
            height,
            data: rgb,
        }],
    };
    super::make_parent_folders(path)?;
    Ok(write_exr(path, &frame)?)
}

/// Pixels of margin around the shadow region in its strip, and the zoom of that strip.
const SHADOW_STRIP_MARGIN: usize = 12;
const SHADOW_STRIP_ZOOM: usize = 2;

/// When both the default warp and the shadow sub-task ran, `strips/SCENE_shadows.png`: the
/// rectangle around the shadow region, zoomed. Row 1: ground truth, the default warp, the warp
/// with the shadow sub-task. Row 2: the shadow region, then each one's FLIP error map.
fn write_shadow_strip(
    out: &Path,
    scene: &str,
    width: usize,
    truth: &[f32],
    shadows: &[bool],
    outputs: &[(Method, Vec<f32>, Vec<f32>)],
) -> CommandResult {
    let find = |wanted: Method| outputs.iter().find(|(method, ..)| *method == wanted);
    let (Some(without), Some(with)) = (find(Method::Gbuffer), find(Method::GbufferShadows)) else {
        return Ok(());
    };
    let height = shadows.len() / width;
    let inside: Vec<(usize, usize)> = (0..shadows.len())
        .filter(|&i| shadows[i])
        .map(|i| (i % width, i / width))
        .collect();
    if inside.is_empty() {
        return Ok(());
    }
    let bound = |pick: fn(&(usize, usize)) -> usize| {
        let values = inside.iter().map(pick);
        (values.clone().min().unwrap_or(0), values.max().unwrap_or(0))
    };
    let ((x0, x1), (y0, y1)) = (bound(|p| p.0), bound(|p| p.1));
    let x0 = x0.saturating_sub(SHADOW_STRIP_MARGIN);
    let y0 = y0.saturating_sub(SHADOW_STRIP_MARGIN);
    let x1 = (x1 + SHADOW_STRIP_MARGIN).min(width - 1);
    let y1 = (y1 + SHADOW_STRIP_MARGIN).min(height - 1);
    let (crop_width, crop_height) = (x1 - x0 + 1, y1 - y0 + 1);
    // Crops an RGB8 panel of the whole frame to the rectangle and zooms it.
    let zoom = |panel: Vec<u8>| -> Vec<u8> {
        let mut zoomed = Vec::with_capacity(crop_width * crop_height * 9 * 3);
        for y in 0..crop_height * SHADOW_STRIP_ZOOM {
            for x in 0..crop_width * SHADOW_STRIP_ZOOM {
                let source = (y0 + y / SHADOW_STRIP_ZOOM) * width + x0 + x / SHADOW_STRIP_ZOOM;
                zoomed.extend_from_slice(&panel[3 * source..3 * source + 3]);
            }
        }
        zoomed
    };
    let flip_panel = |flip: &[f32]| {
        FlipImageFloat::with_data(width as u32, height as u32, flip)
            .apply_color_lut(&magma_lut())
            .to_vec()
    };
    let region: Vec<f32> = truth
        .chunks(3)
        .zip(shadows)
        .flat_map(|(rgb, shadow)| {
            let grey = (rgb[0] + rgb[1] + rgb[2]) / 3.0;
            if *shadow {
                [0.5 + 0.5 * grey, 0.3 * grey, 0.6 + 0.4 * grey]
            } else {
                [0.35 * grey; 3]
            }
        })
        .collect();
    let panels = vec![
        zoom(to_rgb8(truth)),
        zoom(to_rgb8(&without.1)),
        zoom(to_rgb8(&with.1)),
        zoom(to_rgb8(&region)),
        zoom(flip_panel(&without.2)),
        zoom(flip_panel(&with.2)),
    ];
    write_grid(
        &out.join("strips").join(format!("{scene}_shadows.png")),
        crop_width * SHADOW_STRIP_ZOOM,
        crop_height * SHADOW_STRIP_ZOOM,
        3,
        &panels,
    )
}

/// Row 1: ground truth, then each method's output. Row 2: the masks (far-BE dimmed, near-BE
/// tinted yellow, FI tinted blue, holes red), then each method's FLIP error map (magma).
fn write_method_strip(
    path: &Path,
    width: usize,
    height: usize,
    truth: &[f32],
    holes: &[bool],
    regions: &[u32],
    outputs: &[(Vec<f32>, Vec<f32>)],
) -> CommandResult {
    let masks: Vec<f32> = truth
        .chunks(3)
        .zip(holes.iter().zip(regions))
        .flat_map(|(rgb, (hole, region))| {
            let grey = (rgb[0] + rgb[1] + rgb[2]) / 3.0;
            match (*hole, *region) {
                (true, _) => [1.0, 0.1, 0.1],
                (false, REGION_FI) => [0.3 * grey, 0.5 * grey + 0.2, 0.6 + 0.4 * grey],
                (false, REGION_NEAR_BE) => [0.6 + 0.4 * grey, 0.55 + 0.4 * grey, 0.2 * grey],
                _ => [0.35 * grey; 3],
            }
        })
        .collect();
    let mut top = vec![to_rgb8(truth)];
    let mut bottom = vec![to_rgb8(&masks)];
    for (output, flip) in outputs {
        top.push(to_rgb8(output));
        let error = FlipImageFloat::with_data(width as u32, height as u32, flip);
        bottom.push(error.apply_color_lut(&magma_lut()).to_vec());
    }
    let columns = top.len();
    top.extend(bottom);
    write_grid(path, width, height, columns, &top)
}

fn all_scenes(results: &[DatasetResult], methods: &[Method]) -> BTreeMap<Method, MethodResult> {
    let mut total: BTreeMap<Method, MethodResult> = methods
        .iter()
        .map(|m| (*m, MethodResult::default()))
        .collect();
    for result in results {
        for (method, scores) in &result.methods {
            total.get_mut(method).expect("same methods").merge(scores);
        }
    }
    total
}

fn method_table(out: &mut String, methods: &BTreeMap<Method, MethodResult>) {
    writeln!(
        out,
        "| method | PSNR dB: frame / holes / FI / near-BE / shadows / highlights / translucency | \
         SSIM: same regions | \
         FLIP: same regions | detail: same regions | GPU ms |\n|---|---|---|---|---|---|"
    )
    .unwrap();
    for (method, result) in methods {
        let scores: Vec<_> = result.pooled.iter().map(|p| p.scores()).collect();
        let column = |pick: fn(&super::metrics::Scores) -> f64, digits: usize| {
            scores
                .iter()
                .map(|s| s.map_or("-".to_owned(), |s| format!("{:.*}", digits, pick(&s))))
                .collect::<Vec<_>>()
                .join(" / ")
        };
        writeln!(
            out,
            "| {} | {} | {} | {} | {} | {} |",
            method.label(),
            column(|s| s.psnr, 2),
            column(|s| s.ssim, 4),
            column(|s| s.flip, 4),
            column(|s| s.detail, 3),
            result
                .mean_gpu_ms()
                .map_or("-".to_owned(), |ms| format!("{ms:.1}")),
        )
        .unwrap();
    }
}

/// Mean GPU ms per stage of the methods that run on the GPU.
fn stage_table(out: &mut String, methods: &BTreeMap<Method, MethodResult>) {
    write!(out, "| method |").unwrap();
    for (_, name) in timed_stages() {
        write!(out, " {name} |").unwrap();
    }
    writeln!(
        out,
        " total |\n|---|{}---|",
        "---|".repeat(timed_stages().count())
    )
    .unwrap();
    for (method, result) in methods {
        let Some(total) = result.mean_gpu_ms() else {
            continue;
        };
        write!(out, "| {} |", method.label()).unwrap();
        for (stage, _) in timed_stages() {
            write!(out, " {:.1} |", result.mean_stage_ms(stage)).unwrap();
        }
        writeln!(out, " {total:.1} |").unwrap();
    }
}

fn coverage(region_pixels: &[u64; REGION_COUNT]) -> String {
    let share = |i: usize| 100.0 * region_pixels[i] as f64 / region_pixels[0].max(1) as f64;
    format!(
        "holes {:.2}%, FI {:.2}%, near-BE {:.2}%, shadows {:.2}%, highlights {:.2}%, \
         translucency {:.2}% of the pixels",
        share(1),
        share(2),
        share(3),
        share(4),
        share(5),
        share(6)
    )
}

fn report_markdown(results: &[DatasetResult], methods: &[Method]) -> String {
    let mut out = String::new();
    writeln!(
        out,
        "Scores of tone-mapped frames against the rendered ground truth at each target's instant \
         (alpha 1/2 in a 2x stream; in a 3x stream 1/3 and 2/3, split in a table of their own) (PSNR, SSIM: \
         higher is better; FLIP: lower is better; detail: the energy of luma's finest scale \
         against the truth's, 1 is best, below 1 softer, above 1 noisier), pooled over every \
         target pixel of each region. \
         Regions come from the plugin's segmentation and the holes from its default warp, the \
         same pixels for every method. GPU ms: submit plus extrapolation per frame, from \
         timestamp queries, leaving out the first target (lazy shader compilation). The \
         interpolation row uses frame t+1: it shows what extrapolation aims at, at the cost of a \
         frame of latency.\n"
    )
    .unwrap();
    let mut total_pixels = [0u64; REGION_COUNT];
    for result in results {
        for (total, pixels) in total_pixels.iter_mut().zip(result.region_pixels) {
            *total += pixels;
        }
    }
    if results.len() > 1 {
        writeln!(out, "### All scenes ({})\n", coverage(&total_pixels)).unwrap();
        let all = all_scenes(results, methods);
        method_table(&mut out, &all);
        alpha_table(&mut out, &all);
        writeln!(out, "\nGPU ms per stage:\n").unwrap();
        stage_table(&mut out, &all);
        writeln!(out).unwrap();
    }
    for result in results {
        writeln!(
            out,
            "### {} ({}x{}, {} targets; {})\n",
            result.scene,
            result.width,
            result.height,
            result.targets,
            coverage(&result.region_pixels)
        )
        .unwrap();
        method_table(&mut out, &result.methods);
        alpha_table(&mut out, &result.methods);
        writeln!(out, "\nGPU ms per stage:\n").unwrap();
        stage_table(&mut out, &result.methods);
        writeln!(out).unwrap();
    }
    out
}

/// Scores over the whole frame for each target instant, when a dataset has more than one.
fn alpha_table(out: &mut String, methods: &BTreeMap<Method, MethodResult>) {
    let alphas: Vec<(usize, usize)> = methods
        .values()
        .flat_map(|result| result.by_alpha.keys().copied())
        .collect::<std::collections::BTreeSet<_>>()
        .into_iter()
        .collect();
    if alphas.len() < 2 {
        return;
    }
    write!(
        out,
        "\nOver the frame, by target instant (PSNR dB / SSIM / FLIP):\n\n| method |"
    )
    .unwrap();
    for (numerator, denominator) in &alphas {
        write!(out, " alpha {numerator}/{denominator} |").unwrap();
    }
    writeln!(out, "\n|{}", "---|".repeat(1 + alphas.len())).unwrap();
    for (method, result) in methods {
        write!(out, "| {} |", method.label()).unwrap();
        for alpha in &alphas {
            let cell = result
                .by_alpha
                .get(alpha)
                .and_then(|p| p.scores())
                .map_or("-".to_owned(), |s| {
                    format!("{:.2} / {:.4} / {:.4}", s.psnr, s.ssim, s.flip)
                });
            write!(out, " {cell} |").unwrap();
        }
        writeln!(out).unwrap();
    }
}

fn report_json(results: &[DatasetResult], methods: &[Method]) -> serde_json::Value {
    let method_json = |methods: &BTreeMap<Method, MethodResult>| {
        methods
            .iter()
            .map(|(method, result)| {
                let regions: serde_json::Map<String, serde_json::Value> = REGIONS
                    .iter()
                    .zip(&result.pooled)
                    .map(|(name, pooled)| {
                        let scores = pooled.scores().map(|s| {
                            json!({"psnr": finite(s.psnr), "ssim": s.ssim, "flip": s.flip, "detail": finite(s.detail), "pixels": pooled.pixels})
                        });
                        (name.to_string(), scores.unwrap_or(serde_json::Value::Null))
                    })
                    .collect();
                json!({
                    "method": format!("{method:?}"),
                    "label": method.label(),
                    "uses_future_frame": *method == Method::Interpolation,
                    "regions": regions,
                    "gpu_ms": result.mean_gpu_ms(),
                    "gpu_ms_per_stage": result.mean_gpu_ms().map(|_| {
                        timed_stages()
                            .map(|(stage, name)| (name.to_owned(), json!(result.mean_stage_ms(stage))))
                            .collect::<serde_json::Map<_, _>>()
                    }),
                })
            })
            .collect::<Vec<_>>()
    };
    json!({
        "all_scenes": method_json(&all_scenes(results, methods)),
        "scenes": results.iter().map(|r| json!({
            "scene": r.scene,
            "width": r.width,
            "height": r.height,
            "targets": r.targets,
            "region_pixels": dict(&r.region_pixels),
            "methods": method_json(&r.methods),
        })).collect::<Vec<_>>(),
    })
}

/// JSON has no infinity: a perfect PSNR is written as null.
fn finite(value: f64) -> Option<f64> {
    value.is_finite().then_some(value)
}

/// A mask per region of `MASKED_REGIONS`, row by row.
type RegionMasks = [Vec<bool>; REGION_COUNT - 4];

/// Where frame t or the target is covered by translucency (TRANSLUCENT), row by row; nowhere in
/// a dataset without it.
fn translucency(source: &FrameLayers, target: &FrameLayers) -> Vec<bool> {
    let covered = |frame: &FrameLayers| {
        frame.get(TRANSLUCENCY_MASK).map(|mask| {
            mask.data
                .iter()
                .map(|&a| a > TRANSLUCENT)
                .collect::<Vec<_>>()
        })
    };
    let pixels = source.width * source.height;
    match (covered(source), covered(target)) {
        (Some(source), Some(target)) => source.iter().zip(target).map(|(s, t)| *s || t).collect(),
        _ => vec![false; pixels],
    }
}

/// The target's highlights (HIGHLIGHT_ROUGHNESS, HIGHLIGHT_SHARE), row by row.
fn highlights(target: &FrameLayers) -> Vec<bool> {
    let roughness = &target.layer(ROUGHNESS).data;
    let Some(specular) = target.get(SPECULAR_LIGHT) else {
        return vec![false; roughness.len()];
    };
    let lit = luma(&target.layer(FINAL_IMAGE).data);
    lit.iter()
        .zip(luma(&specular.data))
        .zip(roughness)
        .map(|((&lit, specular), &roughness)| {
            roughness < HIGHLIGHT_ROUGHNESS && specular > HIGHLIGHT_SHARE * lit && lit > 0.0
        })
        .collect()
}

fn dict(region_pixels: &[u64; REGION_COUNT]) -> serde_json::Value {
    REGIONS
        .iter()
        .zip(region_pixels)
        .map(|(name, pixels)| (name.to_string(), json!(pixels)))
        .collect::<serde_json::Map<_, _>>()
        .into()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn layer(name: &str, channels: usize, data: Vec<f32>) -> LayerImage {
        LayerImage {
            name: name.to_owned(),
            channels: ["R", "G", "B"][..channels]
                .iter()
                .map(|c| c.to_string())
                .collect(),
            width: 2,
            height: 1,
            data,
        }
    }

    /// Two pixels: one uncovered, one 75% covered by a layer of light (0.3, 0.2, 0.1).
    fn target() -> FrameLayers {
        let opaque = vec![1.0, 2.0, 3.0, 0.5, 0.5, 0.5];
        let final_image = vec![1.0, 2.0, 3.0, 0.425, 0.325, 0.225];
        FrameLayers {
            width: 2,
            height: 1,
            layers: vec![
                layer(FINAL_IMAGE, 3, final_image),
                layer(FINAL_IMAGE_OPAQUE, 3, opaque),
                layer(TRANSLUCENCY_MASK, 1, vec![0.0, 0.75]),
            ],
        }
    }

    #[test]
    fn the_targets_translucency_is_drawn_over_what_lets_it_through() {
        let close = |a: &[f32], b: &[f32]| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-6);
        // The target's opaque colour exactly: the target itself.
        let mut output = vec![1.0, 2.0, 3.0, 1.0, 0.5, 0.5, 0.5, 1.0];
        draw_translucency(&mut output, &target());
        assert!(close(
            &output,
            &[1.0, 2.0, 3.0, 1.0, 0.425, 0.325, 0.225, 1.0]
        ));
        // An error under the layer shows through by a quarter; uncovered, in full.
        let mut output = vec![1.4, 2.0, 3.0, 1.0, 0.9, 0.5, 0.5, 1.0];
        draw_translucency(&mut output, &target());
        assert!(close(
            &output,
            &[1.4, 2.0, 3.0, 1.0, 0.525, 0.325, 0.225, 1.0]
        ));
        // Nothing to draw in a frame without translucency.
        let mut plain = target();
        plain.layers.truncate(1);
        let mut output = vec![0.0; 8];
        draw_translucency(&mut output, &plain);
        assert_eq!(output, vec![0.0; 8]);
    }

    #[test]
    fn before_translucency_both_lit_colours_are_the_opaque_ones() {
        let mut frame = target();
        frame.layers.extend([
            layer(FINAL_IMAGE_NO_DYNAMIC_SHADOWS, 3, vec![2.0; 6]),
            layer(FINAL_IMAGE_OPAQUE_NO_DYNAMIC_SHADOWS, 3, vec![0.7; 6]),
        ]);
        let opaque = before_translucency(&frame);
        assert_eq!(
            opaque.layer(FINAL_IMAGE).data,
            frame.layer(FINAL_IMAGE_OPAQUE).data
        );
        assert_eq!(
            opaque.layer(FINAL_IMAGE_NO_DYNAMIC_SHADOWS).data,
            vec![0.7; 6]
        );
        // A frame without translucency is given as it is.
        let mut plain = target();
        plain.layers.truncate(1);
        assert_eq!(before_translucency(&plain).layers, plain.layers);
    }
}
