//! Reading a network from safetensors: the widths in the metadata give the topology, and every
//! tensor the topology needs must be present, F32, of the right shape and finite.

use safetensors::{Dtype, SafeTensors};

use super::{Layer, LayerKind, Tensor, INPUT_CHANNELS, OUTPUT_CHANNELS};
use crate::error::{bail, Error, PatchexResult, Result};

/// More levels than this would need patches padded to multiples of 64 and more.
pub const MAX_LEVELS: usize = 6;
/// Wider layers would make shaders too large to compile in reasonable time.
pub const MAX_WIDTH: usize = 128;

/// A 3x3 convolution's weights, `weight[((o * inputs + i) * 3 + ky) * 3 + kx]` as PyTorch
/// stores them, and one bias per output.
#[derive(Clone, Debug, PartialEq)]
pub struct ConvWeights {
    pub inputs: usize,
    pub outputs: usize,
    pub weight: Vec<f32>,
    pub bias: Vec<f32>,
}

impl ConvWeights {
    pub fn at(&self, output: usize, input: usize, ky: usize, kx: usize) -> f32 {
        self.weight[((output * self.inputs + input) * 3 + ky) * 3 + kx]
    }
}

/// A whole network: its widths and its layers in execution order (encoder, bottleneck,
/// decoder, output).
#[derive(Clone, Debug)]
pub struct Network {
    pub widths: Vec<usize>,
    pub layers: Vec<Layer>,
}

impl Network {
    /// Patches must be a multiple of this in both directions (one halving per level below 0).
    /// Arithmetic operations of one run over a patch of `extent` texels: each layer's 3x3
    /// convolutions at its level's resolution, a multiply-add counting two as peak figures
    /// count them (activations and the input gather not counted). An empty patch costs none.
    pub fn operations(&self, extent: [u32; 2]) -> u64 {
        if extent.contains(&0) {
            return 0;
        }
        self.layers
            .iter()
            .map(|layer| {
                let texels = (extent[0] >> layer.level).max(1) as u64
                    * (extent[1] >> layer.level).max(1) as u64;
                let convolutions = match layer.kind {
                    LayerKind::Gated { .. } => 2,
                    LayerKind::Output { .. } => 1,
                };
                let weights = 9 * (layer.input_channels() * layer.output_channels()) as u64;
                texels * convolutions * 2 * weights
            })
            .sum()
    }

    pub fn multiple(&self) -> u32 {
        1 << (self.widths.len() - 1)
    }

    /// Parses a safetensors file; `origin` names it in error messages.
    pub fn from_safetensors(bytes: &[u8], origin: &str) -> Result<Self> {
        let not_safetensors = |e: safetensors::SafeTensorError| {
            Error::new(
                PatchexResult::ErrorInvalidArgument,
                format!("{origin} is not a safetensors file: {e}"),
            )
        };
        let (_, metadata) = SafeTensors::read_metadata(bytes).map_err(not_safetensors)?;
        let tensors = SafeTensors::deserialize(bytes).map_err(not_safetensors)?;
        let Some(widths) = metadata.metadata().as_ref().and_then(|m| m.get("widths")) else {
            bail!(
                ErrorInvalidArgument,
                "{origin} has no \"widths\" metadata naming the network's level widths"
            );
        };
        let widths = parse_widths(widths, origin)?;
        let conv = |name: &str, inputs: usize, outputs: usize| -> Result<ConvWeights> {
            Ok(ConvWeights {
                inputs,
                outputs,
                weight: read_tensor(
                    &tensors,
                    origin,
                    &format!("{name}.weight"),
                    &[outputs, inputs, 3, 3],
                )?,
                bias: read_tensor(&tensors, origin, &format!("{name}.bias"), &[outputs])?,
            })
        };
        let gated = |name: &str, inputs: usize, outputs: usize| -> Result<LayerKind> {
            Ok(LayerKind::Gated {
                feature: conv(&format!("{name}.feature"), inputs, outputs)?,
                gate: conv(&format!("{name}.gate"), inputs, outputs)?,
            })
        };

        let levels = widths.len();
        let mut layers = Vec::new();
        for (level, &width) in widths.iter().enumerate() {
            let (main, inputs) = match level {
                0 => (Tensor::Input, INPUT_CHANNELS),
                _ => (Tensor::Layer(level - 1), widths[level - 1]),
            };
            let name = format!("enc{level}");
            layers.push(Layer {
                kind: gated(&name, inputs, width)?,
                name,
                main,
                upsample: false,
                skip: None,
                stride: if level == 0 { 1 } else { 2 },
                dilation: 1,
                level: level as u32,
            });
        }
        let deepest = widths[levels - 1];
        layers.push(Layer {
            name: "bottle".into(),
            kind: gated("bottle", deepest, deepest)?,
            main: Tensor::Layer(levels - 1),
            upsample: false,
            skip: None,
            stride: 1,
            dilation: 2,
            level: (levels - 1) as u32,
        });
        for level in (0..levels - 1).rev() {
            let name = format!("dec{level}");
            layers.push(Layer {
                kind: gated(&name, widths[level + 1] + widths[level], widths[level])?,
                name,
                main: Tensor::Layer(layers.len() - 1),
                upsample: true,
                skip: Some(Tensor::Layer(level)),
                stride: 1,
                dilation: 1,
                level: level as u32,
            });
        }
        layers.push(Layer {
            name: "out".into(),
            kind: LayerKind::Output {
                conv: conv("out", widths[0], OUTPUT_CHANNELS)?,
            },
            main: Tensor::Layer(layers.len() - 1),
            upsample: false,
            skip: None,
            stride: 1,
            dilation: 1,
            level: 0,
        });
        // Weight and bias of the feature and gate convolutions, and of the output convolution.
        let expected = 4 * (layers.len() - 1) + 2;
        if tensors.len() != expected {
            bail!(
                ErrorInvalidArgument,
                "{origin} holds {} tensors; widths {widths:?} need exactly {expected}",
                tensors.len()
            );
        }
        Ok(Self { widths, layers })
    }
}

