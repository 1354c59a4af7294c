//! Check mode's scoring: each generated frame against Bevy's own rendering of its instant, beside
//! repeating frame t, on tone-mapped colour as `patchex eval` scores (x / (1 + x), then sRGB).

use std::fmt::Write as _;
use std::path::Path;

use patchex::abi::PatchexFrameStats;

use crate::frame_generation::Readback;

/// One generated instant's scores, in dB, and what patchex reported of it.
struct Score {
    instant: u64,
    generated: f64,
    repeated: f64,
    hole_fraction: f32,
    /// GPU milliseconds of patchex's passes: the frame's submit and the extrapolation.
    gpu_ms: f32,
}

#[derive(Default)]
pub struct Check {
    width: usize,
    height: usize,
    /// The last rendered frame, tone-mapped RGB.
    frame_t: Option<Vec<f32>>,
    scores: Vec<Score>,
    squared_error_generated: f64,
    squared_error_repeated: f64,
    values: f64,
    /// [frame t, generated, truth] of the instant the strip shows.
    strip: Option<[Vec<f32>; 3]>,
}

impl Check {
    /// Takes one displayed instant's images (RGBA16F rows as copied out).
    pub fn add(
        &mut self,
        instant: u64,
        images: Vec<(Readback, Image)>,
        stats: Option<&PatchexFrameStats>,
        strip_instant: u64,
    ) -> Result<(), String> {
        let find = |what| {
            images
                .iter()
                .find(|(kind, _)| *kind == what)
                .map(|(_, image)| image)
        };
        if let Some(rendered) = find(Readback::Rendered) {
            (self.width, self.height) = (rendered.width, rendered.height);
            self.frame_t = Some(rendered.tone_mapped());
            return Ok(());
        }
        let (Some(truth), Some(generated), Some(frame_t), Some(stats)) = (
            find(Readback::Truth),
            find(Readback::Generated),
            self.frame_t.as_ref(),
            stats,
        ) else {
            return Err(format!(
                "instant {instant}: no frame t, truth or generated frame to score"
            ));
        };
        let (truth, generated) = (truth.tone_mapped(), generated.tone_mapped());
        let generated_error = squared_error(&generated, &truth);
        let repeated_error = squared_error(frame_t, &truth);
        self.squared_error_generated += generated_error;
        self.squared_error_repeated += repeated_error;
        self.values += truth.len() as f64;
        self.scores.push(Score {
            instant,
            generated: psnr(generated_error, truth.len() as f64),
            repeated: psnr(repeated_error, truth.len() as f64),
            hole_fraction: stats.extrapolations[0].hole_fraction,
            gpu_ms: stats
                .submit_gpu_ms
                .iter()
                .chain(&stats.extrapolations[0].gpu_ms)
                .sum(),
        });
        if instant == strip_instant {
            self.strip = Some([frame_t.clone(), generated, truth]);
        }
        Ok(())
    }

    /// Pooled PSNR over every generated frame: (generated, repeating frame t).
    pub fn pooled(&self) -> (f64, f64) {
        (
            psnr(self.squared_error_generated, self.values),
            psnr(self.squared_error_repeated, self.values),
        )
    }

    pub fn report(&self) -> String {
        let mut text = format!(
            "Each generated instant against Bevy's own rendering of it, {}x{}, PSNR of tone-mapped \
             colour; holes and patchex's GPU time (its submit and extrapolation, from timestamp \
             queries) as patchex reports them.\n\n\
             | instant | patchex (dB) | repeating frame t (dB) | holes | patchex GPU ms |\n\
             |---|---|---|---|---|\n",
            self.width, self.height
        );
        for score in &self.scores {
            let _ = writeln!(
                text,
                "| {} | {:.2} | {:.2} | {:.1}% | {:.2} |",
                score.instant,
                score.generated,
                score.repeated,
                100.0 * score.hole_fraction,
                score.gpu_ms
            );
        }
        let (generated, repeated) = self.pooled();
        let count = self.scores.len().max(1) as f32;
        let holes = self
            .scores
            .iter()
            .map(|score| score.hole_fraction)
            .sum::<f32>()
            / count;
        let gpu_ms = self.scores.iter().map(|score| score.gpu_ms).sum::<f32>() / count;
        let _ = writeln!(
            text,
            "| pooled (holes and time: mean) | {generated:.2} | {repeated:.2} | {:.1}% | {gpu_ms:.2} |",
            100.0 * holes
        );
        text
    }

    /// Writes [frame t | generated | Bevy's rendering | 4x absolute error] as a PNG.
    pub fn write_strip(&self, path: &Path) -> Result<(), String> {
        let Some([frame_t, generated, truth]) = &self.strip else {
            return Err("no generated instant was kept for the strip".to_owned());
        };
        let error: Vec<f32> = generated
            .iter()
            .zip(truth)
            .map(|(a, b)| 4.0 * (a - b).abs())
            .collect();
        let panels = [frame_t, generated, truth, &error];
        let (width, height) = (self.width, self.height);
        let mut rgb = Vec::with_capacity(panels.len() * width * height * 3);
        for y in 0..height {
            for panel in panels {
                let row = &panel[y * width * 3..(y + 1) * width * 3];
                rgb.extend(row.iter().map(|v| (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8));
            }
        }
        let file = std::fs::File::create(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let mut encoder = png::Encoder::new(
            std::io::BufWriter::new(file),
            (panels.len() * width) as u32,
            height as u32,
        );
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header().map_err(|e| e.to_string())?;
        writer.write_image_data(&rgb).map_err(|e| e.to_string())
    }
}

/// An RGBA16F image copied out of the GPU, rows `bytes_per_row` apart.
pub struct Image {
    pub width: usize,
    pub height: usize,
    pub bytes_per_row: usize,
    pub bytes: Vec<u8>,
}

impl Image {
    /// RGB, tone-mapped for display: x / (1 + x), then the sRGB curve.
    fn tone_mapped(&self) -> Vec<f32> {
        let mut rgb = Vec::with_capacity(self.width * self.height * 3);
        for row in self.bytes.chunks(self.bytes_per_row).take(self.height) {
            for texel in row[..self.width * 8].chunks_exact(8) {
                for channel in texel[..6].chunks_exact(2) {
                    let linear = half::f16::from_le_bytes([channel[0], channel[1]])
                        .to_f32()
                        .max(0.0);
                    rgb.push(srgb(linear / (1.0 + linear)));
                }
            }
        }
        rgb
    }
}

fn srgb(v: f32) -> f32 {
    if v <= 0.003_130_8 {
        v * 12.92
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

fn squared_error(a: &[f32], b: &[f32]) -> f64 {
    a.iter().zip(b).map(|(x, y)| f64::from(x - y).powi(2)).sum()
}

fn psnr(squared_error: f64, values: f64) -> f64 {
    let mse = squared_error / values;
    if mse == 0.0 {
        f64::INFINITY
    } else {
        10.0 * (1.0 / mse).log10()
    }
}
