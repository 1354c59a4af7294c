//! Everything drawn after lighting, gathered as one premultiplied layer (the forward pass's
//! blended surfaces, then the particles over them) and composited over the lit frame. The layer
//! is what an engine hands a frame generator beside the colour: its coverage is the mask, and
//! its motion is the coverage-weighted motion of what it holds.

use glam::Vec3;

use crate::dataset::{
    FrameLayers, LayerImage, FINAL_IMAGE, FINAL_IMAGE_NO_DYNAMIC_SHADOWS, SPECULAR_LIGHT,
    TRANSLUCENCY_MASK, TRANSLUCENCY_MOTION,
};

pub(crate) struct TranslucentLayer {
    width: usize,
    height: usize,
    /// Radiance times coverage, "over"-composited.
    color: Vec<Vec3>,
    coverage: Vec<f32>,
    /// Backward motion in pixels times coverage, composited the same way.
    motion: Vec<[f32; 2]>,
}

impl TranslucentLayer {
    pub fn new(width: usize, height: usize) -> Self {
        let pixels = width * height;
        Self {
            width,
            height,
            color: vec![Vec3::ZERO; pixels],
            coverage: vec![0.0; pixels],
            motion: vec![[0.0; 2]; pixels],
        }
    }

    /// The forward pass's two RGBA f32 targets, one after the other: (colour, coverage) and
    /// (motion, 0, coverage), both premultiplied.
    pub fn from_forward_targets(texels: &[f32], width: usize, height: usize) -> Self {
        let pixels = width * height;
        let (color, motion) = texels.split_at(4 * pixels);
        Self {
            width,
            height,
            color: color
                .chunks_exact(4)
                .map(|c| Vec3::new(c[0], c[1], c[2]))
                .collect(),
            coverage: color.chunks_exact(4).map(|c| c[3]).collect(),
            motion: motion.chunks_exact(4).map(|m| [m[0], m[1]]).collect(),
        }
    }

    pub fn width(&self) -> usize {
        self.width
    }

    pub fn height(&self) -> usize {
        self.height
    }

    /// Draws `color` at `coverage` over what the layer holds at `pixel`.
    pub fn draw_over(&mut self, pixel: usize, color: Vec3, coverage: f32, motion: [f32; 2]) {
        let behind = 1.0 - coverage;
        self.color[pixel] = coverage * color + behind * self.color[pixel];
        self.coverage[pixel] = coverage + behind * self.coverage[pixel];
        let m = &mut self.motion[pixel];
        *m = [
            coverage * motion[0] + behind * m[0],
            coverage * motion[1] + behind * m[1],
        ];
    }

    /// Composites the layer over the frame's lit colours, hides the view-dependent light behind
    /// it as much as the rest, and adds the mask and motion layers.
    pub fn composite(self, layers: &mut FrameLayers) {
        for layer in layers
            .layers
            .iter_mut()
            .filter(|l| l.name == FINAL_IMAGE || l.name == FINAL_IMAGE_NO_DYNAMIC_SHADOWS)
        {
            for (pixel, c) in layer.data.chunks_mut(3).enumerate() {
                let behind = 1.0 - self.coverage[pixel];
                for (channel, own) in c.iter_mut().zip(self.color[pixel].to_array()) {
                    *channel = own + behind * *channel;
                }
            }
        }
        if let Some(specular) = layers.get_mut(SPECULAR_LIGHT) {
            for (pixel, c) in specular.data.chunks_mut(3).enumerate() {
                c.iter_mut().for_each(|v| *v *= 1.0 - self.coverage[pixel]);
            }
        }
        let motion = self
            .motion
            .iter()
            .zip(&self.coverage)
            .flat_map(|(m, &a)| {
                if a > 0.0 {
                    [m[0] / a, m[1] / a]
                } else {
                    [0.0; 2]
                }
            })
            .collect();
        let (width, height) = (self.width, self.height);
        let layer = |name: &str, channels: &[&str], data| LayerImage {
            name: name.to_owned(),
            channels: channels.iter().map(|c| (*c).to_owned()).collect(),
            width,
            height,
            data,
        };
        let mask = layer(TRANSLUCENCY_MASK, &["R"], self.coverage);
        let motion = layer(TRANSLUCENCY_MOTION, &["R", "G"], motion);
        layers.layers.extend([mask, motion]);
    }
}
