//! The post-processing an engine runs on its HDR colour before display, on the CPU over a frame's
//! layers: bloom (light spilling around bright pixels, a lens's and an eye's glare), then tone
//! mapping to display values. Frame generators sit before it or after it; `patchex eval --post`
//! measures both placements with it.

/// How much of the light bloom spreads, and how far: two Gaussians, a tight glow and a wide
/// haze, with standard deviations as fractions of the image's height.
const BLOOM_STRENGTH: f32 = 0.08;
const BLOOM_SIGMAS: [f32; 2] = [0.01, 0.05];

/// Display values from linear HDR RGB(A): x / (1 + x) per channel, then the sRGB curve. Returns
/// RGB.
pub fn tone_map(linear: &[f32], channels: usize) -> Vec<f32> {
    linear
        .chunks(channels)
        .flat_map(|pixel| {
            pixel[..3].iter().map(|&v| {
                let mapped = (v.max(0.0) / (1.0 + v.max(0.0))).min(1.0);
                if mapped <= 0.003_130_8 {
                    mapped * 12.92
                } else {
                    1.055 * mapped.powf(1.0 / 2.4) - 0.055
                }
            })
        })
        .collect()
}

/// Linear HDR RGB(A) with bloom: (1 - strength) of each pixel's light stays, the rest spreads
/// over both Gaussians equally. Energy is kept, up to what spreads past the edges. Returns RGB.
pub fn bloom(linear: &[f32], channels: usize, width: usize, height: usize) -> Vec<f32> {
    let rgb: Vec<f32> = linear
        .chunks(channels)
        .flat_map(|pixel| {
            pixel[..3]
                .iter()
                .map(|v| if v.is_finite() { v.max(0.0) } else { 0.0 })
        })
        .collect();
    let mut out: Vec<f32> = rgb.iter().map(|v| v * (1.0 - BLOOM_STRENGTH)).collect();
    for fraction in BLOOM_SIGMAS {
        let blurred = gaussian(&rgb, width, height, fraction * height as f32);
        let share = BLOOM_STRENGTH / BLOOM_SIGMAS.len() as f32;
        out.iter_mut()
            .zip(blurred)
            .for_each(|(o, b)| *o += share * b);
    }
    out
}

/// The engine's post chain: bloom, then tone mapping.
pub fn post_process(linear: &[f32], channels: usize, width: usize, height: usize) -> Vec<f32> {
    tone_map(&bloom(linear, channels, width, height), 3)
}

/// A separable Gaussian blur of RGB, zero outside the image.
fn gaussian(rgb: &[f32], width: usize, height: usize, sigma: f32) -> Vec<f32> {
    let radius = (3.0 * sigma).ceil() as isize;
    let weights: Vec<f32> = (-radius..=radius)
        .map(|i| (-0.5 * (i as f32 / sigma).powi(2)).exp())
        .collect();
    let total: f32 = weights.iter().sum();
    let weights: Vec<f32> = weights.iter().map(|w| w / total).collect();
    let pass = |input: &[f32], along_x: bool| {
        let mut output = vec![0.0; input.len()];
        for y in 0..height {
            for x in 0..width {
                let mut sum = [0.0f32; 3];
                for (k, w) in weights.iter().enumerate() {
                    let offset = k as isize - radius;
                    let (sx, sy) = if along_x {
                        (x as isize + offset, y as isize)
                    } else {
                        (x as isize, y as isize + offset)
                    };
                    if sx < 0 || sy < 0 || sx >= width as isize || sy >= height as isize {
                        continue;
                    }
                    let at = 3 * (sy as usize * width + sx as usize);
                    for c in 0..3 {
                        sum[c] += w * input[at + c];
                    }
                }
                output[3 * (y * width + x)..][..3].copy_from_slice(&sum);
            }
        }
        output
    };
    pass(&pass(rgb, true), false)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bloom_spreads_a_bright_pixel_and_keeps_its_light() {
        let (width, height) = (64, 64);
        let mut image = vec![0.0; width * height * 3];
        image[3 * (32 * width + 32)..][..3].copy_from_slice(&[100.0, 50.0, 10.0]);
        let bloomed = bloom(&image, 3, width, height);
        let total: f32 = bloomed.iter().step_by(3).sum();
        assert!((total - 100.0).abs() < 0.5, "{total}");
        assert!(bloomed[3 * (32 * width + 32)] < 100.0 * (1.0 - BLOOM_STRENGTH) + 5.0);
        assert!(
            bloomed[3 * (32 * width + 36)] > 0.0,
            "no glow 4 pixels away"
        );
    }

    #[test]
    fn a_flat_image_keeps_its_value_away_from_the_edges() {
        let (width, height) = (200, 200);
        let image = vec![0.5; width * height * 3];
        let bloomed = bloom(&image, 3, width, height);
        assert!((bloomed[3 * (100 * width + 100)] - 0.5).abs() < 1e-3);
        let display = tone_map(&[0.0, 1.0, 1e9], 3);
        assert_eq!(display[0], 0.0);
        assert!((display[2] - 1.0).abs() < 1e-6 && display[1] > 0.7 && display[1] < 0.75);
    }
}
