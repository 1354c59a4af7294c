//! `patchex eval` end to end, small: every method scored over the frame and each region, the
//! tables and the strip written, the plugin under validation.

use std::path::{Path, PathBuf};
use std::process::Command;

use patchex_scene::dataset::{read_exr, Dataset, FINAL_IMAGE};

fn run(args: &[&str]) -> String {
    let output = Command::new(env!("CARGO_BIN_EXE_patchex"))
        .args(args)
        .output()
        .expect("the patchex binary runs");
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(output.status.success(), "patchex {args:?}:\n{text}");
    text
}

/// Renders 5 frames of crossing_street (two targets between rendered frames) into `out`.
fn render_crossing_street(out: &Path, size: &str) -> PathBuf {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/crossing_street.toml");
    let dataset = out.join("crossing");
    run(&[
        "render",
        scene.to_str().unwrap(),
        "--frames",
        "5",
        "--size",
        size,
        "--out",
        dataset.to_str().unwrap(),
    ]);
    dataset
}

#[test]
fn eval_scores_every_method_over_every_region() {
    let out = tempfile::tempdir().unwrap();
    let dataset = render_crossing_street(out.path(), "160x90");
    let report = out.path().join("eval");
    let printed = run(&[
        "eval",
        dataset.to_str().unwrap(),
        "--validation",
        "--write-frames",
        "--out",
        report.to_str().unwrap(),
    ]);
    // Not on a terminal, a line per scene tells the progress.
    assert!(
        printed.contains("evaluating crossing_street: 2 targets"),
        "{printed}"
    );
    assert!(
        printed.contains("evaluated crossing_street in"),
        "{printed}"
    );
    assert!(report.join("strips/crossing_street.png").exists());
    // Every method's frames, linear as scored: the copy of frame t is frame 0 itself.
    let frames = report.join("frames/crossing_street");
    for method in ["copy", "motion-vector", "gbuffer", "interpolation"] {
        for target in ["0001", "0003"] {
            let path = frames.join(method).join(format!("{target}.exr"));
            assert!(path.is_file(), "{} is written", path.display());
        }
    }
    let copy = read_exr(&frames.join("copy/0001.exr")).unwrap();
    let frame_t = Dataset::open(&dataset).unwrap().read_frame(0).unwrap();
    assert_eq!(
        copy.layer(FINAL_IMAGE).data,
        frame_t.layer(FINAL_IMAGE).data[..]
            .chunks(frame_t.layer(FINAL_IMAGE).channel_count())
            .flat_map(|p| p[..3].to_vec())
            .collect::<Vec<_>>()
    );
    assert!(std::fs::read_to_string(report.join("eval.md"))
        .unwrap()
        .contains("interpolation (uses frame t+1)"));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(report.join("eval.json")).unwrap()).unwrap();
    let methods = json["scenes"][0]["methods"].as_array().unwrap();
    let names: Vec<&str> = methods
        .iter()
        .map(|m| m["method"].as_str().unwrap())
        .collect();
    assert_eq!(
        names,
        [
            "Copy",
            "MotionVector",
            "OcclusionMotion",
            "Gbuffer",
            "GbufferShadows",
            "Interpolation"
        ]
    );
    let score = |method: usize, region: &str, metric: &str| {
        methods[method]["regions"][region][metric]
            .as_f64()
            .unwrap_or_else(|| panic!("{metric} over {region}: {}", methods[method]))
    };
    for method in 0..methods.len() {
        for region in ["frame", "holes", "FI", "near-BE"] {
            let (ssim, flip) = (score(method, region, "ssim"), score(method, region, "flip"));
            assert!((-1.0..=1.0).contains(&ssim) && (0.0..=1.0).contains(&flip));
        }
    }
    // The default warp beats showing frame t again, on every metric over the frame.
    let (copy, gbuffer) = (0, 3);
    assert!(score(gbuffer, "frame", "psnr") > score(copy, "frame", "psnr"));
    assert!(score(gbuffer, "frame", "ssim") > score(copy, "frame", "ssim"));
    assert!(score(gbuffer, "frame", "flip") < score(copy, "frame", "flip"));
    assert!(methods[gbuffer]["gpu_ms"].as_f64().unwrap() > 0.0);
    let stages = &methods[gbuffer]["gpu_ms_per_stage"];
    for stage in ["warp", "segment", "lbp", "remodulate"] {
        assert!(stages[stage].as_f64().unwrap() > 0.0, "{stages}");
    }
    assert!(stages.get("diagnostics").is_none(), "{stages}");
    assert!(methods[copy]["gpu_ms"].is_null());
}

