//! `patchex calibrate DATASET...`: fits k_x and k_y of Algorithm 1 (the growth of each dynamic
//! object's rectangle into its near-background region) from temporal-variation analysis, as the
//! PatchEX paper derives them.
//!
//! For every target frame and every dynamic object on it:
//! 1. the per-pixel change between the target and frame t, after following the target's motion
//!    vectors back into frame t (with a moving camera the raw change covers the whole screen;
//!    following the vectors leaves what motion cannot explain: disocclusions, moving shadows,
//!    the object's edges), as mean absolute change over the RGB channels of tone-mapped colour;
//! 2. Otsu's threshold over the frame splits it into low and high variation;
//! 3. the object's wake: the high-variation background pixels connected to the object through
//!    high-variation background pixels, within a search window around it. The rectangle around
//!    the object and its wake, its extension beyond the object's bounds per axis and averaged
//!    over the two sides, is one sample against the object's mean |motion| on that axis.
//!    Connected pixels only: with a moving camera, high variation is scattered over the whole
//!    background (foliage, speculars, anti-aliased edges), and counting every such pixel in the
//!    window measured the window instead of the object (the fitted k followed the window's
//!    size). The fit reports how many samples reached the window, which bounds what it can
//!    measure.
//!
//! k is the least-squares slope of extension against mean |motion| (the intercept takes the
//! pixel or two that anti-aliased edges add at any motion); the Pearson correlation says how
//! well motion predicts the extension. An axis along which the objects barely move (r below
//! `MIN_CORRELATION`) cannot be fitted and takes the other axis's k.

use std::path::PathBuf;

use clap::Args;
use patchex_scene::dataset::{Dataset, FrameRole, CUSTOM_STENCIL, FINAL_IMAGE, MOTION_VECTOR};
use serde_json::json;

use super::picture::tone_map;
use super::CommandResult;

/// The search window reaches this many pixels, plus `WINDOW_PER_MOTION` times the mean motion,
/// beyond the object's bounds: it bounds the k that can be measured.
const WINDOW_PIXELS: f32 = 4.0;
const WINDOW_PER_MOTION: f32 = 32.0;
/// Objects smaller than this tell little about their surroundings.
const MIN_OBJECT_PIXELS: usize = 16;
/// Objects that move less than this (pixels per target interval) give no growth to measure.
const MIN_MOTION: f32 = 0.05;
const OTSU_BINS: usize = 256;
/// Below this correlation an axis's slope is noise.
const MIN_CORRELATION: f64 = 0.3;

#[derive(Args)]
pub struct CalibrateArgs {
    /// Dataset folders written by `patchex render`.
    #[arg(required = true)]
    datasets: Vec<PathBuf>,
    /// Also write the samples and the fit as JSON here.
    #[arg(long)]
    json: Option<PathBuf>,
}

/// One object on one target frame: mean |motion| and measured extension, per axis.
#[derive(Clone, Copy, Debug)]
struct Sample {
    motion: [f32; 2],
    extension: [f32; 2],
    /// Whether the wake reached the search window on this axis: the extension is then a lower
    /// bound.
    reached_window: [bool; 2],
}

