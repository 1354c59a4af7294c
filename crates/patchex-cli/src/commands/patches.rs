//! `patchex patches DATASET... --out DIR`: the inpainting networks' training data. For every
//! target frame it runs the plugin's plain-Rust reference extrapolation (bit for bit what the
//! shaders compute, within f16 rounding), plans the FI and near-BE patches as the plugin does,
//! and writes each patch as one safetensors file for `training/train.py`:
//!
//! - `input` (8, H, W): the planes the network reads, as the GPU gathers them;
//! - `target` (3, H, W): the rendered target's demodulated colour, what the network should output;
//! - `region` (H, W): 1 on the pixels whose result is used (the patch's region), else 0;
//! - `hole` (H, W): 1 where the warp found no source.
//!
//! Metadata names the dataset, the frame, the network and the patch's place in the frame.
//!
//! With `--holes` it also writes each target's whole frame, its holes as the region, with a
//! `guide` tensor of what the target's G-buffer knows there: `training/hole_study.py` reads it.

use std::collections::HashMap;
use std::path::PathBuf;

use clap::Args;
use patchex::passes::segmentation::{SegmentationSettings, REGION_FI, REGION_NEAR_BE};
use patchex::passes::warp::WarpSettings;
use patchex::reference::gbuffer::pixel_modulation;
use patchex::reference::inpaint::{gather_inputs, plan_patches, Patch};
use patchex::reference::network::Planes;
use patchex::reference::{self, demodulate::demodulate, Image};
use patchex_scene::dataset::Dataset;
use safetensors::tensor::{Dtype, TensorView};

use super::reference_frames::{frame, inputs, Frame};
use super::CommandResult;

/// Levels of the FI and near-BE networks (`FI_WIDTHS`, `NEAR_BE_WIDTHS` in
/// training/patchex_net.py): patches are planned as the plugin plans them for these.
const LEVELS: [u32; 2] = [3, 3];

/// The `guide` planes of a `--holes` sample.
const GUIDE_NAMES: &str =
    "normal_x,normal_y,normal_z,depth,agreement,modulation_r,modulation_g,modulation_b";
const GUIDE_CHANNELS: usize = 8;

#[derive(Args)]
pub struct PatchesArgs {
    /// Dataset folders written by `patchex render`.
    #[arg(required = true)]
    datasets: Vec<PathBuf>,
    /// Output folder for <dataset>_<frame>_<fi|near_be>.safetensors.
    #[arg(long)]
    out: PathBuf,
    /// Also write each target's whole frame as <dataset>_<frame>_holes.safetensors, its holes as
    /// the region, with a `guide` tensor of the target's G-buffer (normal xyz, linear depth, the
    /// warp's best agreement, the remodulation factor rgb): data for a hole network.
    #[arg(long)]
    holes: bool,
}

/// `channels` planes of `image` over `patch`, zero past the frame.
fn crop(image: &Image, channels: usize, patch: Patch, f: impl Fn(&[f32], usize) -> f32) -> Planes {
    let [width, height] = patch.extent.map(|v| v as usize);
    let mut planes = Planes::zeros(channels, width, height);
    for y in 0..height {
        for x in 0..width {
            let (fx, fy) = (patch.origin[0] as usize + x, patch.origin[1] as usize + y);
            if fx < image.width && fy < image.height {
                for c in 0..channels {
                    planes.values[(c * height + y) * width + x] = f(image.at(fx, fy), c);
                }
            }
        }
    }
    planes
}

fn write(
    path: &std::path::Path,
    tensors: &[(&str, &Planes)],
    metadata: HashMap<String, String>,
) -> CommandResult {
    let bytes: Vec<Vec<u8>> = tensors
        .iter()
        .map(|(_, p)| p.values.iter().flat_map(|v| v.to_le_bytes()).collect())
        .collect();
    let views = tensors
        .iter()
        .zip(&bytes)
        .map(|((name, planes), bytes)| {
            let shape = vec![planes.channels, planes.height, planes.width];
            Ok((name.to_string(), TensorView::new(Dtype::F32, shape, bytes)?))
        })
        .collect::<Result<Vec<_>, safetensors::SafeTensorError>>()?;
    std::fs::write(path, safetensors::serialize(views, Some(metadata))?)?;
    Ok(())
}

