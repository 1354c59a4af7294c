//! The inpainting networks of PatchEX: small U-Nets of gated convolutions, one for the FI patch
//! and a smaller one for the near-BE patch (`training/patchex_net.py` defines and trains them).
//!
//! A network is read from a safetensors file whose metadata names its level widths; the
//! topology follows from them, so the file, the plain-Rust reference (`reference::network`) and
//! the generated shaders (`codegen`) can never disagree about it.

pub mod codegen;
pub mod weights;

pub use weights::{ConvWeights, Network};

use std::path::Path;

use crate::error::{bail, Result};

/// The weights built into the library: `training/train.py`'s output for the command, data and
/// seed in `assets/networks/manifest.json`, the networks measured in the README.
pub const SHIPPED_FI: &[u8] = include_bytes!("../../assets/networks/fi.safetensors");
pub const SHIPPED_NEAR_BE: &[u8] = include_bytes!("../../assets/networks/near_be.safetensors");

/// The network in the file at `path`, or the built-in `shipped` weights without one.
pub fn load(path: Option<&Path>, shipped: &[u8], name: &str) -> Result<Network> {
    match path {
        None => Network::from_safetensors(shipped, &format!("built-in {name} network")),
        Some(path) => match std::fs::read(path) {
            Ok(bytes) => Network::from_safetensors(&bytes, &path.display().to_string()),
            Err(error) => bail!(
                ErrorInvalidArgument,
                "cannot read the {name} network's weights {}: {error}",
                path.display()
            ),
        },
    }
}

/// How the layers store their outputs (`PatchexNetworkPrecision`); the arithmetic is f32 either
/// way, and the gathered input is always RGBA16F.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TensorPrecision {
    /// RGBA16F: half the memory and bandwidth of f32.
    #[default]
    F16,
    F32,
}

impl TensorPrecision {
    pub fn format(self) -> ash::vk::Format {
        match self {
            Self::F16 => ash::vk::Format::R16G16B16A16_SFLOAT,
            Self::F32 => ash::vk::Format::R32G32B32A32_SFLOAT,
        }
    }

    /// The storage texel format in WGSL.
    pub fn wgsl_format(self) -> &'static str {
        match self {
            Self::F16 => "rgba16float",
            Self::F32 => "rgba32float",
        }
    }
}

/// Planes the network reads, in order (`training/patchex_net.py`, `INPUT_NAMES`): warped
/// demodulated colour (3), hole mask, roughness, metallic, LBP code / 255, and one zero plane
/// that rounds the input up to two RGBA images.
pub const INPUT_CHANNELS: usize = 8;
/// Planes it writes: the repaired demodulated colour.
pub const OUTPUT_CHANNELS: usize = 3;

/// Which tensor a layer reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tensor {
    Input,
    /// The output of layer `n`.
    Layer(usize),
}

/// One layer of the U-Net: a 3x3 convolution over `main` (upsampled 2x by nearest neighbour
/// first when `upsample`), followed in channels by `skip` when present.
#[derive(Clone, Debug)]
pub struct Layer {
    pub name: String,
    pub main: Tensor,
    pub upsample: bool,
    pub skip: Option<Tensor>,
    pub stride: u32,
    pub dilation: u32,
    /// 0 is the patch's resolution; each level halves it.
    pub level: u32,
    pub kind: LayerKind,
}

#[derive(Clone, Debug)]
pub enum LayerKind {
    /// `sigmoid(gate(x)) * elu(feature(x))`.
    Gated {
        feature: ConvWeights,
        gate: ConvWeights,
    },
    /// The last layer: a plain convolution whose result is added to the input colour.
    Output { conv: ConvWeights },
}

impl Layer {
    pub fn output_channels(&self) -> usize {
        match &self.kind {
            LayerKind::Gated { feature, .. } => feature.outputs,
            LayerKind::Output { conv } => conv.outputs,
        }
    }

    pub fn input_channels(&self) -> usize {
        match &self.kind {
            LayerKind::Gated { feature, .. } => feature.inputs,
            LayerKind::Output { conv } => conv.inputs,
        }
    }
}
