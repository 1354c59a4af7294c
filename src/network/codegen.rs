//! One compute shader per step of the two networks run side by side, generated from their
//! weights and compiled with naga when the networks are loaded: each runs the layer of that step
//! of each network that has one, over its own patch, in one dispatch. The weights are constants
//! in the code and every loop is unrolled: on a CPU driver this runs about 10x faster than
//! reading weights from a buffer in a loop (`shared/LAVAPIPE.md`), and a GPU driver folds them
//! into its instruction stream as well.
//!
//! Every tensor lives in an RGBA16F (or, with `TensorPrecision::F32`, RGBA32F) image array, four
//! channels a layer, the patch at its origin; layer `level` covers `patch.extent >> level`
//! texels. Each invocation computes every output channel of one texel, so each input texel is
//! fetched once per tap. The first layer reads the frame instead: its workgroup gathers the
//! input planes of its tile and the tile's border into workgroup memory
//! (`shaders/include/network_gather.wgsl`), convolves them from there, and stores its own texels
//! for the output layer and the blend, so no pass of its own runs before the networks.

use std::fmt::Write;

use naga::back::spv;

use super::weights::MAX_LEVELS;
use super::{ConvWeights, Layer, LayerKind, Tensor, TensorPrecision, INPUT_CHANNELS};
use crate::error::{bail, Result};
use crate::shaders::{Binding, DescriptorKind, ShaderInfo};

/// Workgroup edge of every step's shader.
pub const GROUP_EDGE: u32 = 8;

/// The bindings of one network's layer in a step's shader: the first network's at 0 to 4, the
/// second's at 5 to 9 (`NETWORK_BINDINGS` past the first's).
pub const NETWORK_BINDINGS: u32 = 5;
const BINDINGS: [Binding; 2 * NETWORK_BINDINGS as usize] = [
    network_binding(0, DescriptorKind::SampledImage, "main_input"),
    network_binding(1, DescriptorKind::SampledImage, "skip_input"),
    network_binding(2, DescriptorKind::SampledImage, "network_input"),
    network_binding(3, DescriptorKind::StorageImage, "layer_output"),
    network_binding(4, DescriptorKind::StorageBuffer, "network_patch"),
    network_binding(5, DescriptorKind::SampledImage, "main_input"),
    network_binding(6, DescriptorKind::SampledImage, "skip_input"),
    network_binding(7, DescriptorKind::SampledImage, "network_input"),
    network_binding(8, DescriptorKind::StorageImage, "layer_output"),
    network_binding(9, DescriptorKind::StorageBuffer, "network_patch"),
];
/// The first layers' bindings: each network's input tensor, which they write, its output and
/// its `Patch` record; between the two networks', the frame they gather from.
const GATHER_BINDINGS: [Binding; 8] = [
    Binding {
        reads: false,
        ..network_binding(2, DescriptorKind::StorageImage, "network_input")
    },
    network_binding(3, DescriptorKind::StorageImage, "layer_output"),
    network_binding(4, DescriptorKind::StorageBuffer, "network_patch"),
    Binding {
        writes: false,
        ..network_binding(binding::WARPED, DescriptorKind::StorageImage, "warped")
    },
    network_binding(binding::MATERIAL, DescriptorKind::SampledImage, "material"),
    Binding {
        reads: false,
        ..network_binding(7, DescriptorKind::StorageImage, "network_input")
    },
    network_binding(8, DescriptorKind::StorageImage, "layer_output"),
    network_binding(9, DescriptorKind::StorageBuffer, "network_patch"),
];

/// Binding `binding`: the layer's output is written, everything else read.
const fn network_binding(binding: u32, kind: DescriptorKind, name: &'static str) -> Binding {
    let writes = matches!(kind, DescriptorKind::StorageImage);
    Binding {
        binding,
        kind,
        writes,
        reads: !writes,
        name,
    }
}

