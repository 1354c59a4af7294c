//! `patchex selftest` as a user runs it: installed by `scripts/install.sh` into a prefix, run
//! from a folder outside the repository, where it must find its library, scene and assets
//! beside itself. It passes on this machine's driver, and fails when a pass is broken
//! (`PATCHEX_TEST_FAULT` leaves a stage's commands out).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn text(output: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    )
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
        6,
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
