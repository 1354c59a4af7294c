//! The `patchex` binary end to end: render a tiny sequence with validation, make its contact
//! sheet, inspect an asset, and reject bad arguments. And `patchex selftest` as a user runs it:
//! installed by `scripts/install.sh` into a prefix, run from a folder outside the repository,
//! where it must find its library, scene and assets beside itself. It passes on this machine's
//! driver, and fails when a pass is broken (`PATCHEX_TEST_FAULT` leaves a stage's commands out).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn patchex(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_patchex"))
        .args(args)
        .output()
        .expect("the patchex binary runs")
}

fn text(output: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    )
}

#[test]
fn render_then_sheet_writes_a_dataset_and_a_png() {
    let out = tempfile::tempdir().unwrap();
    let scene = repo().join("crates/patchex-scene/tests/scenes/shading.toml");
    let assets = repo().join("assets");
    let dataset = out.path().join("seq");
    let rendered = patchex(&[
        "render",
        scene.to_str().unwrap(),
        "--frames",
        "2",
        "--size",
        "64x36",
        "--validation",
        "--assets",
        assets.to_str().unwrap(),
        "--out",
        dataset.to_str().unwrap(),
    ]);
    assert!(rendered.status.success(), "{}", text(&rendered));
    for file in ["manifest.json", "frame_0000.exr", "frame_0001.exr"] {
        assert!(dataset.join(file).is_file(), "missing {file}");
    }

    // Missing folders on the way to the output are made.
    let sheet_path = out.path().join("sheets/new/sheet.png");
    let sheet = patchex(&[
        "sheet",
        dataset.to_str().unwrap(),
        "--frame",
        "1",
        "--out",
        sheet_path.to_str().unwrap(),
    ]);
    assert!(sheet.status.success(), "{}", text(&sheet));
    let decoder = png::Decoder::new(std::io::BufReader::new(
        std::fs::File::open(&sheet_path).unwrap(),
    ));
    let info = decoder.read_info().unwrap().info().clone();
    // 13 layers in 4 columns: 4 rows of 64x36 tiles.
    assert_eq!((info.width, info.height), (4 * 64, 4 * 36));

    // Several datasets make a gallery of the chosen layers.
    let gallery = patchex(&[
        "sheet",
        dataset.to_str().unwrap(),
        dataset.to_str().unwrap(),
        "--layers",
        "FinalImage,ShadowMask",
        "--columns",
        "2",
        "--out",
        sheet_path.to_str().unwrap(),
    ]);
    assert!(gallery.status.success(), "{}", text(&gallery));
    let decoder = png::Decoder::new(std::io::BufReader::new(
        std::fs::File::open(&sheet_path).unwrap(),
    ));
    let info = decoder.read_info().unwrap().info().clone();
    assert_eq!((info.width, info.height), (2 * 64, 2 * 36));

    let missing = patchex(&[
        "sheet",
        dataset.to_str().unwrap(),
        "--layers",
        "Albedo",
        "--out",
        sheet_path.to_str().unwrap(),
    ]);
    assert!(!missing.status.success());
    assert!(text(&missing).contains("Albedo"), "{}", text(&missing));
}

#[test]
fn inspect_lists_the_clips_of_an_asset() {
    let asset = repo().join("assets/characters/RobotExpressive.glb");
    let output = patchex(&["inspect", asset.to_str().unwrap()]);
    assert!(output.status.success(), "{}", text(&output));
    let listing = text(&output);
    assert!(
        listing.contains("clip \"Dance\"") && listing.contains("skins 2"),
        "{listing}"
    );
}

#[test]
fn bad_sizes_and_missing_scenes_are_reported() {
    let bad_size = patchex(&[
        "render",
        "x.toml",
        "--size",
        "640by360",
        "--out",
        "/tmp/unused",
    ]);
    assert!(!bad_size.status.success());
    assert!(
        text(&bad_size).contains("WIDTHxHEIGHT"),
        "{}",
        text(&bad_size)
    );

    let missing = patchex(&["render", "/nonexistent/scene.toml", "--out", "/tmp/unused"]);
    assert!(!missing.status.success());
    assert!(
        text(&missing).contains("/nonexistent/scene.toml"),
        "{}",
        text(&missing)
    );
}

