pub mod bench;
pub mod calibrate;
pub mod costs;
pub mod demo;
pub mod eval;
pub mod fixed_costs;
pub mod inspect;
pub mod interpolate;
pub mod metrics;
pub mod patches;
pub mod picture;
pub mod plugin_driver;
pub mod reference_frames;
pub mod render;
pub mod scenes;
pub mod selftest;
pub mod sheet;

/// Errors of any subcommand, shown to the user as one line.
pub type CommandResult = Result<(), Box<dyn std::error::Error>>;

/// A file patchex ships (a default scene, its assets, weights), whatever the working directory:
/// beside an installed tool, in PREFIX/share/patchex/ as `scripts/install.sh` lays it out, else
/// in the repository the tool was built from, else in the working directory (a built tool
/// copied beside another checkout, as on a machine without a toolchain).
pub fn shipped_path(relative: &str) -> std::path::PathBuf {
    let installed = std::env::current_exe().ok().and_then(|exe| {
        let share = exe.parent()?.parent()?.join("share").join("patchex");
        share.is_dir().then_some(share)
    });
    let built_from = || {
        let repository = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .ancestors()
            .nth(2)
            .expect("crates/patchex-cli is two deep");
        repository.is_dir().then(|| repository.to_path_buf())
    };
    let root = installed
        .or_else(built_from)
        .unwrap_or_else(|| std::path::PathBuf::from("."));
    root.join(relative)
}

/// Makes the folders above a file a command is about to write; an error names the path.
pub fn make_parent_folders(path: &std::path::Path) -> CommandResult {
    if let Some(folder) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(folder)
            .map_err(|error| format!("cannot write {}: {error}", path.display()))?;
    }
    Ok(())
}

/// Creates the file a command writes, and the folders above it; an error names the path.
pub fn create_output(path: &std::path::Path) -> Result<std::fs::File, Box<dyn std::error::Error>> {
    make_parent_folders(path)?;
    Ok(std::fs::File::create(path)
        .map_err(|error| format!("cannot write {}: {error}", path.display()))?)
}

/// Writes `contents` to `path` as [`create_output`] does.
pub fn write_output(path: &std::path::Path, contents: impl AsRef<[u8]>) -> CommandResult {
    use std::io::Write;
    create_output(path)?
        .write_all(contents.as_ref())
        .map_err(|error| format!("cannot write {}: {error}", path.display()).into())
}
