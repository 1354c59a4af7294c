//! Tone mapping, PSNR and picture strips for the demo and the evaluation.

use std::path::Path;

/// Reinhard tone mapping and sRGB encoding of linear HDR values with `channels` per pixel; the
/// result is RGB in [0, 1], the space the demo's PSNR is measured in.
pub use patchex_scene::render::post::tone_map;

/// Peak signal-to-noise ratio of two RGB images in [0, 1], in dB.
pub fn psnr(a: &[f32], b: &[f32]) -> f64 {
    let squared: f64 = a.iter().zip(b).map(|(x, y)| ((x - y) as f64).powi(2)).sum();
    let mse = squared / a.len() as f64;
    if mse == 0.0 {
        f64::INFINITY
    } else {
        10.0 * (1.0 / mse).log10()
    }
}

/// RGB in [0, 1] to 8-bit.
pub fn to_rgb8(rgb: &[f32]) -> Vec<u8> {
    rgb.iter()
        .map(|v| (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8)
        .collect()
}

/// Writes [frame t | extrapolated | ground truth | 4x absolute error] side by side.
pub fn write_strip(
    path: &Path,
    width: usize,
    height: usize,
    frame_t: &[f32],
    extrapolated: &[f32],
    truth: &[f32],
) -> Result<(), Box<dyn std::error::Error>> {
    let error: Vec<f32> = extrapolated
        .iter()
        .zip(truth)
        .map(|(x, y)| ((x - y).abs() * 4.0).min(1.0))
        .collect();
    let panels = [frame_t, extrapolated, truth, &error].map(to_rgb8);
    write_grid(path, width, height, 4, &panels)
}

/// Writes 8-bit RGB panels of `width` x `height` into a PNG grid, `columns` panels per row.
pub fn write_grid(
    path: &Path,
    width: usize,
    height: usize,
    columns: usize,
    panels: &[Vec<u8>],
) -> Result<(), Box<dyn std::error::Error>> {
    let rows = panels.len().div_ceil(columns);
    let grid_width = width * columns;
    let mut bytes = vec![0u8; grid_width * height * rows * 3];
    for (index, panel) in panels.iter().enumerate() {
        let (column, row) = (index % columns, index / columns);
        for y in 0..height {
            let from = y * width * 3;
            let to = ((row * height + y) * grid_width + column * width) * 3;
            bytes[to..to + width * 3].copy_from_slice(&panel[from..from + width * 3]);
        }
    }
    let file = std::io::BufWriter::new(super::create_output(path)?);
    let mut encoder = png::Encoder::new(file, grid_width as u32, (height * rows) as u32);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.write_header()?.write_image_data(&bytes)?;
    Ok(())
}
