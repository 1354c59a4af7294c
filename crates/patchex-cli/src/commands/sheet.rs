//! `patchex sheet DATASET... --frame K --out sheet.png`: the chosen layers (default: all, in
//! the dataset's order) of frame K of each dataset as tiles, four per row. Several datasets of
//! the same size make a gallery, e.g. the FinalImage of every scene.

use super::CommandResult;
use clap::Args;
use patchex_scene::dataset::*;
use patchex_scene::Dataset;
use std::path::PathBuf;

#[derive(Args)]
pub struct SheetArgs {
    /// Dataset folders written by `patchex render`, all of one resolution.
    #[arg(required = true)]
    datasets: Vec<PathBuf>,
    #[arg(long, default_value_t = 0)]
    frame: usize,
    #[arg(long)]
    out: PathBuf,
    /// Tiles per row.
    #[arg(long, default_value_t = 4)]
    columns: usize,
    /// Only these layers, comma-separated (default: all, in dataset order).
    #[arg(long, value_delimiter = ',')]
    layers: Vec<String>,
}

type Rgb = [u8; 3];

/// The tiles of one dataset's frame.
struct FrameTiles {
    tiles: Vec<Vec<Rgb>>,
    width: usize,
    height: usize,
}

fn frame_tiles(path: &PathBuf, args: &SheetArgs) -> Result<FrameTiles, Box<dyn std::error::Error>> {
    let dataset = Dataset::open(path)?;
    let frame = dataset.read_frame(args.frame)?;
    let (near, far) = (dataset.manifest.near, dataset.manifest.far);
    let chosen: Vec<&LayerImage> = if args.layers.is_empty() {
        frame.layers.iter().collect()
    } else {
        args.layers
            .iter()
            .map(|name| {
                frame
                    .get(name)
                    .ok_or_else(|| format!("{}: the frame has no layer {name:?}", path.display()))
            })
            .collect::<Result<_, _>>()?
    };
    let sky: Vec<bool> = frame
        .get(SCENE_DEPTH)
        .map(|depth| depth.data.iter().map(|&d| d >= far).collect())
        .unwrap_or_else(|| vec![false; frame.width * frame.height]);
    let view = ViewInfo { near, far, sky };
    Ok(FrameTiles {
        tiles: chosen.iter().map(|layer| visualize(layer, &view)).collect(),
        width: frame.width,
        height: frame.height,
    })
}

pub fn run(args: SheetArgs) -> CommandResult {
    let mut tiles: Vec<Vec<Rgb>> = Vec::new();
    let mut size = None;
    for path in &args.datasets {
        let frame = frame_tiles(path, &args)?;
        let frame_size = (frame.width, frame.height);
        if *size.get_or_insert(frame_size) != frame_size {
            return Err(format!("{} is not the size of the first dataset", path.display()).into());
        }
        tiles.extend(frame.tiles);
    }
    let (w, h) = size.expect("clap requires one dataset");
    let columns = args.columns.max(1);
    let rows = tiles.len().div_ceil(columns);
    let sheet_width = columns * w;
    let mut pixels = vec![0u8; sheet_width * rows * h * 3];
    for (index, tile) in tiles.iter().enumerate() {
        let (x0, y0) = ((index % columns) * w, (index / columns) * h);
        for y in 0..h {
            for x in 0..w {
                let offset = ((y0 + y) * sheet_width + x0 + x) * 3;
                pixels[offset..offset + 3].copy_from_slice(&tile[y * w + x]);
            }
        }
    }
    let file = super::create_output(&args.out)?;
    let mut encoder = png::Encoder::new(
        std::io::BufWriter::new(file),
        sheet_width as u32,
        (rows * h) as u32,
    );
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.write_header()?.write_image_data(&pixels)?;
    println!("{} ({} tiles)", args.out.display(), tiles.len());
    Ok(())
}

fn to_srgb8(linear: f32) -> u8 {
    let v = linear.clamp(0.0, 1.0);
    let encoded = if v <= 0.003_130_8 {
        v * 12.92
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    };
    (encoded * 255.0 + 0.5) as u8
}

fn gray(v: f32) -> Rgb {
    let g = (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8;
    [g, g, g]
}

/// Colour for hue in [0, 1) at full value, scaled by `saturation`.
fn hue(h: f32, saturation: f32) -> Rgb {
    let channel = |offset: f32| {
        let k = (h * 6.0 + offset).rem_euclid(6.0);
        let c = 1.0 - (k.min(4.0 - k).clamp(0.0, 1.0));
        ((1.0 - saturation * c) * 255.0) as u8
    };
    [channel(5.0), channel(3.0), channel(1.0)]
}

/// What the visualisations need besides the layer itself.
struct ViewInfo {
    near: f32,
    far: f32,
    /// Background pixels, whose world positions are far-away points of no interest.
    sky: Vec<bool>,
}

/// Maps one layer to displayable colours.
fn visualize(layer: &LayerImage, view: &ViewInfo) -> Vec<Rgb> {
    let (near, far) = (view.near, view.far);
    let pixels = (0..layer.height).flat_map(|y| (0..layer.width).map(move |x| (x, y)));
    match layer.name.as_str() {
        FINAL_IMAGE | FINAL_IMAGE_NO_DYNAMIC_SHADOWS | SPECULAR_LIGHT => pixels
            .map(|(x, y)| {
                // Reinhard tone mapping, then sRGB.
                let p = layer.pixel(x, y);
                [0, 1, 2].map(|c| to_srgb8(p[c] / (1.0 + p[c])))
            })
            .collect(),
        BASE_COLOR => pixels
            .map(|(x, y)| [0, 1, 2].map(|c| to_srgb8(layer.value(x, y, c))))
            .collect(),
        WORLD_NORMAL => pixels
            .map(|(x, y)| [0, 1, 2].map(|c| ((layer.value(x, y, c) * 0.5 + 0.5) * 255.0) as u8))
            .collect(),
        SCENE_DEPTH => pixels
            .map(|(x, y)| {
                gray(1.0 - (layer.value(x, y, 0) / near).max(1.0).ln() / (far / near).ln())
            })
            .collect(),
        // Smooth 4 m colour bands per axis (a sawtooth would flicker on planes at a band
        // edge); the sky's far points are noise, so they stay black.
        WORLD_POSITION => pixels
            .map(|(x, y)| {
                if view.sky[y * layer.width + x] {
                    [0, 0, 0]
                } else {
                    [0, 1, 2].map(|c| {
                        let phase = layer.value(x, y, c) * std::f32::consts::TAU / 4.0;
                        ((0.5 + 0.5 * phase.sin()) * 255.0) as u8
                    })
                }
            })
            .collect(),
        CUSTOM_STENCIL => pixels
            .map(|(x, y)| {
                let id = layer.value(x, y, 0).round() as u32;
                if id == 0 {
                    [0, 0, 0]
                } else {
                    hue((id as f32 * 0.618_034).fract(), 1.0)
                }
            })
            .collect(),
        MOTION_VECTOR => {
            let largest = layer
                .data
                .chunks_exact(2)
                .map(|m| m[0].hypot(m[1]))
                .fold(1e-3f32, f32::max);
            pixels
                .map(|(x, y)| {
                    let m = layer.pixel(x, y);
                    let angle = m[1].atan2(m[0]) / std::f32::consts::TAU + 0.5;
                    hue(angle, m[0].hypot(m[1]) / largest)
                })
                .collect()
        }
        _ => pixels.map(|(x, y)| gray(layer.value(x, y, 0))).collect(),
    }
}
