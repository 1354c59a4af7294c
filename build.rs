//! Compiles every compute pass under `shaders/` from WGSL to SPIR-V with naga, validates it, and
//! generates `shaders.rs` in OUT_DIR: per pass, the SPIR-V words, the workgroup size, the
//! descriptor bindings and a `#[repr(C)]` mirror of its push-constant block. The host reads all of
//! these from the generated module, so a binding number or a workgroup size is written once, in
//! the shader.
//!
//! A pass may pull shared helpers from `shaders/include/NAME.wgsl` with a line `// #import NAME`.
//! Errors are reported against the file and line they came from, not the assembled source.

use std::fmt::Write as _;
use std::fs;
use std::path::{Path, PathBuf};

use naga::back::spv;

#[path = "src/spirv_options.rs"]
mod spirv_options;

const SHADER_DIR: &str = "shaders";
const INCLUDE_DIR: &str = "shaders/include";
const IMPORT_DIRECTIVE: &str = "// #import ";

/// One file's lines inside an assembled shader source.
struct Segment {
    path: PathBuf,
    first_line: usize,
    line_count: usize,
}

struct AssembledSource {
    text: String,
    segments: Vec<Segment>,
}

impl AssembledSource {
    /// Maps a 1-based line of the assembled text back to (file, 1-based line).
    fn locate(&self, line: usize) -> (PathBuf, usize) {
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

fn assemble(pass_path: &Path) -> Result<AssembledSource, String> {
    let pass_text =
        fs::read_to_string(pass_path).map_err(|e| format!("{}: {e}", pass_path.display()))?;
    let mut text = String::new();
    let mut segments = Vec::new();
    let mut next_line = 1;
    for (index, line) in pass_text.lines().enumerate() {
        let Some(name) = line.trim().strip_prefix(IMPORT_DIRECTIVE) else {
            continue;
        };
        let include_path = Path::new(INCLUDE_DIR).join(format!("{}.wgsl", name.trim()));
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

fn located_error(source: &AssembledSource, line: Option<u32>, message: &str) -> String {
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

struct CompiledPass {
    name: String,
    words: Vec<u32>,
    workgroup_size: [u32; 3],
    bindings: Vec<BindingInfo>,
    push_constants: Option<String>,
}

/// One descriptor binding as the shader declares it.
struct BindingInfo {
    binding: u32,
    kind: &'static str,
    /// The shader may store through it (a storage image or buffer without `read` access).
    writes: bool,
    name: String,
}

fn compile(pass_path: &Path) -> Result<CompiledPass, String> {
    let source = assemble(pass_path)?;
    let module = naga::front::wgsl::parse_str(&source.text).map_err(|e| {
        let line = e.location(&source.text).map(|l| l.line_number);
        located_error(&source, line, &e.emit_to_string(&source.text))
    })?;
    let info = spirv_options::validator().validate(&module).map_err(|e| {
        let line = e.location(&source.text).map(|l| l.line_number);
        located_error(&source, line, &e.emit_to_string(&source.text))
    })?;
    let options = spirv_options::spirv_options();
    let words = spv::write_vec(&module, &info, &options, None)
        .map_err(|e| located_error(&source, None, &format!("SPIR-V output: {e}")))?;

    let [entry] = module.entry_points.as_slice() else {
        return Err(located_error(
            &source,
            None,
            "a pass has exactly one entry point",
        ));
    };
    if entry.stage != naga::ShaderStage::Compute || entry.name != "main" {
        return Err(located_error(
            &source,
            None,
            "the entry point must be `@compute fn main`",
        ));
    }

    let mut bindings = Vec::new();
    let mut push_constants = None;
    for (_, global) in module.global_variables.iter() {
        let name = global.name.clone().unwrap_or_default();
        if global.space == naga::AddressSpace::Immediate {
            push_constants = Some(push_constant_struct(&module, global.ty)?);
            continue;
        }
        let Some(binding) = &global.binding else {
            continue;
        };
        if binding.group != 0 {
            return Err(located_error(
                &source,
                None,
                "every binding lives in @group(0)",
            ));
        }
        // What the host orders passes by: whether the shader may store through the binding.
        let stores = |access: naga::StorageAccess| access.contains(naga::StorageAccess::STORE);
        let (kind, writes) = match (&global.space, &module.types[global.ty].inner) {
            (naga::AddressSpace::Uniform, _) => ("UniformBuffer", false),
            (naga::AddressSpace::Storage { access }, _) => ("StorageBuffer", stores(*access)),
            (
                _,
                naga::TypeInner::Image {
                    class: naga::ImageClass::Storage { access, .. },
                    ..
                },
            ) => ("StorageImage", stores(*access)),
            (_, naga::TypeInner::Image { .. }) => ("SampledImage", false),
            (_, naga::TypeInner::Sampler { .. }) => ("Sampler", false),
            (_, other) => return Err(format!("{name}: unsupported binding type {other:?}")),
        };
        bindings.push(BindingInfo {
            binding: binding.binding,
            kind,
            writes,
            name,
        });
    }
    bindings.sort_by_key(|b| b.binding);

    Ok(CompiledPass {
        name: pass_path
            .file_stem()
            .unwrap()
            .to_string_lossy()
            .into_owned(),
        words,
        workgroup_size: entry.workgroup_size,
        bindings,
        push_constants,
    })
}

/// Rust type of a push-constant member, with its size in bytes.
fn rust_type(module: &naga::Module, ty: naga::Handle<naga::Type>) -> Result<String, String> {
    use naga::{ScalarKind, TypeInner};
    let scalar = |s: naga::Scalar| match (s.kind, s.width) {
        (ScalarKind::Float, 4) => Ok("f32"),
        (ScalarKind::Uint, 4) => Ok("u32"),
        (ScalarKind::Sint, 4) => Ok("i32"),
        _ => Err(format!(
            "push constants support 32-bit scalars only, not {s:?}"
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
        other => Err(format!("unsupported push-constant member type {other:?}")),
    }
}

fn push_constant_struct(
    module: &naga::Module,
    ty: naga::Handle<naga::Type>,
) -> Result<String, String> {
    let naga::TypeInner::Struct { members, span } = &module.types[ty].inner else {
        return Err("the immediate (push constant) variable must be a struct".into());
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
        "    /// Push constants, laid out exactly as the shader declares them.\n    \
         #[repr(C)]\n    #[derive(Clone, Copy, Debug, Default, PartialEq)]\n    \
         pub struct Params {{\n{fields}    }}\n    \
         const _: () = assert!(std::mem::size_of::<Params>() == {span});\n    \
         impl super::PushConstants for Params {{}}\n"
    ))
}

fn emit(pass: &CompiledPass) -> String {
    let mut out = String::new();
    writeln!(out, "pub mod {} {{", pass.name).unwrap();
    writeln!(
        out,
        "    #[allow(unused_imports)]\n    use super::{{Binding, DescriptorKind}};"
    )
    .unwrap();
    writeln!(out, "    pub const NAME: &str = {:?};", pass.name).unwrap();
    writeln!(
        out,
        "    pub const WORKGROUP_SIZE: [u32; 3] = {:?};",
        pass.workgroup_size
    )
    .unwrap();
    writeln!(out, "    pub const BINDINGS: &[Binding] = &[").unwrap();
    for BindingInfo {
        binding,
        kind,
        writes,
        name,
    } in &pass.bindings
    {
        writeln!(
            out,
            "        Binding {{ binding: {binding}, kind: DescriptorKind::{kind}, writes: {writes}, \
             name: {name:?} }},"
        )
        .unwrap();
    }
    writeln!(out, "    ];").unwrap();
    writeln!(out, "    pub mod binding {{").unwrap();
    for BindingInfo { binding, name, .. } in &pass.bindings {
        writeln!(
            out,
            "        pub const {}: u32 = {binding};",
            name.to_uppercase()
        )
        .unwrap();
    }
    writeln!(out, "    }}").unwrap();
    let push_constant_size = match &pass.push_constants {
        Some(push_constants) => {
            out.push_str(push_constants);
            "std::mem::size_of::<Params>() as u32"
        }
        None => "0",
    };
    writeln!(
        out,
        "    pub const SHADER: super::ShaderInfo = super::ShaderInfo {{ name: NAME, spirv: SPIRV, \
         workgroup_size: WORKGROUP_SIZE, bindings: BINDINGS, push_constant_size: {push_constant_size} }};"
    )
    .unwrap();
    write!(out, "    pub const SPIRV: &[u32] = &[").unwrap();
    for (index, word) in pass.words.iter().enumerate() {
        if index % 8 == 0 {
            out.push_str("\n        ");
        }
        write!(out, "{word:#010x}, ").unwrap();
    }
    writeln!(out, "\n    ];\n}}").unwrap();
    out
}

/// PATCHEX_ABI_VERSION as src/abi.rs declares it.
fn abi_version() -> u32 {
    const DECLARATION: &str = "pub const PATCHEX_ABI_VERSION: u32 = ";
    println!("cargo:rerun-if-changed=src/abi.rs");
    let abi = fs::read_to_string("src/abi.rs").expect("src/abi.rs reads");
    abi.lines()
        .find_map(|line| {
            line.strip_prefix(DECLARATION)?
                .strip_suffix(';')?
                .parse()
                .ok()
        })
        .expect("src/abi.rs declares PATCHEX_ABI_VERSION")
}

fn main() {
    // The shared library names itself by its ABI version, as shared libraries do: what links it
    // records "libpatchex.so.N" and will not load a library of another ABI.
    println!(
        "cargo:rustc-cdylib-link-arg=-Wl,-soname,libpatchex.so.{}",
        abi_version()
    );
    println!("cargo:rerun-if-changed={SHADER_DIR}");
    println!("cargo:rerun-if-changed={INCLUDE_DIR}");
    let mut passes: Vec<PathBuf> = fs::read_dir(SHADER_DIR)
        .expect("shaders/ exists")
        .map(|entry| entry.expect("readable shaders/ entry").path())
        .filter(|path| path.extension().is_some_and(|ext| ext == "wgsl"))
        .collect();
    passes.sort();

    let mut generated =
        String::from("// Generated by build.rs from shaders/*.wgsl. Do not edit.\n");
    let mut failures = Vec::new();
    for path in &passes {
        println!("cargo:rerun-if-changed={}", path.display());
        match compile(path) {
            Ok(pass) => generated.push_str(&emit(&pass)),
            Err(error) => failures.push(error),
        }
    }
    if !failures.is_empty() {
        for failure in &failures {
            eprintln!("error: {failure}");
        }
        panic!(
            "{} shader(s) failed to compile:\n{}",
            failures.len(),
            failures.join("\n")
        );
    }
    let out_dir = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    fs::write(out_dir.join("shaders.rs"), generated).expect("OUT_DIR is writable");
}
