pub mod bench;
pub mod calibrate;
pub mod costs;
pub mod demo;
pub mod eval;
pub mod inspect;
pub mod interpolate;
pub mod metrics;
pub mod patches;
pub mod picture;
pub mod plugin_driver;
pub mod render;
pub mod scenes;
pub mod sheet;

/// Errors of any subcommand, shown to the user as one line.
pub type CommandResult = Result<(), Box<dyn std::error::Error>>;

/// A file of this repository (a default scene or weights), whatever the working directory.
pub fn repository_path(relative: &str) -> std::path::PathBuf {
    let crate_dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let repository = crate_dir
        .ancestors()
        .nth(2)
        .expect("crates/patchex-cli is two deep");
    repository.join(relative)
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
