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

/// The name `PATCHEX_STRUCT_TYPE_SHADOW_FLOW_SETTINGS` gives its struct: `PatchexShadowFlowSettings`.
fn struct_of_type_constant(constant: &str) -> String {
    let words = constant
        .trim_start_matches("PATCHEX_STRUCT_TYPE_")
        .split('_');
    let camel: String = words
        .map(|word| word[..1].to_string() + &word[1..].to_lowercase())
        .collect();
    format!("Patchex{camel}")
}

/// cbindgen emits only the types an exported function names. Every struct a `struct_type`
/// constant tags (the chained extensions above all) and every `#[repr(C)]` struct of the ABI
/// must reach C callers all the same.
#[test]
fn header_declares_every_struct_of_the_abi() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let abi = std::fs::read_to_string(root.join("src/abi.rs")).expect("src/abi.rs reads");
    let header = std::fs::read_to_string(root.join("include/patchex.h")).expect("header reads");
    let tagged = abi.lines().filter_map(|line| {
        let constant = line.strip_prefix("pub const PATCHEX_STRUCT_TYPE_")?;
        let name = constant.split(':').next()?;
        Some(struct_of_type_constant(&format!(
            "PATCHEX_STRUCT_TYPE_{name}"
        )))
    });
    let lines: Vec<&str> = abi.lines().collect();
    let repr_c = lines.windows(3).filter_map(|window| {
        if !window[0].starts_with("#[repr(C)]") {
            return None;
        }
        let declaration = window[1..].iter().find(|l| l.starts_with("pub struct "))?;
        let name = declaration
            .strip_prefix("pub struct ")?
            .split([' ', '{'])
            .next()?;
        Some(name.to_string())
    });
    let structs: Vec<String> = tagged.chain(repr_c).collect();
    assert!(
        structs.len() > 20,
        "the scan finds the ABI's structs: {structs:?}"
    );
    let missing: Vec<&String> = structs
        .iter()
        .filter(|name| !header.contains(&format!("typedef struct {name} {{")))
        .collect();
    assert!(
        missing.is_empty(),
        "include/patchex.h lacks {missing:?}: add them to cbindgen.toml's [export] include"
    );
}

/// The header's FORMATS table lists exactly the formats each role accepts.
#[test]
fn header_format_table_matches_what_each_role_accepts() {
    use patchex::vk::image::*;
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let header = std::fs::read_to_string(root.join("include/patchex.h")).expect("header reads");
    for (role, formats) in [
        ("colour", FLOAT_COLOR_FORMATS),
        ("depth", DEPTH_FORMATS),
        ("stencil", STENCIL_FORMATS),
        ("motion vectors", MOTION_FORMATS),
        ("shadow mask", MASK_FORMATS),
        ("output", OUTPUT_FORMATS),
        ("diagnostics", DIAGNOSTICS_FORMATS),
    ] {
        let prefix = format!(" *   {role}: ");
        let line = header
            .lines()
            .find_map(|line| line.strip_prefix(&prefix))
            .unwrap_or_else(|| panic!("the header's FORMATS table has a `{role}` line"));
        let listed: Vec<&str> = line.split_whitespace().collect();
        let accepted: Vec<String> = formats.iter().map(|f| format!("{f:?}")).collect();
        assert_eq!(listed, accepted, "the header's `{role}` formats");
    }
}

/// Every result code is documented, and every function that returns one lists the codes it can
/// return, each of them a code that exists.
#[test]
fn header_documents_every_result_code_and_what_each_function_returns() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let header = std::fs::read_to_string(root.join("include/patchex.h")).expect("header reads");
    let lines: Vec<&str> = header.lines().collect();
    let codes: Vec<&str> = lines
        .iter()
        .filter_map(|line| line.trim().strip_prefix("PATCHEX_RESULT_"))
        .filter_map(|rest| rest.split(' ').next())
        .collect();
    assert!(
        codes.len() >= 21,
        "the scan finds the result codes: {codes:?}"
    );
    for (i, line) in lines.iter().enumerate() {
        if line.trim().starts_with("PATCHEX_RESULT_") {
            assert!(
                lines[i - 1].trim().starts_with("//"),
                "{} has no comment",
                line.trim()
            );
        }
    }
    for (i, line) in lines.iter().enumerate() {
        let Some(name) = line.strip_prefix("PatchexResult patchex_") else {
            continue;
        };
        let name = name.split('(').next().unwrap_or(name);
        let comment: Vec<&str> = lines[..i]
            .iter()
            .rev()
            .take_while(|l| l.starts_with("//"))
            .copied()
            .collect();
        let comment = comment.into_iter().rev().collect::<Vec<_>>().join(" ");
        // The last "Returns" paragraph is the list.
        let returns = comment
            .rsplit("Returns ")
            .next()
            .filter(|_| comment.contains("Returns "))
            .unwrap_or_else(|| panic!("patchex_{name} does not say what it returns"));
        let named: Vec<&str> = returns
            .split(|c: char| !(c.is_ascii_uppercase() || c == '_'))
            .filter(|word| {
                word.len() > 3 && word.chars().all(|c| c.is_ascii_uppercase() || c == '_')
            })
            .map(|word| word.trim_start_matches("PATCHEX_RESULT_"))
            .collect();
        assert!(
            named.len() >= 3,
            "patchex_{name} names its codes: {named:?}"
        );
        for code in named {
            assert!(
                codes.contains(&code),
                "patchex_{name} names {code}, which does not exist"
            );
        }
    }
}
