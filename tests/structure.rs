//! The frame graph's rule, held against the source: every barrier is placed by the recorder
//! (`src/vk/recorder.rs`) from what the passes declare, and none is written by hand elsewhere.

use std::fs;
use std::path::{Path, PathBuf};

fn rust_files(dir: &Path, found: &mut Vec<PathBuf>) {
    for entry in fs::read_dir(dir).expect("src/ reads") {
        let path = entry.expect("readable entry").path();
        if path.is_dir() {
            rust_files(&path, found);
        } else if path.extension().is_some_and(|ext| ext == "rs") {
            found.push(path);
        }
    }
}

/// The files under src/ with a line of code (comments aside) that `holds`, as paths from the
/// crate.
fn files_where(holds: impl Fn(&str) -> bool) -> Vec<String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    rust_files(&root.join("src"), &mut files);
    let mut holding: Vec<String> = files
        .iter()
        .filter(|path| {
            fs::read_to_string(path)
                .expect("a source file reads")
                .lines()
                .any(|line| !line.trim_start().starts_with("//") && holds(line))
        })
        .map(|path| {
            path.strip_prefix(root)
                .expect("under the crate")
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    holding.sort();
    holding
}

fn files_with(needle: &str) -> Vec<String> {
    files_where(|line| line.contains(needle))
}

#[test]
fn barriers_are_recorded_in_one_module() {
    assert_eq!(files_with("cmd_pipeline_barrier"), ["src/vk/barriers.rs"]);
}

#[test]
fn only_the_recorder_places_barriers() {
    // `barriers::` also names the engine-image type the calls hand to the recorder.
    let callers =
        files_where(|line| line.contains("barriers::") && !line.contains("EngineImageAccess"));
    assert_eq!(callers, ["src/vk/recorder.rs"]);
}

/// A dispatch recorded past the recorder would not be ordered: passes call `rec.dispatch`, and
/// only the recorder calls the pipeline's own.
#[test]
fn only_the_recorder_dispatches() {
    assert_eq!(files_with("cmd_dispatch"), ["src/vk/pipeline.rs"]);
    assert_eq!(files_with("dispatch(self.device"), ["src/vk/recorder.rs"]);
    assert_eq!(
        files_with("dispatch_indirect(self.device"),
        ["src/vk/recorder.rs"]
    );
    assert!(files_with("dispatch(device").is_empty());
    assert!(files_with("dispatch_indirect(device").is_empty());
}
