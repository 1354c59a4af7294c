//! The C++ engine in examples/cpp-engine, built the way a C++ user builds against patchex:
//! the library installed into a prefix with scripts/install.sh, found by CMake's
//! find_package (and by pkg-config), then run for 30 frames under the validation layers with
//! the full preset, the shadow input and a HUD drawn over every generated frame; and once more
//! with the target's shadow mask and the flow off.

mod support;

use std::path::PathBuf;
use std::process::Command;

use patchex::abi::PATCHEX_ABI_VERSION;
use patchex::loader::PatchexLibrary;
use support::{install, pkg_config_flags, run};

#[test]
fn cpp_engine_renders_and_extrapolates_30_frames_on_its_render_thread() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let scratch = tempfile::tempdir().expect("a scratch directory");
    let (prefix, build) = (scratch.path().join("prefix"), scratch.path().join("build"));
    install(&root, &prefix);

    let flags = pkg_config_flags(&prefix);
    assert!(
        flags.contains("-lpatchex") && flags.contains(&format!("{}/include", prefix.display())),
        "pkg-config finds the installed patchex: {flags}"
    );

    run(
        Command::new("cmake")
            .arg("-S")
            .arg(root.join("examples/cpp-engine"))
            .arg("-B")
            .arg(&build)
            .arg(format!("-DCMAKE_PREFIX_PATH={}", prefix.display())),
        "cmake configure",
    );
    run(
        Command::new("cmake").arg("--build").arg(&build),
        "cmake --build",
    );
    let engine = |extra: &[&str]| {
        let output = run(
            Command::new(build.join("patchex-cpp-engine"))
                .args(["--frames", "30"])
                .args(extra),
            "the C++ engine",
        );
        println!("{output}");
        assert_eq!(
            output.matches("PSNR").count(),
            2 * 30 + 1,
            "a PSNR per extrapolated frame and the mean"
        );
        assert!(output.contains("HUD drawn for its own instant over 60 generated frames"));
        assert!(output.contains("ok (0 validation messages)"));
        let mean = output
            .lines()
            .find_map(|line| line.strip_prefix("mean PSNR over 60 extrapolated frames: "))
            .and_then(|rest| rest.split(' ').next()?.parse::<f64>().ok())
            .expect("the mean PSNR is printed");
        (output, mean)
    };
    let (output, with_flow) = engine(&[]);
    assert!(output.contains("preset FULL with the shadow input,"));
    // The balls' shadows at each in-between instant, and no flow.
    let (output, with_mask) = engine(&["--target-shadows"]);
    assert!(output.contains("preset FULL with the shadow input and the target's shadow mask"));
    assert!(
        with_mask > with_flow,
        "{with_mask} dB with the target's shadow mask against {with_flow} dB without"
    );
}

/// The shared library exports the patchex_* entry points and nothing else of its own, and is
/// named libpatchex.so.N by its ABI version.
#[test]
fn library_exports_only_the_c_abi() {
    let library = PatchexLibrary::beside_current_exe().expect("the patchex cdylib is built");
    let output = Command::new("nm")
        .args(["-D", "--defined-only"])
        .arg(&library)
        .output()
        .expect("nm runs");
    assert!(output.status.success());
    let symbols: Vec<String> = String::from_utf8_lossy(&output.stdout)
        .lines()
        .filter_map(|line| line.split_whitespace().nth(2).map(str::to_string))
        .collect();
    let expected = [
        "patchex_abi_version",
        "patchex_create",
        "patchex_destroy",
        "patchex_extrapolate",
        "patchex_get_frame_stats",
        "patchex_last_error",
        "patchex_result_string",
        "patchex_submit_gbuffers",
    ];
    for name in expected {
        assert!(symbols.iter().any(|s| s == name), "{name} is exported");
    }
    let dynamic = Command::new("readelf")
        .arg("-d")
        .arg(&library)
        .output()
        .expect("readelf runs");
    let soname = format!("Library soname: [libpatchex.so.{PATCHEX_ABI_VERSION}]");
    assert!(
        String::from_utf8_lossy(&dynamic.stdout).contains(&soname),
        "the library's SONAME carries the ABI version: {soname}"
    );
    let unexpected: Vec<_> = symbols
        .iter()
        .filter(|s| !expected.contains(&s.as_str()))
        .collect();
    assert!(unexpected.is_empty(), "unexpected exports: {unexpected:?}");
}
