//! The committed C header must be exactly what cbindgen generates from the sources.
//! Regenerate it with `PATCHEX_BLESS_HEADER=1 cargo test --test header`.

use std::path::Path;

#[test]
fn committed_header_matches_cbindgen_output() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let config =
        cbindgen::Config::from_file(root.join("cbindgen.toml")).expect("cbindgen.toml parses");
    let mut generated = Vec::new();
    cbindgen::Builder::new()
        .with_src(root.join("src/abi.rs"))
        .with_src(root.join("src/error.rs"))
        .with_src(root.join("src/ffi.rs"))
        .with_config(config)
        .generate()
        .expect("cbindgen generates the header")
        .write(&mut generated);
    let generated = String::from_utf8(generated).expect("header is UTF-8");
    let path = root.join("include/patchex.h");
    if std::env::var_os("PATCHEX_BLESS_HEADER").is_some() {
        std::fs::write(&path, &generated).expect("include/ is writable");
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        committed == generated,
        "include/patchex.h is stale: run `PATCHEX_BLESS_HEADER=1 cargo test --test header` and commit it"
    );
}
