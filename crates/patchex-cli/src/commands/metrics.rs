//! Image quality metrics on tone-mapped RGB in [0, 1], per pixel so they can be pooled over any
//! region: squared error (for PSNR), SSIM (Wang et al. 2004, on luma), NVIDIA's FLIP, and the
//! fine detail kept: the energy of luma's finest scale against the reference's, which PSNR
//! barely registers when an image is a little soft.

use nv_flip::{FlipImageRgb8, DEFAULT_PIXELS_PER_DEGREE};

const LUMA: [f32; 3] = [0.2126, 0.7152, 0.0722];
/// SSIM's Gaussian window: 11 taps, sigma 1.5, and its stabilising constants for range 1.
const SSIM_RADIUS: i32 = 5;
const SSIM_SIGMA: f32 = 1.5;
const SSIM_C1: f32 = 0.01 * 0.01;
const SSIM_C2: f32 = 0.03 * 0.03;
/// The finest scale: luma less its Gaussian blur of sigma 1 pixel.
const DETAIL_RADIUS: i32 = 3;
const DETAIL_SIGMA: f32 = 1.0;

/// Per-pixel error maps of `test` against `reference` (both RGB, row-major).
pub struct ErrorMaps {
    /// Mean over the three channels of the squared difference.
    pub squared: Vec<f32>,
    pub ssim: Vec<f32>,
    pub flip: Vec<f32>,
    /// The squared finest-scale luma of the test image and of the reference.
    pub detail: Vec<f32>,
    pub reference_detail: Vec<f32>,
}

pub fn error_maps(reference: &[f32], test: &[f32], width: usize, height: usize) -> ErrorMaps {
    let squared = reference
        .chunks(3)
        .zip(test.chunks(3))
        .map(|(r, t)| (0..3).map(|c| (r[c] - t[c]).powi(2)).sum::<f32>() / 3.0)
        .collect();
    let (reference_luma, test_luma) = (luma(reference), luma(test));
    ErrorMaps {
        squared,
        ssim: ssim_map(&reference_luma, &test_luma, width, height),
        flip: flip_map(reference, test, width, height),
        detail: detail_map(&test_luma, width, height),
        reference_detail: detail_map(&reference_luma, width, height),
    }
}

fn detail_map(luma: &[f32], width: usize, height: usize) -> Vec<f32> {
    let blurred = blur(luma, width, height, DETAIL_RADIUS, DETAIL_SIGMA);
    luma.iter()
        .zip(blurred)
        .map(|(value, blurred)| (value - blurred).powi(2))
        .collect()
}

/// Rec. 709 luma of each RGB pixel.
pub fn luma(rgb: &[f32]) -> Vec<f32> {
    rgb.chunks(3)
        .map(|p| p[0] * LUMA[0] + p[1] * LUMA[1] + p[2] * LUMA[2])
        .collect()
}

/// Separable Gaussian blur with clamp-to-edge.
fn blur(values: &[f32], width: usize, height: usize, radius: i32, sigma: f32) -> Vec<f32> {
    let taps: Vec<f32> = (-radius..=radius)
        .map(|d| (-(d * d) as f32 / (2.0 * sigma * sigma)).exp())
        .collect();
    let total: f32 = taps.iter().sum();
    let pass = |input: &[f32], horizontal: bool| -> Vec<f32> {
        let mut output = vec![0.0; input.len()];
        for y in 0..height as i32 {
            for x in 0..width as i32 {
                let mut sum = 0.0;
                for (tap, d) in taps.iter().zip(-radius..=radius) {
                    let (sx, sy) = if horizontal {
                        ((x + d).clamp(0, width as i32 - 1), y)
                    } else {
                        (x, (y + d).clamp(0, height as i32 - 1))
                    };
                    sum += tap * input[sy as usize * width + sx as usize];
                }
                output[y as usize * width + x as usize] = sum / total;
            }
        }
        output
    };
    pass(&pass(values, true), false)
}

fn ssim_map(x: &[f32], y: &[f32], width: usize, height: usize) -> Vec<f32> {
    let product = |a: &[f32], b: &[f32]| a.iter().zip(b).map(|(p, q)| p * q).collect::<Vec<_>>();
    let window = |values: &[f32]| blur(values, width, height, SSIM_RADIUS, SSIM_SIGMA);
    let (mean_x, mean_y) = (window(x), window(y));
    let xx = window(&product(x, x));
    let yy = window(&product(y, y));
    let xy = window(&product(x, y));
    (0..x.len())
        .map(|i| {
            let (mx, my) = (mean_x[i], mean_y[i]);
            let var_x = xx[i] - mx * mx;
            let var_y = yy[i] - my * my;
            let cov = xy[i] - mx * my;
            ((2.0 * mx * my + SSIM_C1) * (2.0 * cov + SSIM_C2))
                / ((mx * mx + my * my + SSIM_C1) * (var_x + var_y + SSIM_C2))
        })
        .collect()
}