pub fn run(args: CalibrateArgs) -> CommandResult {
    let mut samples = Vec::new();
    for dir in &args.datasets {
        let dataset = Dataset::open(dir)?;
        let before = samples.len();
        for info in &dataset.manifest.frames {
            if info.role == FrameRole::Target && info.index > 0 {
                let previous = dataset.read_frame(dataset.manifest.source_of(info.index).0)?;
                let target = dataset.read_frame(info.index)?;
                samples.extend(frame_samples(&previous, &target));
            }
        }
        println!(
            "{}: {} object samples",
            dataset.manifest.scene,
            samples.len() - before
        );
    }
    if samples.len() < 2 {
        return Err("fewer than two moving objects in the datasets: nothing to fit".into());
    }
    let mut fits = Vec::new();
    for (axis, name) in ["x", "y"].iter().enumerate() {
        let points: Vec<(f64, f64)> = samples
            .iter()
            .map(|s| (s.motion[axis] as f64, s.extension[axis] as f64))
            .collect();
        let fit = fit_line(&points);
        let bounded = samples.iter().filter(|s| s.reached_window[axis]).count();
        println!(
            "{name}: extension = {:.2} * mean|v_{name}| + {:.2} px; Pearson r = {:.3} over {} \
             samples (mean|v_{name}| {:.2} px, mean extension {:.2} px; {bounded} reached the \
             search window)",
            fit.slope,
            fit.intercept,
            fit.correlation,
            points.len(),
            fit.mean_x,
            fit.mean_y
        );
        fits.push(fit);
    }
    let fitted = |fit: &Fit| fit.correlation >= MIN_CORRELATION;
    let k = match (fitted(&fits[0]), fitted(&fits[1])) {
        (true, true) => Some([fits[0].slope, fits[1].slope]),
        (true, false) => Some([fits[0].slope; 2]),
        (false, true) => Some([fits[1].slope; 2]),
        (false, false) => None,
    };
    match k {
        Some(k) => println!("k_x = {:.2}, k_y = {:.2}", k[0], k[1]),
        None => println!(
            "no fit: motion does not predict the extension on either axis (r below \
             {MIN_CORRELATION}); keep k"
        ),
    }
    if let Some(path) = &args.json {
        let report = json!({
            "k_x": k.map(|k| k[0]),
            "k_y": k.map(|k| k[1]),
            "slope_x": fits[0].slope,
            "slope_y": fits[1].slope,
            "intercept_x": fits[0].intercept,
            "intercept_y": fits[1].intercept,
            "correlation_x": fits[0].correlation,
            "correlation_y": fits[1].correlation,
            "samples": samples.iter().map(|s| json!({
                "mean_motion": s.motion,
                "extension": s.extension,
                "reached_window": s.reached_window,
            })).collect::<Vec<_>>(),
        });
        super::write_output(path, serde_json::to_string_pretty(&report)? + "\n")?;
    }
    Ok(())
}

/// Per-pixel motion-compensated change of the target from frame t, in [0, 1].
fn variation(
    previous: &patchex_scene::FrameLayers,
    target: &patchex_scene::FrameLayers,
) -> Vec<f32> {
    let (width, height) = (target.width, target.height);
    let before = tone_map(&previous.layer(FINAL_IMAGE).data, 3);
    let now = tone_map(&target.layer(FINAL_IMAGE).data, 3);
    let motion = target.layer(MOTION_VECTOR);
    (0..width * height)
        .map(|p| {
            let (x, y) = (p % width, p / width);
            let v = motion.pixel(x, y);
            let sx = ((x as f32 + 0.5 + v[0]).floor() as i64).clamp(0, width as i64 - 1) as usize;
            let sy = ((y as f32 + 0.5 + v[1]).floor() as i64).clamp(0, height as i64 - 1) as usize;
            let s = sy * width + sx;
            (0..3)
                .map(|c| (now[p * 3 + c] - before[s * 3 + c]).abs())
                .sum::<f32>()
                / 3.0
        })
        .collect()
}

/// Otsu's threshold: the split of `values` (in [0, 1]) that maximises between-class variance.
fn otsu_threshold(values: &[f32]) -> f32 {
    let mut histogram = [0u64; OTSU_BINS];
    for v in values {
        histogram[((v.clamp(0.0, 1.0) * (OTSU_BINS - 1) as f32) as usize).min(OTSU_BINS - 1)] += 1;
    }
    let total = values.len() as f64;
    let sum_all: f64 = histogram
        .iter()
        .enumerate()
        .map(|(i, n)| i as f64 * *n as f64)
        .sum();
    let (mut below, mut sum_below) = (0.0, 0.0);
    let (mut best, mut best_bin) = (-1.0, 0);
    for (bin, count) in histogram.iter().enumerate() {
        below += *count as f64;
        sum_below += bin as f64 * *count as f64;
        let above = total - below;
        if below == 0.0 || above == 0.0 {
            continue;
        }
        let mean_below = sum_below / below;
        let mean_above = (sum_all - sum_below) / above;
        let between = below * above * (mean_below - mean_above).powi(2);
        if between > best {
            best = between;
            best_bin = bin;
        }
    }
    (best_bin as f32 + 1.0) / (OTSU_BINS - 1) as f32
}

