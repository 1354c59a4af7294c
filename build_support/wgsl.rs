//! WGSL for build scripts, shared by the plugin's (`build.rs`) and the scene renderer's
//! (`crates/patchex-scene/build.rs`), each of which includes this file with `#[path]`:
//! - `assemble`: a shader with the helpers it imports (`// #import NAME` pulls in
//!   `INCLUDE_DIR/NAME.wgsl`), and errors mapped back to the file and line they came from;
//! - `mirror_struct`: a `#[repr(C)]` Rust mirror of a WGSL struct, its padding spelled out, so a
//!   layout shared by a shader and the host is written once, in the shader.

use std::fmt::Write as _;
use std::fs;
use std::path::{Path, PathBuf};

const IMPORT_DIRECTIVE: &str = "// #import ";

/// One file's lines inside an assembled shader source.
struct Segment {
    path: PathBuf,
    first_line: usize,
    line_count: usize,
}

pub struct AssembledSource {
    pub text: String,
    segments: Vec<Segment>,
}

impl AssembledSource {
    /// Maps a 1-based line of the assembled text back to (file, 1-based line).
    pub fn locate(&self, line: usize) -> (PathBuf, usize) {
        for segment in &self.segments {
            if line >= segment.first_line && line < segment.first_line + segment.line_count {
                return (segment.path.clone(), line - segment.first_line + 1);
            }
        }
        let last = self
            .segments
            .last()
            .expect("a pass has at least its own segment");
        (last.path.clone(), line.saturating_sub(last.first_line) + 1)
    }
}

pub fn assemble(pass_path: &Path, include_dir: &Path) -> Result<AssembledSource, String> {
    let pass_text =
        fs::read_to_string(pass_path).map_err(|e| format!("{}: {e}", pass_path.display()))?;
    let mut text = String::new();
    let mut segments = Vec::new();
    let mut next_line = 1;
    for (index, line) in pass_text.lines().enumerate() {
        let Some(name) = line.trim().strip_prefix(IMPORT_DIRECTIVE) else {
            continue;
        };
        let include_path = include_dir.join(format!("{}.wgsl", name.trim()));
        let include = fs::read_to_string(&include_path).map_err(|e| {
            format!(
                "{}:{}: cannot import {}: {e}",
                pass_path.display(),
                index + 1,
                include_path.display()
            )
        })?;
        println!("cargo:rerun-if-changed={}", include_path.display());
        let line_count = include.lines().count();
        segments.push(Segment {
            path: include_path,
            first_line: next_line,
            line_count,
        });
        next_line += line_count;
        for include_line in include.lines() {
            text.push_str(include_line);
            text.push('\n');
        }
    }
    segments.push(Segment {
        path: pass_path.to_path_buf(),
        first_line: next_line,
        line_count: pass_text.lines().count(),
    });
    text.push_str(&pass_text);
    Ok(AssembledSource { text, segments })
}

pub fn located_error(source: &AssembledSource, line: Option<u32>, message: &str) -> String {
    match line {
        Some(line) => {
            let (path, line) = source.locate(line as usize);
            format!("{}:{line}: {message}", path.display())
        }
        None => format!(
            "{}: {message}",
            source.segments.last().unwrap().path.display()
        ),
    }
}

/// Rust type of a struct member.
fn rust_type(module: &naga::Module, ty: naga::Handle<naga::Type>) -> Result<String, String> {
    use naga::{ScalarKind, TypeInner};
    let scalar = |s: naga::Scalar| match (s.kind, s.width) {
        (ScalarKind::Float, 4) => Ok("f32"),
        (ScalarKind::Uint, 4) => Ok("u32"),
        (ScalarKind::Sint, 4) => Ok("i32"),
        _ => Err(format!(
            "mirrored structs hold 32-bit scalars only, not {s:?}"
        )),
    };
    match &module.types[ty].inner {
        TypeInner::Scalar(s) => Ok(scalar(*s)?.to_string()),
        TypeInner::Vector { size, scalar: s } => Ok(format!("[{}; {}]", scalar(*s)?, *size as u8)),
        TypeInner::Matrix {
            columns,
            rows,
            scalar: s,
        } => Ok(format!(
            "[[{}; {}]; {}]",
            scalar(*s)?,
            *rows as u8,
            *columns as u8
        )),
        other => Err(format!(
            "unsupported member type in a mirrored struct: {other:?}"
        )),
    }
}

/// A `#[repr(C)]` struct `name` deriving `derives`, laid out exactly as WGSL struct `ty` (its
/// padding spelled out as fields), with its size asserted.
pub fn mirror_struct(
    module: &naga::Module,
    ty: naga::Handle<naga::Type>,
    name: &str,
    derives: &str,
) -> Result<String, String> {
    let naga::TypeInner::Struct { members, span } = &module.types[ty].inner else {
        return Err(format!(
            "{name} mirrors a struct, not {:?}",
            module.types[ty].inner
        ));
    };
    let mut layouter = naga::proc::Layouter::default();
    layouter
        .update(module.to_ctx())
        .map_err(|e| e.to_string())?;
    let mut fields = String::new();
    let mut cursor = 0;
    for (index, member) in members.iter().enumerate() {
        if member.offset > cursor {
            writeln!(
                fields,
                "        pub _pad{index}: [u8; {}],",
                member.offset - cursor
            )
            .unwrap();
        }
        let name = member
            .name
            .clone()
            .unwrap_or_else(|| format!("field{index}"));
        writeln!(
            fields,
            "        pub {name}: {},",
            rust_type(module, member.ty)?
        )
        .unwrap();
        cursor = member.offset + layouter[member.ty].size;
    }
    if *span > cursor {
        writeln!(fields, "        pub _pad_end: [u8; {}],", span - cursor).unwrap();
    }
    Ok(format!(
        "    #[repr(C)]\n    #[derive({derives})]\n    \
         pub struct {name} {{\n{fields}    }}\n    \
         const _: () = assert!(std::mem::size_of::<{name}>() == {span});\n"
    ))
}
