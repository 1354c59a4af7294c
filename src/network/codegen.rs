//! One compute shader per network layer, generated from its weights and compiled with naga when
//! the networks are loaded. The weights are constants in the code and every loop is unrolled:
//! on a CPU driver this runs about 10x faster than reading weights from a buffer in a loop
//! (`shared/LAVAPIPE.md`), and a GPU driver folds them into its instruction stream as well.
//!
//! Every tensor lives in an RGBA16F (or, with `TensorPrecision::F32`, RGBA32F) image array, four
//! channels a layer, the patch at its origin; layer `level` covers `patch.extent >> level` texels. Each invocation computes every
//! output channel of one texel, so each input texel is fetched once per tap.

use std::fmt::Write;

use naga::back::spv;

use super::weights::MAX_LEVELS;
use super::{ConvWeights, Layer, LayerKind, TensorPrecision};
use crate::error::{bail, Result};
use crate::shaders::{Binding, DescriptorKind, ShaderInfo};

/// Workgroup edge of every layer's shader.
pub const GROUP_EDGE: u32 = 8;

/// The bindings of every layer's shader; the ones a layer does not read are bound all the same,
/// so that one descriptor layout serves them all.
pub const BINDINGS: [Binding; 5] = [
    Binding {
        binding: 0,
        kind: DescriptorKind::SampledImage,
        writes: false,
        reads: true,
        name: "main_input",
    },
    Binding {
        binding: 1,
        kind: DescriptorKind::SampledImage,
        writes: false,
        reads: true,
        name: "skip_input",
    },
    Binding {
        binding: 2,
        kind: DescriptorKind::SampledImage,
        writes: false,
        reads: true,
        name: "network_input",
    },
    Binding {
        binding: 3,
        kind: DescriptorKind::StorageImage,
        writes: true,
        reads: false,
        name: "layer_output",
    },
    Binding {
        binding: 4,
        kind: DescriptorKind::StorageBuffer,
        writes: false,
        reads: true,
        name: "network_patch",
    },
];

/// The `Patch` record the layers read: origin, padded extent and resolution divisor of the
/// patch, then the indirect dispatch of each level.
pub const PATCH_WGSL: &str = include_str!("../../shaders/include/patch.wgsl");
/// Where the extent (two u32), the divisor (a u32) and the dispatches start in the record.
pub const PATCH_EXTENT_OFFSET: u64 = 8;
pub const PATCH_DIVISOR_OFFSET: u64 = 16;
pub const PATCH_DISPATCH_OFFSET: u64 = 32;
pub const PATCH_BYTES: u64 = PATCH_DISPATCH_OFFSET + 16 * MAX_LEVELS as u64;

/// The reflection of a generated layer shader (its code is made at run time).
pub fn shader_info(layer: &Layer) -> ShaderInfo {
    ShaderInfo {
        name: match &layer.kind {
            LayerKind::Gated { .. } => "network gated layer",
            LayerKind::Output { .. } => "network output layer",
        },
        spirv: &[],
        workgroup_size: [GROUP_EDGE, GROUP_EDGE, 1],
        bindings: &BINDINGS,
        push_constant_size: 0,
        arithmetic: 0,
    }
}

