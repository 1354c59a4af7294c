//! Compiles every WGSL file under `shaders/` to SPIR-V with naga, so no shader compiler ships.
//! A parse or validation error fails the build with the file, line and column.

use std::path::{Path, PathBuf};

const SHADERS: &[&str] = &["gbuffer.wgsl", "shadow.wgsl", "resolve.wgsl"];

fn main() {
    let manifest_dir =
        PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"));
    let out_dir = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    for name in SHADERS {
        let source_path = manifest_dir.join("shaders").join(name);
        println!("cargo:rerun-if-changed={}", source_path.display());
        match compile(&source_path) {
            Ok(words) => {
                let bytes: Vec<u8> = words.iter().flat_map(|word| word.to_le_bytes()).collect();
                let spv_path = out_dir.join(name).with_extension("spv");
                std::fs::write(&spv_path, bytes).expect("writing SPIR-V into OUT_DIR");
            }
            Err(message) => {
                eprintln!("{message}");
                std::process::exit(1);
            }
        }
    }
}

fn compile(path: &Path) -> Result<Vec<u32>, String> {
    let shown = path.display().to_string();
    let source = std::fs::read_to_string(path).map_err(|e| format!("{shown}: {e}"))?;
    let module = naga::front::wgsl::parse_str(&source)
        .map_err(|e| e.emit_to_string_with_path(&source, &shown))?;
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::IMMEDIATES,
    )
    .validate(&module)
    .map_err(|e| e.emit_to_string_with_path(&source, &shown))?;
    // The renderer builds Vulkan-convention projections itself (y down, depth 0..1), so naga
    // must not flip clip-space y the way it does for wgpu.
    let options = naga::back::spv::Options {
        flags: naga::back::spv::WriterFlags::LABEL_VARYINGS,
        ..Default::default()
    };
    naga::back::spv::write_vec(&module, &info, &options, None).map_err(|e| format!("{shown}: {e}"))
}
