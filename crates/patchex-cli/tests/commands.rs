//! The `patchex` binary end to end: render a tiny sequence with validation, make its contact
//! sheet, inspect an asset, and reject bad arguments.

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