/// WGSL source of `layer`.
pub fn wgsl(layer: &Layer, precision: TensorPrecision) -> String {
    let mut s = String::new();
    let level = layer.level;
    s.push_str(PATCH_WGSL);
    s.push_str(
        &"@group(0) @binding(0) var main_input: texture_2d_array<f32>;
@group(0) @binding(1) var skip_input: texture_2d_array<f32>;
@group(0) @binding(2) var network_input: texture_2d_array<f32>;
@group(0) @binding(3) var layer_output: texture_storage_2d_array<OUTPUT_FORMAT, write>;
@group(0) @binding(4) var<storage, read> network_patch: Patch;

// Every output is held to the half-float range, so that FP16 storage never makes an infinity.
const MAX_HALF: f32 = 65504.0;

fn elu(x: vec4f) -> vec4f {
    return select(exp(x) - 1.0, x, x > vec4f(0.0));
}

fn sigmoid(x: vec4f) -> vec4f {
    return 1.0 / (1.0 + exp(-x));
}

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
"
        .replace("OUTPUT_FORMAT", precision.wgsl_format()),
    );
    // The main input's extent in this layer's coordinates: a stride-2 layer reads the level
    // above at twice its own size, an upsampling one reads the level below doubled.
    let main_level = if layer.stride == 2 { level - 1 } else { level };
    writeln!(
        s,
        "    let extent = network_patch.extent >> vec2u({level}u);"
    )
    .unwrap();
    writeln!(
        s,
        "    let main_extent = vec2i(network_patch.extent >> vec2u({main_level}u));"
    )
    .unwrap();
    s.push_str(
        "    if (any(id.xy >= extent)) {\n        return;\n    }\n    let p = vec2i(id.xy);\n",
    );

    let (convs, outputs): (Vec<&ConvWeights>, usize) = match &layer.kind {
        LayerKind::Gated { feature, gate } => (vec![feature, gate], feature.outputs),
        LayerKind::Output { conv } => (vec![conv], conv.outputs),
    };
    let output_groups = outputs.div_ceil(4);
    // A skip tensor comes from this layer's own level, as wide as its output.
    let skip_channels = layer.skip.map_or(0, |_| outputs);
    let main_groups = (convs[0].inputs - skip_channels).div_ceil(4);
    let skip_groups = skip_channels / 4;
    for (c, conv) in convs.iter().enumerate() {
        for o in 0..output_groups {
            let bias: Vec<f32> = (0..4).map(|k| bias_at(conv, 4 * o + k)).collect();
            writeln!(s, "    var acc{c}_{o} = vec4f({});", list(&bias)).unwrap();
        }
    }
    for ky in 0..3 {
        for kx in 0..3 {
            let d = layer.dilation as i32;
            let (dx, dy) = ((kx as i32 - 1) * d, (ky as i32 - 1) * d);
            writeln!(s, "    {{").unwrap();
            writeln!(
                s,
                "        let q = p * {}i + vec2i({dx}, {dy});",
                layer.stride
            )
            .unwrap();
            writeln!(
                s,
                "        let inside = all(q >= vec2i(0)) && all(q < main_extent);"
            )
            .unwrap();
            writeln!(
                s,
                "        let c = vec2u(clamp(q, vec2i(0), main_extent - 1));"
            )
            .unwrap();
            // An upsampled main input is read at half the coordinates.
            let m = if layer.upsample { "c / 2u" } else { "c" };
            let mut inputs = Vec::new();
            for g in 0..main_groups {
                writeln!(
                    s,
                    "        let x{g} = select(vec4f(0.0), textureLoad(main_input, {m}, {g}, 0), inside);"
                )
                .unwrap();
                inputs.push(g);
            }
            for g in 0..skip_groups {
                // The skip tensor is at this layer's own level, as large as `main_extent`.
                let index = main_groups + g;
                writeln!(
                    s,
                    "        let x{index} = select(vec4f(0.0), textureLoad(skip_input, c, {g}, 0), inside);"
                )
                .unwrap();
                inputs.push(index);
            }
            for (c, conv) in convs.iter().enumerate() {
                for o in 0..output_groups {
                    let terms: Vec<String> = inputs
                        .iter()
                        .map(|&g| format!("{} * x{g}", matrix(conv, o, g, ky, kx)))
                        .collect();
                    writeln!(s, "        acc{c}_{o} += {};", terms.join(" + ")).unwrap();
                }
            }
            writeln!(s, "    }}").unwrap();
        }
    }
    for o in 0..output_groups {
        let value = match &layer.kind {
            LayerKind::Gated { .. } => format!("sigmoid(acc1_{o}) * elu(acc0_{o})"),
            LayerKind::Output { .. } => {
                "vec4f(textureLoad(network_input, id.xy, 0, 0).rgb + acc0_0.rgb, 1.0)".into()
            }
        };
        writeln!(
            s,
            "    textureStore(layer_output, id.xy, {o}, clamp({value}, vec4f(-MAX_HALF), vec4f(MAX_HALF)));"
        )
        .unwrap();
    }
    s.push_str("}\n");
    s
}

fn bias_at(conv: &ConvWeights, output: usize) -> f32 {
    conv.bias.get(output).copied().unwrap_or(0.0)
}

/// The 4x4 block from input group `g` to output group `o` at one tap, column-major as WGSL
/// builds it (column j holds input channel 4g+j's weights to the four outputs).
fn matrix(conv: &ConvWeights, o: usize, g: usize, ky: usize, kx: usize) -> String {
    let mut values = Vec::with_capacity(16);
    for j in 0..4 {
        for k in 0..4 {
            let (output, input) = (4 * o + k, 4 * g + j);
            values.push(if output < conv.outputs && input < conv.inputs {
                conv.at(output, input, ky, kx)
            } else {
                0.0
            });
        }
    }
    format!("mat4x4f({})", list(&values))
}

fn list(values: &[f32]) -> String {
    let items: Vec<String> = values.iter().map(|v| format!("{v:?}")).collect();
    items.join(", ")
}

/// Compiles generated WGSL to validated SPIR-V with the options of the hand-written passes.
pub fn compile(source: &str, what: &str) -> Result<Vec<u32>> {
    let module = match naga::front::wgsl::parse_str(source) {
        Ok(module) => module,
        Err(e) => bail!(ErrorInternal, "{what}: generated WGSL does not parse: {e}"),
    };
    let info = match crate::spirv_options::validator().validate(&module) {
        Ok(info) => info,
        Err(e) => bail!(ErrorInternal, "{what}: generated WGSL is invalid: {e:?}"),
    };
    match spv::write_vec(&module, &info, &crate::spirv_options::spirv_options(), None) {
        Ok(words) => Ok(words),
        Err(e) => bail!(ErrorInternal, "{what}: SPIR-V generation failed: {e}"),
    }
}
