//! Builds the C++17 engine program in tests/cpp against include/patchex.h and the built shared
//! library, as a C++ engine would, and runs it under the validation layers.

use std::path::PathBuf;
use std::process::Command;

use patchex::loader::PatchexLibrary;

#[test]
fn cpp_engine_extrapolates_through_the_header() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let library = PatchexLibrary::beside_current_exe().expect("the patchex cdylib is built");
    let library_dir = library.parent().unwrap();
    let binary = library_dir.join("cpp-extrapolate-once");
    let compiled = Command::new("g++")
        // Vulkan's `VkFoo info{VK_STRUCTURE_TYPE_FOO}` idiom leaves the other fields zeroed.
        .args([
            "-std=c++17",
            "-Wall",
            "-Wextra",
            "-Werror",
            "-Wno-missing-field-initializers",
            "-O1",
        ])
        .arg("-I")
        .arg(root.join("include"))
        .arg(root.join("tests/cpp/extrapolate_once.cpp"))
        .arg("-o")
        .arg(&binary)
        .arg(format!("-L{}", library_dir.display()))
        .arg(format!("-Wl,-rpath,{}", library_dir.display()))
        .args(["-lpatchex", "-lvulkan"])
        .status()
        .expect("g++ runs");
    assert!(
        compiled.success(),
        "the C++ engine compiles against include/patchex.h"
    );
    let run = Command::new(&binary).output().expect("the C++ engine runs");
    let stdout = String::from_utf8_lossy(&run.stdout);
    println!("{stdout}{}", String::from_utf8_lossy(&run.stderr));
    assert!(run.status.success(), "the C++ engine reports failure");
    assert!(stdout.contains("ok (0 validation messages)"));
}

/// The shared library exports the patchex_* entry points and nothing else of its own.
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
    let unexpected: Vec<_> = symbols
        .iter()
        .filter(|s| !expected.contains(&s.as_str()))
        .collect();
    assert!(unexpected.is_empty(), "unexpected exports: {unexpected:?}");
}