fn frame_samples(
    previous: &patchex_scene::FrameLayers,
    target: &patchex_scene::FrameLayers,
) -> Vec<Sample> {
    let (width, height) = (target.width, target.height);
    let change = variation(previous, target);
    let threshold = otsu_threshold(&change);
    let stencil = target.layer(CUSTOM_STENCIL);
    let motion = target.layer(MOTION_VECTOR);
    let id_at = |x: usize, y: usize| stencil.value(x, y, 0) as u32;

    // Bounds, pixel count and |motion| sums per object id.
    let mut objects: std::collections::BTreeMap<u32, ([usize; 4], usize, [f32; 2])> =
        Default::default();
    for y in 0..height {
        for x in 0..width {
            let id = id_at(x, y);
            if id == 0 {
                continue;
            }
            let v = motion.pixel(x, y);
            let entry = objects.entry(id).or_insert(([x, y, x, y], 0, [0.0; 2]));
            entry.0 = [
                entry.0[0].min(x),
                entry.0[1].min(y),
                entry.0[2].max(x),
                entry.0[3].max(y),
            ];
            entry.1 += 1;
            entry.2[0] += v[0].abs();
            entry.2[1] += v[1].abs();
        }
    }
    objects
        .iter()
        .filter(|(_, (_, pixels, _))| *pixels >= MIN_OBJECT_PIXELS)
        .filter_map(|(&id, &([left, top, right, bottom], pixels, sums))| {
            let mean = [sums[0] / pixels as f32, sums[1] / pixels as f32];
            if mean[0].max(mean[1]) < MIN_MOTION {
                return None;
            }
            let reach = |m: f32| (WINDOW_PIXELS + WINDOW_PER_MOTION * m).ceil() as usize;
            let window = [
                left.saturating_sub(reach(mean[0])),
                top.saturating_sub(reach(mean[1])),
                (right + reach(mean[0])).min(width - 1),
                (bottom + reach(mean[1])).min(height - 1),
            ];
            let wake = Wake {
                window,
                width,
                in_wake: |x: usize, y: usize| id_at(x, y) == 0 && change[y * width + x] > threshold,
            };
            let object: Vec<(usize, usize)> = (top..=bottom)
                .flat_map(|y| (left..=right).map(move |x| (x, y)))
                .filter(|&(x, y)| id_at(x, y) == id)
                .collect();
            let grown = wake.bounds(&object, [left, top, right, bottom]);
            let reached_window = [
                grown[0] == window[0] && window[0] > 0
                    || grown[2] == window[2] && window[2] < width - 1,
                grown[1] == window[1] && window[1] > 0
                    || grown[3] == window[3] && window[3] < height - 1,
            ];
            // Sides the image edge cuts off measure the edge, not the object: average the others.
            let extension =
                |low: usize, high: usize, grown_low: usize, grown_high: usize, limit: usize| {
                    let mut sides = Vec::new();
                    if low > 0 {
                        sides.push((low - grown_low) as f32);
                    }
                    if high < limit - 1 {
                        sides.push((grown_high - high) as f32);
                    }
                    (!sides.is_empty()).then(|| sides.iter().sum::<f32>() / sides.len() as f32)
                };
            Some(Sample {
                motion: mean,
                extension: [
                    extension(left, right, grown[0], grown[2], width)?,
                    extension(top, bottom, grown[1], grown[3], height)?,
                ],
                reached_window,
            })
        })
        .collect()
}

/// The high-variation background connected to an object, within a window.
struct Wake<F> {
    /// Left, top, right, bottom, inclusive.
    window: [usize; 4],
    width: usize,
    in_wake: F,
}

