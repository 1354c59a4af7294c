//! Compiles every compute pass under `shaders/` from WGSL to SPIR-V with naga, validates it, and
//! generates `shaders.rs` in OUT_DIR: per pass, the SPIR-V words, the workgroup size, the
//! descriptor bindings and a `#[repr(C)]` mirror of its push-constant block. The host reads all of
//! these from the generated module, so a binding number or a workgroup size is written once, in
//! the shader.
//!
//! A pass may pull shared helpers from `shaders/include/NAME.wgsl` with a line `// #import NAME`
//! (`build_support/wgsl.rs`). Errors are reported against the file and line they came from, not
//! the assembled source.

use std::fmt::Write as _;
use std::fs;
use std::path::{Path, PathBuf};

use naga::back::spv;

#[path = "src/spirv_options.rs"]
mod spirv_options;
#[path = "build_support/wgsl.rs"]
mod wgsl;

use wgsl::{assemble, located_error};

const SHADER_DIR: &str = "shaders";
const INCLUDE_DIR: &str = "shaders/include";
/// What every pass's push constants derive.
const PARAMS_DERIVES: &str = "Clone, Copy, Debug, Default, PartialEq";
struct CompiledPass {
    name: String,
    words: Vec<u32>,
    workgroup_size: [u32; 3],
    bindings: Vec<BindingInfo>,
    push_constants: Option<String>,
    /// Mirrors of the structs its uniform buffers hold, which the host fills.
    uniforms: Vec<String>,
    arithmetic: u64,
}

/// One descriptor binding as the shader declares it.
struct BindingInfo {
    binding: u32,
    kind: &'static str,
    /// The shader may store through it (a storage image or buffer without `read` access).
    writes: bool,
    /// The shader may load through it (everything but a write-only storage image).
    reads: bool,
    name: String,
}

fn compile(pass_path: &Path) -> Result<CompiledPass, String> {
    let source = assemble(pass_path, Path::new(INCLUDE_DIR))?;
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
    let mut uniforms = Vec::new();
    for (_, global) in module.global_variables.iter() {
        let name = global.name.clone().unwrap_or_default();
        if global.space == naga::AddressSpace::Immediate {
            let params = wgsl::mirror_struct(&module, global.ty, "Params", PARAMS_DERIVES)?;
            push_constants = Some(format!(
                "    /// Push constants, laid out exactly as the shader declares them.\n{params}    \
                 impl super::PushConstants for Params {{}}\n"
            ));
            continue;
        }
        let Some(binding) = &global.binding else {
            continue;
        };
        if global.space == naga::AddressSpace::Uniform {
            let name = module.types[global.ty].name.clone().unwrap_or_default();
            let mirrored = wgsl::mirror_struct(&module, global.ty, &name, PARAMS_DERIVES)?;
            uniforms.push(format!(
                "    /// A uniform buffer's contents, laid out exactly as the shader declares \
                 them.\n{mirrored}    impl super::PushConstants for {name} {{}}\n"
            ));
        }
        if binding.group != 0 {
            return Err(located_error(
                &source,
                None,
                "every binding lives in @group(0)",
            ));
        }
        // What the host orders passes by: whether the shader may store through the binding.
        let stores = |access: naga::StorageAccess| access.contains(naga::StorageAccess::STORE);
        let loads = |access: naga::StorageAccess| access.contains(naga::StorageAccess::LOAD);
        let (kind, writes, reads) = match (&global.space, &module.types[global.ty].inner) {
            (naga::AddressSpace::Uniform, _) => ("UniformBuffer", false, true),
            (naga::AddressSpace::Storage { access }, _) => {
                ("StorageBuffer", stores(*access), loads(*access))
            }
            (
                _,
                naga::TypeInner::Image {
                    class: naga::ImageClass::Storage { access, .. },
                    ..
                },
            ) => ("StorageImage", stores(*access), loads(*access)),
            (_, naga::TypeInner::Image { .. }) => ("SampledImage", false, true),
            (_, naga::TypeInner::Sampler { .. }) => ("Sampler", false, false),
            (_, other) => return Err(format!("{name}: unsupported binding type {other:?}")),
        };
        bindings.push(BindingInfo {
            binding: binding.binding,
            kind,
            writes,
            reads,
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
        uniforms,
        arithmetic: arithmetic(&module, &info, &entry.function, info.get_entry_point(0)),
    })
}

/// Arithmetic operations one invocation of `function` performs as written: each arithmetic
/// expression once per vector lane, a called function's once per call. Every branch and loop
/// body counts once, so this is a static count, not a measurement: the roofline's compute side
/// (`patchex bench`).
fn arithmetic(
    module: &naga::Module,
    info: &naga::valid::ModuleInfo,
    function: &naga::Function,
    function_info: &naga::valid::FunctionInfo,
) -> u64 {
    use naga::Expression as E;
    let mut operations = 0;
    for (handle, expression) in function.expressions.iter() {
        let lanes = match function_info[handle].ty.inner_with(&module.types) {
            naga::TypeInner::Vector { size, .. } => *size as u64,
            _ => 1,
        };
        operations += match expression {
            E::Binary { .. } | E::Unary { .. } | E::Math { .. } | E::Select { .. } => lanes,
            E::Relational { .. } | E::As { .. } => lanes,
            E::CallResult(callee) => {
                arithmetic(module, info, &module.functions[*callee], &info[*callee])
            }
            _ => 0,
        };
    }
    operations
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
        reads,
        name,
    } in &pass.bindings
    {
        writeln!(
            out,
            "        Binding {{ binding: {binding}, kind: DescriptorKind::{kind}, writes: {writes}, \
             reads: {reads}, name: {name:?} }},"
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
    for uniform in &pass.uniforms {
        out.push_str(uniform);
    }
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
         workgroup_size: WORKGROUP_SIZE, bindings: BINDINGS, push_constant_size: {push_constant_size}, \
         arithmetic: {} }};",
        pass.arithmetic
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