/// The whole target frame as one sample, its holes as the region, with the target's `guide`
/// planes (`GUIDE_NAMES`).
fn write_holes(
    out: &std::path::Path,
    name: &str,
    target_index: usize,
    alpha: f32,
    target: &Frame,
    truth: &Image,
    result: &reference::Extrapolation,
) -> CommandResult {
    let (width, height) = (truth.width, truth.height);
    let frame = Patch {
        origin: [0, 0],
        extent: [width as u32, height as u32],
        divisor: 1,
    };
    let warped = &result.warped;
    let guide = Image::from_fn(width, height, GUIDE_CHANNELS, |x, y| {
        let normal = target.normal.at(x, y);
        let (modulation, _) = pixel_modulation(&target.base_color, Some(&target.material), x, y);
        vec![
            normal[0],
            normal[1],
            normal[2],
            target.depth.at(x, y)[0],
            warped.best_agreement[y * width + x],
            modulation.x,
            modulation.y,
            modulation.z,
        ]
    });
    let hole = crop(&warped.warped, 1, frame, |p, _| 1.0 - p[3]);
    let metadata = HashMap::from([
        ("dataset".to_string(), name.to_string()),
        ("frame".to_string(), target_index.to_string()),
        ("network".to_string(), "holes".to_string()),
        ("alpha".to_string(), alpha.to_string()),
        ("guide".to_string(), GUIDE_NAMES.to_string()),
    ]);
    let input = gather_inputs(&warped.warped, Some(&target.material), frame);
    write(
        &out.join(format!("{name}_{target_index:04}_holes.safetensors")),
        &[
            ("input", &input),
            ("target", &crop(truth, 3, frame, |p, c| p[c])),
            ("region", &hole),
            ("hole", &hole),
            ("guide", &crop(&guide, GUIDE_CHANNELS, frame, |p, c| p[c])),
        ],
        metadata,
    )
}

pub fn run(args: PatchesArgs) -> CommandResult {
    std::fs::create_dir_all(&args.out)?;
    let mut written = 0;
    for dir in &args.datasets {
        let dataset = Dataset::open(dir)?;
        let name = dir
            .file_name()
            .map_or("dataset".into(), |n| n.to_string_lossy().into_owned());
        let targets = (0..dataset.manifest.frames.len()).filter(|&i| {
            let (source, alpha) = dataset.manifest.source_of(i);
            alpha > 0.0 && source != i
        });
        for target_index in targets {
            let (source_index, alpha) = dataset.manifest.source_of(target_index);
            let (source, target) = (
                frame(&dataset, source_index)?,
                frame(&dataset, target_index)?,
            );
            let result = reference::extrapolate(
                &inputs(&source),
                &inputs(&target),
                None,
                alpha,
                &WarpSettings::default(),
                &SegmentationSettings::default(),
                Default::default(),
            );
            let (truth, _) = demodulate(&target.color, &target.base_color, Some(&target.material));
            let regions = &result.segmented.regions;
            // At the frame's resolution, whatever the patch's size: training crops it anyway.
            let patches =
                plan_patches(regions, &result.segmented.rects, LEVELS, false, 1, u32::MAX);
            for (network, region_id, patch) in [
                ("fi", REGION_FI, patches.fi),
                ("near_be", REGION_NEAR_BE, patches.near_be),
            ] {
                if patch.is_empty() {
                    continue;
                }
                let warped = &result.warped.warped;
                let input = gather_inputs(warped, Some(&target.material), patch);
                let target_planes = crop(&truth, 3, patch, |p, c| p[c]);
                let region = crop(regions, 1, patch, |p, _| {
                    (p[0] as u32 == region_id) as u32 as f32
                });
                let hole = crop(warped, 1, patch, |p, _| 1.0 - p[3]);
                let metadata = HashMap::from([
                    ("dataset".to_string(), name.clone()),
                    ("frame".to_string(), target_index.to_string()),
                    ("network".to_string(), network.to_string()),
                    ("alpha".to_string(), alpha.to_string()),
                    ("origin".to_string(), format!("{:?}", patch.origin)),
                ]);
                write(
                    &args
                        .out
                        .join(format!("{name}_{target_index:04}_{network}.safetensors")),
                    &[
                        ("input", &input),
                        ("target", &target_planes),
                        ("region", &region),
                        ("hole", &hole),
                    ],
                    metadata,
                )?;
                written += 1;
            }
            if args.holes {
                write_holes(
                    &args.out,
                    &name,
                    target_index,
                    alpha,
                    &target,
                    &truth,
                    &result,
                )?;
                written += 1;
            }
            println!(
                "{name} frame {target_index}: FI {:?}, near-BE {:?}",
                patches.fi, patches.near_be
            );
        }
    }
    println!("{written} patches written to {}", args.out.display());
    Ok(())
}
