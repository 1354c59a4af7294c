//! The main job end to end, small: `patchex demo` renders a real scene, extrapolates through the
//! plugin's shared library under validation, and reports extrapolation beating frame t.

use std::path::Path;
use std::process::Command;

/// Runs the demo on crossing_street, 6 frames at 128x72 under validation, with `options`;
/// returns its output folder and what it printed.
fn demo(options: &[&str]) -> (tempfile::TempDir, String) {
    let repo = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let out = tempfile::tempdir().unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_patchex"))
        .arg("demo")
        .arg(repo.join("scenes/crossing_street.toml"))
        .args(["--frames", "6", "--size", "128x72", "--validation"])
        .args(options)
        .arg("--out")
        .arg(out.path())
        .output()
        .expect("the patchex binary runs");
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(output.status.success(), "{text}");
    (out, text)
}

#[test]
fn demo_extrapolates_a_rendered_scene_and_writes_its_report() {
    let (out, text) = demo(&[]);
    for target in [1, 3, 5] {
        assert!(
            out.path()
                .join(format!("strips/target_{target:04}.png"))
                .exists(),
            "{text}"
        );
    }
    let summary = std::fs::read_to_string(out.path().join("summary.json")).unwrap();
    let numbers = |key: &str| -> Vec<f64> {
        summary
            .split(&format!("\"{key}\": "))
            .skip(1)
            .map(|rest| {
                rest.split([',', '}'])
                    .next()
                    .unwrap()
                    .trim()
                    .parse()
                    .unwrap()
            })
            .collect()
    };
    let (extrapolated, frame_t) = (numbers("psnr_extrapolated"), numbers("psnr_frame_t"));
    assert_eq!(extrapolated.len(), 3, "{summary}");
    for (e, t) in extrapolated.iter().zip(&frame_t) {
        assert!(
            e > t,
            "extrapolated {e:.2} dB should beat frame t {t:.2} dB\n{summary}"
        );
    }
}

/// With the target's shadow masks: every target runs the target shadows stage, and no flow.
#[test]
fn demo_hands_the_plugin_the_target_shadow_masks() {
    let (out, _) = demo(&["--shadows", "--target-shadows"]);
    let summary = std::fs::read_to_string(out.path().join("summary.json")).unwrap();
    assert_eq!(
        summary.matches("\"target shadows\": ").count(),
        3,
        "{summary}"
    );
    assert!(!summary.contains("\"shadow flow\": "), "{summary}");

    // The mask alone is refused: it needs the shadow input.
    let refused = Command::new(env!("CARGO_BIN_EXE_patchex"))
        .args(["demo", "--target-shadows"])
        .output()
        .expect("the patchex binary runs");
    assert!(!refused.status.success());
}