fn to_srgb8(rgb: &[f32]) -> Vec<u8> {
    rgb.iter()
        .map(|v| (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8)
        .collect()
}

/// FLIP error per pixel (0 = identical, 1 = maximal), for a viewer at FLIP's default distance
/// (67 pixels per degree: a 0.7 m wide 4K monitor seen from 0.7 m).
fn flip_map(reference: &[f32], test: &[f32], width: usize, height: usize) -> Vec<f32> {
    let image = |rgb: &[f32]| FlipImageRgb8::with_data(width as u32, height as u32, &to_srgb8(rgb));
    nv_flip::flip(image(reference), image(test), DEFAULT_PIXELS_PER_DEGREE).to_vec()
}

/// Sums of per-pixel errors over one region, pooled over frames.
#[derive(Clone, Copy, Debug, Default)]
pub struct Pooled {
    pub pixels: u64,
    squared: f64,
    ssim: f64,
    flip: f64,
    detail: f64,
    reference_detail: f64,
}

impl Pooled {
    pub fn add(&mut self, maps: &ErrorMaps, pixel: usize) {
        self.pixels += 1;
        self.squared += maps.squared[pixel] as f64;
        self.ssim += maps.ssim[pixel] as f64;
        self.flip += maps.flip[pixel] as f64;
        self.detail += maps.detail[pixel] as f64;
        self.reference_detail += maps.reference_detail[pixel] as f64;
    }

    pub fn merge(&mut self, other: &Pooled) {
        self.pixels += other.pixels;
        self.squared += other.squared;
        self.ssim += other.ssim;
        self.flip += other.flip;
        self.detail += other.detail;
        self.reference_detail += other.reference_detail;
    }

    /// PSNR in dB, SSIM, mean FLIP and the detail ratio; `None` for a region with no pixels.
    pub fn scores(&self) -> Option<Scores> {
        (self.pixels > 0).then(|| {
            let n = self.pixels as f64;
            let mse = self.squared / n;
            Scores {
                psnr: if mse > 0.0 {
                    10.0 * (1.0 / mse).log10()
                } else {
                    f64::INFINITY
                },
                ssim: self.ssim / n,
                flip: self.flip / n,
                detail: self.detail / self.reference_detail,
            }
        })
    }
}

#[derive(Clone, Copy, Debug)]
pub struct Scores {
    pub psnr: f64,
    pub ssim: f64,
    pub flip: f64,
    /// The finest scale's energy against the reference's: 1 keeps its detail, below 1 is
    /// softer, above 1 is noisier or sharpened. NaN where the reference is flat.
    pub detail: f64,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ramp(width: usize, height: usize) -> Vec<f32> {
        (0..width * height * 3)
            .map(|i| ((i * 37) % 101) as f32 / 100.0)
            .collect()
    }

    #[test]
    fn identical_images_score_perfectly() {
        let image = ramp(24, 16);
        let maps = error_maps(&image, &image, 24, 16);
        let mut pooled = Pooled::default();
        for pixel in 0..24 * 16 {
            pooled.add(&maps, pixel);
        }
        let scores = pooled.scores().unwrap();
        assert_eq!(scores.psnr, f64::INFINITY);
        assert!((scores.ssim - 1.0).abs() < 1e-5, "{scores:?}");
        assert!(scores.flip < 1e-6, "{scores:?}");
        assert_eq!(scores.detail, 1.0);
    }

    #[test]
    fn a_blurred_image_keeps_less_detail() {
        let (width, height) = (32, 32);
        let reference = ramp(width, height);
        let channel = |c: usize| {
            reference
                .iter()
                .skip(c)
                .step_by(3)
                .copied()
                .collect::<Vec<_>>()
        };
        let blurred: Vec<Vec<f32>> = (0..3)
            .map(|c| blur(&channel(c), width, height, 2, 1.0))
            .collect();
        let soft: Vec<f32> = (0..width * height)
            .flat_map(|p| (0..3).map(move |c| p * 3 + c))
            .map(|i| blurred[i % 3][i / 3])
            .collect();
        let maps = error_maps(&reference, &soft, width, height);
        let mut pooled = Pooled::default();
        (0..width * height).for_each(|p| pooled.add(&maps, p));
        let detail = pooled.scores().unwrap().detail;
        assert!(detail < 0.5, "{detail}");
    }

    #[test]
    fn more_noise_scores_worse_on_every_metric() {
        let (width, height) = (32, 32);
        let reference = ramp(width, height);
        let noisy = |amount: f32| -> Vec<f32> {
            reference
                .iter()
                .enumerate()
                .map(|(i, v)| (v + amount * if i % 2 == 0 { 1.0 } else { -1.0 }).clamp(0.0, 1.0))
                .collect()
        };
        let score = |amount| {
            let maps = error_maps(&reference, &noisy(amount), width, height);
            let mut pooled = Pooled::default();
            (0..width * height).for_each(|p| pooled.add(&maps, p));
            pooled.scores().unwrap()
        };
        let (little, much) = (score(0.02), score(0.2));
        assert!(little.psnr > much.psnr + 10.0, "{little:?} {much:?}");
        assert!(little.ssim > much.ssim, "{little:?} {much:?}");
        assert!(little.flip < much.flip, "{little:?} {much:?}");
        assert!(Pooled::default().scores().is_none());
    }
}