/// `patchex patches --holes` writes each target's whole frame: its holes as the region, the
/// planes the networks read, and the target's G-buffer as `guide`, whose modulation turns the
/// demodulated target back into the rendered colour.
#[test]
fn patches_with_holes_writes_whole_frames_with_their_guide() {
    use patchex_scene::dataset::{Dataset, FINAL_IMAGE};
    use safetensors::SafeTensors;

    let out = tempfile::tempdir().unwrap();
    let scene = repo().join("crates/patchex-scene/tests/scenes/crossing.toml");
    let dataset = out.path().join("seq");
    let rendered = patchex(&[
        "render",
        scene.to_str().unwrap(),
        "--frames",
        "3",
        "--size",
        "96x54",
        "--assets",
        repo().join("assets").to_str().unwrap(),
        "--out",
        dataset.to_str().unwrap(),
    ]);
    assert!(rendered.status.success(), "{}", text(&rendered));
    let samples = out.path().join("samples");
    let written = patchex(&[
        "patches",
        dataset.to_str().unwrap(),
        "--holes",
        "--out",
        samples.to_str().unwrap(),
    ]);
    assert!(written.status.success(), "{}", text(&written));

    let bytes = std::fs::read(samples.join("seq_0001_holes.safetensors")).unwrap();
    let tensors = SafeTensors::deserialize(&bytes).unwrap();
    let plane = |name: &str, channels: usize| -> Vec<f32> {
        let view = tensors.tensor(name).unwrap();
        assert_eq!(view.shape(), [channels, 54, 96], "{name}");
        view.data()
            .chunks(4)
            .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
            .collect()
    };
    let (input, target, region, hole, guide) = (
        plane("input", 8),
        plane("target", 3),
        plane("region", 1),
        plane("hole", 1),
        plane("guide", 8),
    );
    let pixels = 96 * 54;
    assert_eq!(region, hole);
    assert_eq!(
        &input[3 * pixels..4 * pixels],
        &hole[..],
        "the input's hole plane"
    );
    assert!(hole.iter().all(|&h| h == 0.0 || h == 1.0));
    let holes = hole.iter().filter(|&&h| h == 1.0).count();
    assert!(holes > 0 && holes < pixels / 2, "{holes} holes");

    let truth = Dataset::open(&dataset).unwrap().read_frame(1).unwrap();
    let colour = truth.layer(FINAL_IMAGE);
    let mut checked = 0;
    for y in 0..54 {
        for x in 0..96 {
            let i = y * 96 + x;
            let normal: f32 = (0..3).map(|c| guide[c * pixels + i].powi(2)).sum();
            assert!((normal.sqrt() - 1.0).abs() < 1e-3, "normal at ({x}, {y})");
            for c in 0..3 {
                let modulation = guide[(5 + c) * pixels + i];
                let rendered = colour.value(x, y, c);
                if modulation > 0.05 && rendered < 1e3 {
                    let back = target[c * pixels + i] * modulation;
                    assert!(
                        (back - rendered).abs() <= 1e-3 * rendered.max(1.0),
                        "({x}, {y}) channel {c}: {back} against {rendered}"
                    );
                    checked += 1;
                }
            }
        }
    }
    assert!(checked > pixels, "{checked} values checked");
}

#[test]
fn an_installed_selftest_passes_and_fails_on_a_broken_pass() {
    // The tool and the library this build made, installed as a user would install them.
    let tool = PathBuf::from(env!("CARGO_BIN_EXE_patchex"));
    let library = tool.with_file_name("libpatchex.so");
    assert!(
        library.is_file(),
        "{} is built first (cargo build -p patchex)",
        library.display()
    );
    let prefix = tempfile::tempdir().unwrap();
    let installed = Command::new(repo().join("scripts/install.sh"))
        .args([prefix.path(), &library, &tool])
        .output()
        .expect("install.sh runs");
    assert!(installed.status.success(), "{}", text(&installed));

    let elsewhere = tempfile::tempdir().unwrap();
    let selftest = |fault: Option<&str>| {
        let mut command = Command::new(prefix.path().join("bin/patchex"));
        command
            .args(["selftest", "--size", "96x54"])
            .current_dir(elsewhere.path())
            .env_remove("PATCHEX_TEST_FAULT");
        if let Some(stage) = fault {
            command.env("PATCHEX_TEST_FAULT", stage);
        }
        command.output().expect("the installed tool runs")
    };

    let clean = selftest(None);
    let report = text(&clean);
    assert!(clean.status.success(), "{report}");
    assert!(report.contains("selftest: PASS"), "{report}");
    assert_eq!(
        report.matches("\nPASS ").count(),
        10,
        "a line per configuration: {report}"
    );
    assert!(
        report.contains("validation and synchronization validation on"),
        "{report}"
    );

    let broken = selftest(Some("remodulate"));
    let report = text(&broken);
    assert_eq!(broken.status.code(), Some(1), "{report}");
    assert!(report.contains("selftest: FAIL"), "{report}");
    assert!(
        report.contains("FAIL warp + shadows (WARP_AND_SHADOWS)"),
        "the configurations that remodulate on their own fail: {report}"
    );
}