fn parse_widths(text: &str, origin: &str) -> Result<Vec<usize>> {
    let inner = text
        .trim()
        .strip_prefix('[')
        .and_then(|t| t.strip_suffix(']'));
    let widths: Option<Vec<usize>> =
        inner.and_then(|inner| inner.split(',').map(|w| w.trim().parse().ok()).collect());
    match widths {
        Some(widths)
            if (1..=MAX_LEVELS).contains(&widths.len())
                && widths.iter().all(|&w| w > 0 && w % 4 == 0 && w <= MAX_WIDTH) =>
        {
            Ok(widths)
        }
        _ => bail!(
            ErrorInvalidArgument,
            "{origin}: widths {text:?} must be a list of 1 to {MAX_LEVELS} multiples of 4, each at most {MAX_WIDTH}"
        ),
    }
}

fn read_tensor(
    tensors: &SafeTensors,
    origin: &str,
    name: &str,
    shape: &[usize],
) -> Result<Vec<f32>> {
    let Ok(view) = tensors.tensor(name) else {
        bail!(ErrorInvalidArgument, "{origin} lacks the tensor {name}");
    };
    if view.dtype() != Dtype::F32 || view.shape() != shape {
        bail!(
            ErrorInvalidArgument,
            "{origin}: tensor {name} is {:?} {:?}; the topology needs F32 {shape:?}",
            view.dtype(),
            view.shape()
        );
    }
    let values: Vec<f32> = view
        .data()
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    if let Some(index) = values.iter().position(|v| !v.is_finite()) {
        bail!(
            ErrorInvalidArgument,
            "{origin}: tensor {name} holds {} at element {index}",
            values[index]
        );
    }
    Ok(values)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::network::SHIPPED_FI;

    #[test]
    fn operations_follow_the_patch_and_the_layers() {
        let network = Network::from_safetensors(SHIPPED_FI, "built-in FI network").unwrap();
        let side = 4 * network.multiple();
        let small = network.operations([side, side]);
        // Every level divides a multiple of the network's: texels, so operations, scale by 4.
        assert_eq!(network.operations([2 * side, 2 * side]), 4 * small);
        assert_eq!(network.operations([0, side]), 0);
        // At full resolution a layer costs two operations per weight per texel (a gated one
        // two convolutions); the first layer alone, over a patch's texels, is a lower bound.
        let first = &network.layers[0];
        let per_texel = 2 * 9 * (first.input_channels() * first.output_channels()) as u64;
        assert!(small > per_texel * (side * side) as u64, "{small}");
    }
}