/// PatchEX and two ablations through the networks preset, under validation: the networks ran
/// (inference and blend timed) and are scored as every other method.
#[test]
fn eval_scores_the_networks_and_their_ablations() {
    let out = tempfile::tempdir().unwrap();
    let dataset = render_crossing_street(out.path(), "160x90");
    let report = out.path().join("eval");
    run(&[
        "eval",
        dataset.to_str().unwrap(),
        "--methods",
        "gbuffer,patchex,patchex-no-shadows,patchex-whole-frame",
        "--validation",
        "--out",
        report.to_str().unwrap(),
    ]);
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(report.join("eval.json")).unwrap()).unwrap();
    let methods = json["scenes"][0]["methods"].as_array().unwrap();
    let stage = |method: &serde_json::Value, name: &str| {
        method["gpu_ms_per_stage"][name].as_f64().unwrap_or(0.0)
    };
    assert_eq!(methods.len(), 4);
    assert_eq!(stage(&methods[0], "inference"), 0.0);
    for method in &methods[1..] {
        assert!(stage(method, "inference") > 0.0, "{method}");
        assert!(stage(method, "blend") > 0.0, "{method}");
        let psnr = method["regions"]["frame"]["psnr"].as_f64().unwrap();
        assert!(psnr > 20.0, "{method}");
    }
}

/// Calibration on characters walking across a street: each walker's wake (the high-variation
/// background connected to it) is measured inside the search window, and at under a pixel of
/// motion per target it is a pixel wide or less.
#[test]
fn calibrate_measures_each_walkers_wake() {
    let out = tempfile::tempdir().unwrap();
    let dataset = render_crossing_street(out.path(), "480x270");
    let report = out.path().join("reports/calibration.json");
    let printed = run(&[
        "calibrate",
        dataset.to_str().unwrap(),
        "--json",
        report.to_str().unwrap(),
    ]);
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    let samples = json["samples"].as_array().unwrap();
    assert!(samples.len() >= 6, "{printed}");
    let mut extension = 0.0;
    for sample in samples {
        let reached = sample["reached_window"].as_array().unwrap();
        assert!(reached.iter().all(|r| r == false), "{printed}");
        let motion = sample["mean_motion"][0].as_f64().unwrap();
        assert!(
            motion < 1.0,
            "the walkers move under a pixel a target: {printed}"
        );
        extension += sample["extension"][0].as_f64().unwrap() / samples.len() as f64;
    }
    assert!(
        (0.0..=1.0).contains(&extension),
        "a wake of a pixel or less: {extension} px; {printed}"
    );
}

/// 3x frame generation: a stream rendered with two targets between rendered frames is scored at
/// alpha 1/3 and 2/3 against the rendered instants, and the warp beats repeating frame t at both.
#[test]
fn eval_scores_both_instants_of_a_3x_stream() {
    let out = tempfile::tempdir().unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/fast_run.toml");
    let dataset = out.path().join("fast_run_3x");
    run(&[
        "render",
        scene.to_str().unwrap(),
        "--frames",
        "7",
        "--size",
        "128x72",
        "--targets-between",
        "2",
        "--out",
        dataset.to_str().unwrap(),
    ]);
    let report = out.path().join("eval");
    run(&[
        "eval",
        dataset.to_str().unwrap(),
        "--methods",
        "copy,gbuffer",
        "--out",
        report.to_str().unwrap(),
    ]);
    let markdown = std::fs::read_to_string(report.join("eval.md")).unwrap();
    let row = |label: &str| {
        // The by-alpha table's row: the label and two cells.
        markdown
            .lines()
            .find(|line| {
                line.starts_with(&format!("| {label} |")) && line.matches('|').count() == 4
            })
            .unwrap_or_else(|| panic!("{label} by alpha in:\n{markdown}"))
            .split('|')
            .map(|cell| cell.trim().split(" / ").next().unwrap().parse::<f64>().ok())
            .collect::<Vec<_>>()
    };
    assert!(
        markdown.contains("| method | alpha 1/3 | alpha 2/3 |"),
        "{markdown}"
    );
    let (copy, warp) = (
        row("copy of frame t"),
        row("G-buffer-guided warp (default)"),
    );
    for alpha in [2, 3] {
        assert!(warp[alpha].unwrap() > copy[alpha].unwrap(), "{markdown}");
    }
    // Repeating frame t is further from the truth at 2/3 than at 1/3.
    assert!(copy[2].unwrap() > copy[3].unwrap(), "{markdown}");
}