/// Within a network's bindings: the layer's main input, its skip input (the main input again
/// for a layer without one, which does not read it), the network's gathered input (which the
/// first layer writes), the layer's output and the network's `Patch` record. Past both
/// networks', the frame the first layer gathers from (`network_gather.wgsl`).
pub mod binding {
    pub const MAIN: u32 = 0;
    pub const SKIP: u32 = 1;
    pub const NETWORK_INPUT: u32 = 2;
    pub const OUTPUT: u32 = 3;
    pub const PATCH: u32 = 4;
    pub const WARPED: u32 = 10;
    pub const MATERIAL: u32 = 11;
}

/// `GatherParams` in `shaders/include/network_gather.wgsl`, the first layer's push constants.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct GatherParams {
    pub frame_extent: [u32; 2],
    pub has_material: u32,
    pub _pad_end: u32,
}

impl crate::shaders::PushConstants for GatherParams {}

/// The layer gathers the network's input from the frame: the first.
pub fn gathers(layer: &Layer) -> bool {
    layer.main == Tensor::Input
}

/// The `Patch` record the layers read: origin, padded extent and resolution divisor of the
/// patch, then the indirect dispatch of each level.
pub const PATCH_WGSL: &str = include_str!("../../shaders/include/patch.wgsl");
/// What every step's code uses of the hand-written shaders' helpers, and what the first
/// layer's gather does.
const GBUFFER_WGSL: &str = include_str!("../../shaders/include/gbuffer.wgsl");
const GATHER_WGSL: [&str; 2] = [
    include_str!("../../shaders/include/lbp.wgsl"),
    include_str!("../../shaders/include/network_gather.wgsl"),
];
/// Where the extent (two u32), the divisor (a u32) and the dispatches start in the record.
pub const PATCH_EXTENT_OFFSET: u64 = 8;
pub const PATCH_DIVISOR_OFFSET: u64 = 16;
pub const PATCH_DISPATCH_OFFSET: u64 = 32;
pub const PATCH_BYTES: u64 = PATCH_DISPATCH_OFFSET + 16 * MAX_LEVELS as u64;

/// The layers of one step, of the first and the second network; `None` for a network that has
/// no layer at this step.
pub type StepLayers<'a> = [Option<&'a Layer>; 2];

/// The reflection of a step's generated shader (its code is made at run time): the bindings of
/// the networks that have a layer at this step.
pub fn shader_info(layers: StepLayers) -> ShaderInfo {
    let n = NETWORK_BINDINGS as usize;
    let gather = step_gathers(layers);
    let bindings: &'static [Binding] = match (layers, gather) {
        ([Some(_), Some(_)], false) => &BINDINGS,
        ([Some(_), None], false) => &BINDINGS[..n],
        ([None, Some(_)], false) => &BINDINGS[n..],
        ([Some(_), Some(_)], true) => &GATHER_BINDINGS,
        ([Some(_), None], true) => &GATHER_BINDINGS[..5],
        ([None, Some(_)], true) => &GATHER_BINDINGS[3..],
        ([None, None], _) => &[],
    };
    ShaderInfo {
        name: "network step",
        spirv: &[],
        workgroup_size: [GROUP_EDGE, GROUP_EDGE, 1],
        bindings,
        push_constant_size: if gather {
            size_of::<GatherParams>() as u32
        } else {
            0
        },
        arithmetic: 0,
    }
}

/// The step's layers gather their input from the frame: the networks' first layers, which
/// come together at the first step (`Network::from_safetensors` starts every network so).
pub fn step_gathers(layers: StepLayers) -> bool {
    let gather = layers.iter().flatten().any(|layer| gathers(layer));
    debug_assert!(layers
        .iter()
        .flatten()
        .all(|layer| gathers(layer) == gather));
    gather
}

