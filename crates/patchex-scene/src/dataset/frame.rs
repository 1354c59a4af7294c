//! One frame's layers in memory: what the renderer produces and what the reader returns.

use super::layers::{LayerSpec, LAYERS};

/// One layer, pixels row-major from the top-left, channels interleaved.
#[derive(Clone, Debug, PartialEq)]
pub struct LayerImage {
    pub name: String,
    /// Channel suffixes in order, e.g. ["R", "G", "B"].
    pub channels: Vec<String>,
    pub width: usize,
    pub height: usize,
    pub data: Vec<f32>,
}

impl LayerImage {
    pub fn channel_count(&self) -> usize {
        self.channels.len()
    }

    pub fn pixel(&self, x: usize, y: usize) -> &[f32] {
        let n = self.channel_count();
        let start = (y * self.width + x) * n;
        &self.data[start..start + n]
    }

    pub fn value(&self, x: usize, y: usize, channel: usize) -> f32 {
        self.data[(y * self.width + x) * self.channel_count() + channel]
    }

    /// One channel as a plane.
    pub fn plane(&self, channel: usize) -> Vec<f32> {
        self.data
            .iter()
            .skip(channel)
            .step_by(self.channel_count())
            .copied()
            .collect()
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct FrameLayers {
    pub width: usize,
    pub height: usize,
    pub layers: Vec<LayerImage>,
}

impl FrameLayers {
    pub fn get(&self, name: &str) -> Option<&LayerImage> {
        self.layers.iter().find(|layer| layer.name == name)
    }

    /// Like [`FrameLayers::get`] for layers the caller knows are present.
    pub fn layer(&self, name: &str) -> &LayerImage {
        self.get(name)
            .unwrap_or_else(|| panic!("frame has no layer {name:?}"))
    }

    pub fn get_mut(&mut self, name: &str) -> Option<&mut LayerImage> {
        self.layers.iter_mut().find(|layer| layer.name == name)
    }

    pub fn names(&self) -> Vec<String> {
        self.layers.iter().map(|layer| layer.name.clone()).collect()
    }

    /// Builds the layers from the resolve pass's planar output.
    pub(crate) fn from_planes(planes: &[f32], width: usize, height: usize, lit: bool) -> Self {
        let plane_size = width * height;
        let layers = LAYERS
            .iter()
            .filter(|spec| lit || !spec.lit)
            .map(|spec: &LayerSpec| {
                let n = spec.channels.len();
                let mut data = vec![0f32; plane_size * n];
                for c in 0..n {
                    let plane = &planes[(spec.first_plane + c) * plane_size..][..plane_size];
                    for (pixel, &value) in plane.iter().enumerate() {
                        data[pixel * n + c] = value;
                    }
                }
                LayerImage {
                    name: spec.name.to_owned(),
                    channels: spec.channels.iter().map(|c| (*c).to_owned()).collect(),
                    width,
                    height,
                    data,
                }
            })
            .collect();
        Self {
            width,
            height,
            layers,
        }
    }
}