impl<F: Fn(usize, usize) -> bool> Wake<F> {
    /// `bounds` grown to every wake pixel reachable from `object`'s pixels through 4-connected
    /// wake pixels inside the window.
    fn bounds(&self, object: &[(usize, usize)], mut bounds: [usize; 4]) -> [usize; 4] {
        let [left, top, right, bottom] = self.window;
        let mut seen = vec![false; self.width * (bottom + 1)];
        let mut stack = object.to_vec();
        while let Some((x, y)) = stack.pop() {
            let neighbours = [
                (x > left).then(|| (x - 1, y)),
                (x < right).then(|| (x + 1, y)),
                (y > top).then(|| (x, y - 1)),
                (y < bottom).then(|| (x, y + 1)),
            ];
            for (nx, ny) in neighbours.into_iter().flatten() {
                let visited = &mut seen[ny * self.width + nx];
                if !*visited && (self.in_wake)(nx, ny) {
                    *visited = true;
                    bounds = [
                        bounds[0].min(nx),
                        bounds[1].min(ny),
                        bounds[2].max(nx),
                        bounds[3].max(ny),
                    ];
                    stack.push((nx, ny));
                }
            }
        }
        bounds
    }
}

struct Fit {
    slope: f64,
    intercept: f64,
    correlation: f64,
    mean_x: f64,
    mean_y: f64,
}

/// Least-squares line through `points`.
fn fit_line(points: &[(f64, f64)]) -> Fit {
    let n = points.len() as f64;
    let mean_x = points.iter().map(|(x, _)| x).sum::<f64>() / n;
    let mean_y = points.iter().map(|(_, y)| y).sum::<f64>() / n;
    let cov: f64 = points
        .iter()
        .map(|(x, y)| (x - mean_x) * (y - mean_y))
        .sum();
    let var_x: f64 = points.iter().map(|(x, _)| (x - mean_x).powi(2)).sum();
    let var_y: f64 = points.iter().map(|(_, y)| (y - mean_y).powi(2)).sum();
    let slope = if var_x > 0.0 { cov / var_x } else { 0.0 };
    Fit {
        slope,
        intercept: mean_y - slope * mean_x,
        correlation: if var_x > 0.0 && var_y > 0.0 {
            cov / (var_x * var_y).sqrt()
        } else {
            0.0
        },
        mean_x,
        mean_y,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn otsu_splits_two_clusters_between_them() {
        let values: Vec<f32> = (0..1000)
            .map(|i| {
                if i % 4 == 0 {
                    0.8 + (i % 7) as f32 * 0.01
                } else {
                    0.05 + (i % 5) as f32 * 0.01
                }
            })
            .collect();
        let threshold = otsu_threshold(&values);
        assert!(threshold > 0.09 && threshold < 0.8, "{threshold}");
    }

    #[test]
    fn wake_holds_what_touches_the_object_and_stops_at_the_window() {
        // A 12x6 frame: the object in columns 4-5, a high-variation strip two pixels wide to
        // its left (what it uncovered), and high-variation pixels that touch neither, one of
        // them inside the window.
        let width = 12;
        let high = |x: usize, y: usize| (x == 2 || x == 3) && y >= 1 || (x, y) == (8, 2);
        let object: Vec<(usize, usize)> = (1..5).flat_map(|y| [(4, y), (5, y)]).collect();
        let wake = Wake {
            window: [0, 0, 9, 5],
            width,
            in_wake: |x: usize, y: usize| !(4..=5).contains(&x) && high(x, y),
        };
        assert_eq!(wake.bounds(&object, [4, 1, 5, 4]), [2, 1, 5, 5]);
        let narrow = Wake {
            window: [3, 0, 9, 5],
            ..wake
        };
        assert_eq!(narrow.bounds(&object, [4, 1, 5, 4]), [3, 1, 5, 5]);
    }

    #[test]
    fn fit_recovers_a_linear_law() {
        let points: Vec<(f64, f64)> = (1..20).map(|i| (i as f64, 2.5 * i as f64 + 1.0)).collect();
        let fit = fit_line(&points);
        assert!((fit.slope - 2.5).abs() < 1e-12);
        assert!((fit.intercept - 1.0).abs() < 1e-12);
        assert!((fit.correlation - 1.0).abs() < 1e-12);
    }
}