/// WGSL source of a step running `layers` side by side: one function per network's layer, and
/// a `main` that gives each workgroup to the network whose rows it falls in (`step_group` in
/// shaders/include/patch.wgsl).
pub fn wgsl(layers: StepLayers, precision: TensorPrecision) -> String {
    let mut s = String::new();
    s.push_str(PATCH_WGSL);
    // Every output is held to the half-float range (its `MAX_HALF`), so that FP16 storage never
    // makes an infinity.
    s.push_str(GBUFFER_WGSL);
    if step_gathers(layers) {
        GATHER_WGSL.iter().for_each(|text| s.push_str(text));
    }
    s.push_str(
        "
fn elu(x: vec4f) -> vec4f {
    return select(exp(x) - 1.0, x, x > vec4f(0.0));
}

fn sigmoid(x: vec4f) -> vec4f {
    return 1.0 / (1.0 + exp(-x));
}
",
    );
    for (network, layer) in layers.iter().enumerate() {
        if let Some(layer) = layer {
            layer_function(&mut s, layer, network, precision);
        }
    }
    writeln!(
        s,
        "@compute @workgroup_size({GROUP_EDGE}, {GROUP_EDGE}, 1)
fn main(@builtin(workgroup_id) group: vec3u, @builtin(local_invocation_id) local: vec3u) {{"
    )
    .unwrap();
    // A layer takes its workgroup's tile (its first texel) and the invocation's place in it.
    let texel = |group: &str| format!("{group} * {GROUP_EDGE}u, local.xy");
    match layers {
        [Some(first), Some(_)] => writeln!(
            s,
            "    // Read before the branch, where every invocation reads the same.
    let first_extent = network_patch_0.extent;
    let second_extent = network_patch_1.extent;
    let step = step_group(group.xy, network_patch_0.dispatch[{}]);
    if (step.second) {{
        layer_1({texel}, second_extent);
    }} else {{
        layer_0({texel}, first_extent);
    }}",
            first.level,
            texel = texel("step.group"),
        ),
        [Some(_), None] => writeln!(
            s,
            "    layer_0({}, network_patch_0.extent);",
            texel("group.xy")
        ),
        [None, Some(_)] => writeln!(
            s,
            "    layer_1({}, network_patch_1.extent);",
            texel("group.xy")
        ),
        [None, None] => Ok(()),
    }
    .unwrap();
    s.push_str("}\n");
    s
}

/// Declares network `network`'s bindings and writes `layer_{network}(tile, local, patch_extent)`,
/// which computes every output channel of texel `tile + local` of `layer` over a patch of
/// `patch_extent`.
fn layer_function(s: &mut String, layer: &Layer, network: usize, precision: TensorPrecision) {
    let base = network as u32 * NETWORK_BINDINGS;
    let n = network;
    let gather = gathers(layer);
    if gather {
        // The planes of the tile and its border, written once, read by all of the taps.
        writeln!(
            s,
            "@group(0) @binding({}) var network_input_{n}: texture_storage_2d_array<rgba16float, write>;
var<workgroup> gathered_{n}: array<vec4f, {}>;",
            base + binding::NETWORK_INPUT,
            INPUT_CHANNELS.div_ceil(4) * gathered_side(layer).pow(2) as usize,
        )
        .unwrap();
    } else {
        writeln!(
            s,
            "@group(0) @binding({}) var main_input_{n}: texture_2d_array<f32>;
@group(0) @binding({}) var skip_input_{n}: texture_2d_array<f32>;
@group(0) @binding({}) var network_input_{n}: texture_2d_array<f32>;",
            base + binding::MAIN,
            base + binding::SKIP,
            base + binding::NETWORK_INPUT,
        )
        .unwrap();
    }
    writeln!(
        s,
        "@group(0) @binding({}) var layer_output_{n}: texture_storage_2d_array<{}, write>;
@group(0) @binding({}) var<storage, read> network_patch_{n}: Patch;

fn layer_{n}(tile: vec2u, local: vec2u, patch_extent: vec2u) {{",
        base + binding::OUTPUT,
        precision.wgsl_format(),
        base + binding::PATCH,
    )
    .unwrap();
    let level = layer.level;
    // The main input's extent in this layer's coordinates: a stride-2 layer reads the level
    // above at twice its own size, an upsampling one reads the level below doubled.
    let main_level = if layer.stride == 2 { level - 1 } else { level };
    writeln!(s, "    let extent = patch_extent >> vec2u({level}u);").unwrap();
    writeln!(
        s,
        "    let main_extent = vec2i(patch_extent >> vec2u({main_level}u));"
    )
    .unwrap();
    if gather {
        gather_tile(s, layer, n);
    }
    s.push_str(
        "    let texel = tile + local;
    if (any(texel >= extent)) {
        return;
    }
",
    );
    if !gather {
        // The texel the taps are read around; a gathering layer reads its tile instead.
        s.push_str("    let p = vec2i(texel);\n");
    }
    if gather {
        // The output layer adds its result to the input colour, and the blend reads it back.
        let border = layer.dilation;
        let side = gathered_side(layer);
        writeln!(
            s,
            "    let own = (local.y + {border}u) * {side}u + local.x + {border}u;"
        )
        .unwrap();
        for g in 0..INPUT_CHANNELS.div_ceil(4) {
            writeln!(
                s,
                "    textureStore(network_input_{n}, texel, {g}, gathered_{n}[{}u + own]);",
                g as u32 * side * side
            )
            .unwrap();
        }
    }

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
            if gather {
                // The tap's texel in the gathered tile, zero outside the patch already.
                let side = gathered_side(layer);
                let at = |offset: i32, axis: &str| format!("(i32(local.{axis}) + {})", offset + d);
                writeln!(
                    s,
                    "        let t = u32({} * {side} + {});",
                    at(dy, "y"),
                    at(dx, "x")
                )
                .unwrap();
            } else {
                writeln!(
                    s,
                    "        let q = p * {}i + vec2i({dx}, {dy});
        let inside = all(q >= vec2i(0)) && all(q < main_extent);
        let c = vec2u(clamp(q, vec2i(0), main_extent - 1));",
                    layer.stride
                )
                .unwrap();
            }
            // An upsampled main input is read at half the coordinates.
            let m = if layer.upsample { "c / 2u" } else { "c" };
            let mut inputs = Vec::new();
            for g in 0..main_groups {
                if gather {
                    let plane = g as u32 * gathered_side(layer).pow(2);
                    writeln!(s, "        let x{g} = gathered_{n}[{plane}u + t];").unwrap();
                    inputs.push(g);
                    continue;
                }
                writeln!(
                    s,
                    "        let x{g} = select(vec4f(0.0), textureLoad(main_input_{n}, {m}, {g}, 0), inside);"
                )
                .unwrap();
                inputs.push(g);
            }
            for g in 0..skip_groups {
                // The skip tensor is at this layer's own level, as large as `main_extent`.
                let index = main_groups + g;
                writeln!(
                    s,
                    "        let x{index} = select(vec4f(0.0), textureLoad(skip_input_{n}, c, {g}, 0), inside);"
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
                format!("vec4f(textureLoad(network_input_{n}, texel, 0, 0).rgb + acc0_0.rgb, 1.0)")
            }
        };
        writeln!(
            s,
            "    textureStore(layer_output_{n}, texel, {o}, clamp({value}, vec4f(-MAX_HALF), vec4f(MAX_HALF)));"
        )
        .unwrap();
    }
    s.push_str("}\n\n");
}

/// Texels on a side of the tile a first layer gathers: the workgroup's, and the taps' reach
/// around it.
fn gathered_side(layer: &Layer) -> u32 {
    GROUP_EDGE + 2 * layer.dilation
}

/// Writes the first layer's gather of its tile and border into `gathered_{n}`, every plane at
/// every texel, zero outside the patch as the convolution pads. Every invocation takes part, so
/// the function returns before none of them has.
fn gather_tile(s: &mut String, layer: &Layer, n: usize) {
    debug_assert!(layer.stride == 1 && !layer.upsample && layer.skip.is_none());
    let side = gathered_side(layer);
    let texels = side * side;
    let lanes = GROUP_EDGE * GROUP_EDGE;
    writeln!(
        s,
        "    for (var i = local.y * {GROUP_EDGE}u + local.x; i < {texels}u; i += {lanes}u) {{
        let q = vec2i(tile) - {border} + vec2i(vec2u(i % {side}u, i / {side}u));
        var g = Gathered(vec4f(0.0), vec4f(0.0));
        if (all(q >= vec2i(0)) && all(q < main_extent)) {{
            g = gather(vec2u(q), network_patch_{n}.origin, network_patch_{n}.divisor);
        }}
        gathered_{n}[i] = g.colour_hole;
        gathered_{n}[{texels}u + i] = g.surface;
    }}
    workgroupBarrier();",
        border = layer.dilation,
    )
    .unwrap();
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
