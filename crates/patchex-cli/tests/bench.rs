//! `patchex bench` end to end at small sizes: every configuration measured at every size, the
//! table in the paper's stage groups, the growth with resolution, and the plot.

use std::path::Path;
use std::process::Command;

#[test]
fn bench_measures_every_configuration_at_every_size_and_plots_the_trade() {
    let out = tempfile::tempdir().unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/shadow_terrain.toml");
    let output = Command::new(env!("CARGO_BIN_EXE_patchex"))
        .args(["bench", "--scenes", scene.to_str().unwrap()])
        .args(["--sizes", "96x54,192x108", "--frames", "5", "--out"])
        .arg(out.path())
        .output()
        .expect("the patchex binary runs");
    let printed = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "patchex bench:\n{printed}");

    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.path().join("bench.json")).unwrap())
            .unwrap();
    // The fixed costs of a command, measured on the device: a dispatch takes time.
    assert!(
        json["fixed_costs_us"]["dispatch"].as_f64().unwrap() > 0.0,
        "{}",
        json["fixed_costs_us"]
    );
    assert!(json["fixed_costs_us"]["barrier"]
        .as_f64()
        .unwrap()
        .is_finite());
    let rows = json["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 2 * 11, "two sizes, eleven configurations");
    for row in rows {
        // Targets 3 (frames 0, 2 and 3); every stage group took time, inference only where
        // networks ran.
        assert_eq!(row["targets"], 1, "{row}");
        assert!(row["psnr"].as_f64().unwrap() > 20.0, "{row}");
        for group in ["G-buffer", "warping", "preprocessing"] {
            assert!(row["gpu_ms"][group].as_f64().unwrap() > 0.0, "{row}");
        }
        let configuration = row["configuration"].as_str().unwrap();
        let networks = configuration.starts_with("Patchex");
        // Warp-only configurations remodulate in the warp: nothing is left to blend.
        let warp_only = [
            "MotionVector",
            "OcclusionMotion",
            "Gbuffer",
            "GbufferBilinear",
            "GbufferHighlights",
        ]
        .contains(&configuration);
        let blending = row["gpu_ms"]["blending"].as_f64().unwrap();
        assert_eq!(blending > 0.0, !warp_only, "{row}");
        // Every configuration reports its context's memory and each stage's traffic.
        assert!(
            row["costs"]["device_memory_bytes"].as_u64().unwrap() > 0,
            "{row}"
        );
        assert!(
            row["costs"]["bytes_per_pixel"].as_f64().unwrap() > 0.0,
            "{row}"
        );
        let inference = row["gpu_ms"]["inference"].as_f64().unwrap();
        assert_eq!(inference > 0.0, networks, "{row}");
    }
    // The shadow sub-task costs time on top of the same warp.
    let total = |label: &str, height: u64| {
        rows.iter()
            .find(|r| r["label"] == label && r["height"] == height)
            .unwrap()["total_gpu_ms"]
            .as_f64()
            .unwrap()
    };
    assert!(
        total("G-buffer-guided warp + shadows (WARP_AND_SHADOWS)", 108)
            > total("G-buffer-guided warp (WARP_ONLY)", 108)
    );

    let markdown = std::fs::read_to_string(out.path().join("bench.md")).unwrap();
    assert!(
        markdown.contains("| 108p | G-buffer-guided warp + shadows (WARP_AND_SHADOWS) |"),
        "{markdown}"
    );
    assert!(markdown.contains("Growth with resolution"), "{markdown}");
    assert!(markdown.contains("| 108p |") && markdown.contains("whole frame / patches"));
    assert!(markdown.contains("Catmull-Rom / bilinear"), "{markdown}");
    assert!(
        markdown.contains("µs per dispatch among independent"),
        "{markdown}"
    );
    let plot = std::fs::read(out.path().join("trade.png")).unwrap();
    assert!(plot.starts_with(b"\x89PNG"), "trade.png is a PNG");
}
