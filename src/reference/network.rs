//! Plain-Rust forward pass of an inpainting network, the oracle for the generated shaders.
//! Tensors are planar (`[channel][y][x]`). As on the GPU, each layer's output is held to the
//! half-float range and, when `f16_storage` is set (RGBA16F tensors), rounded to f16.

use super::gbuffer::MAX_HALF;
use crate::network::{Layer, LayerKind, Network, Tensor, INPUT_CHANNELS};

/// A planar tensor.
#[derive(Clone, Debug, PartialEq)]
pub struct Planes {
    pub channels: usize,
    pub width: usize,
    pub height: usize,
    pub values: Vec<f32>,
}

impl Planes {
    pub fn zeros(channels: usize, width: usize, height: usize) -> Self {
        Self {
            channels,
            width,
            height,
            values: vec![0.0; channels * width * height],
        }
    }

    pub fn at(&self, c: usize, x: usize, y: usize) -> f32 {
        self.values[(c * self.height + y) * self.width + x]
    }

    fn at_or_zero(&self, c: usize, x: i64, y: i64) -> f32 {
        if x < 0 || y < 0 || x >= self.width as i64 || y >= self.height as i64 {
            0.0
        } else {
            self.at(c, x as usize, y as usize)
        }
    }
}

fn elu(x: f32) -> f32 {
    if x > 0.0 {
        x
    } else {
        x.exp() - 1.0
    }
}

fn sigmoid(x: f32) -> f32 {
    1.0 / (1.0 + (-x).exp())
}

/// Runs `network` on `input` (INPUT_CHANNELS planes whose size is a multiple of
/// `network.multiple()`); returns the output colour planes.
pub fn forward(network: &Network, input: &Planes, f16_storage: bool) -> Planes {
    assert_eq!(input.channels, INPUT_CHANNELS);
    assert!(input.width % network.multiple() as usize == 0);
    assert!(input.height % network.multiple() as usize == 0);
    let mut outputs: Vec<Planes> = Vec::with_capacity(network.layers.len());
    for layer in &network.layers {
        let tensor = |t: Tensor| match t {
            Tensor::Input => input,
            Tensor::Layer(n) => &outputs[n],
        };
        let mut out = run_layer(layer, tensor(layer.main), layer.skip.map(tensor), input);
        for v in &mut out.values {
            *v = v.clamp(-MAX_HALF, MAX_HALF);
            if f16_storage {
                *v = half::f16::from_f32(*v).to_f32();
            }
        }
        outputs.push(out);
    }
    outputs.pop().expect("a network has layers")
}

fn run_layer(layer: &Layer, main: &Planes, skip: Option<&Planes>, input: &Planes) -> Planes {
    let scale = 1usize << layer.level;
    let (width, height) = (input.width / scale, input.height / scale);
    let main_channels = main.channels;
    // Input channel c at (x, y) of this layer's input, zero outside it (PyTorch's padding).
    let fetch = |c: usize, x: i64, y: i64| -> f32 {
        if c < main_channels {
            if layer.upsample {
                if x < 0 || y < 0 || x >= 2 * main.width as i64 || y >= 2 * main.height as i64 {
                    return 0.0;
                }
                main.at(c, (x / 2) as usize, (y / 2) as usize)
            } else {
                main.at_or_zero(c, x, y)
            }
        } else {
            skip.expect("channels past main come from the skip tensor")
                .at_or_zero(c - main_channels, x, y)
        }
    };
    let convolve = |conv: &crate::network::ConvWeights, o: usize, x: usize, y: usize| -> f32 {
        let mut sum = conv.bias[o];
        for ky in 0..3 {
            for kx in 0..3 {
                let sx =
                    (x * layer.stride as usize) as i64 + (kx as i64 - 1) * layer.dilation as i64;
                let sy =
                    (y * layer.stride as usize) as i64 + (ky as i64 - 1) * layer.dilation as i64;
                for i in 0..conv.inputs {
                    sum += conv.at(o, i, ky, kx) * fetch(i, sx, sy);
                }
            }
        }
        sum
    };
    let mut out = Planes::zeros(layer.output_channels(), width, height);
    for o in 0..out.channels {
        for y in 0..height {
            for x in 0..width {
                out.values[(o * height + y) * width + x] = match &layer.kind {
                    LayerKind::Gated { feature, gate } => {
                        sigmoid(convolve(gate, o, x, y)) * elu(convolve(feature, o, x, y))
                    }
                    LayerKind::Output { conv } => input.at(o, x, y) + convolve(conv, o, x, y),
                };
            }
        }
    }
    out
}
