//! Everything drawn after lighting, gathered as one premultiplied layer (the forward pass's
//! blended surfaces, then the particles, seen through the surfaces they lie beyond) and
//! composited over the lit frame. The layer
//! is what an engine hands a frame generator beside the colour: its coverage is the mask, and
//! its motion is the coverage-weighted motion of what it holds.

use std::ops::{Add, Mul, Sub};

use glam::{Vec2, Vec3};

use crate::dataset::{
    FrameLayers, LayerImage, FINAL_IMAGE, FINAL_IMAGE_NO_DYNAMIC_SHADOWS, FINAL_IMAGE_OPAQUE,
    FINAL_IMAGE_OPAQUE_NO_DYNAMIC_SHADOWS, SPECULAR_LIGHT, TRANSLUCENCY_MASK, TRANSLUCENCY_MOTION,
};

/// One texel of a premultiplied layer: radiance and backward motion in pixels, each times
/// coverage, and coverage. Layers composite by sums and scales of these.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Texel {
    pub color: Vec3,
    pub motion: Vec2,
    pub coverage: f32,
}

impl Texel {
    /// `color` moving by `motion`, drawn at `coverage`.
    pub fn new(color: Vec3, motion: [f32; 2], coverage: f32) -> Self {
        Self {
            color: coverage * color,
            motion: coverage * Vec2::from(motion),
            coverage,
        }
    }

    /// `self` "over" `below`.
    fn over(self, below: Self) -> Self {
        self + below * (1.0 - self.coverage)
    }
}

impl Add for Texel {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self {
            color: self.color + o.color,
            motion: self.motion + o.motion,
            coverage: self.coverage + o.coverage,
        }
    }
}

impl Sub for Texel {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        self + o * -1.0
    }
}

impl Mul<f32> for Texel {
    type Output = Self;
    fn mul(self, k: f32) -> Self {
        Self {
            color: k * self.color,
            motion: k * self.motion,
            coverage: k * self.coverage,
        }
    }
}

pub(crate) struct TranslucentLayer {
    width: usize,
    height: usize,
    /// Everything drawn so far.
    texels: Vec<Texel>,
    /// The forward pass's blended surfaces alone, and their linear depth (coverage-weighted over
    /// the surfaces a pixel holds; infinite where it holds none): a particle beyond them is seen
    /// through them.
    surfaces: Vec<Texel>,
    surface_depth: Vec<f32>,
}

impl TranslucentLayer {
    pub fn new(width: usize, height: usize) -> Self {
        let pixels = width * height;
        Self {
            width,
            height,
            texels: vec![Texel::default(); pixels],
            surfaces: vec![Texel::default(); pixels],
            surface_depth: vec![f32::INFINITY; pixels],
        }
    }

    /// The forward pass's two RGBA f32 targets, one after the other: (colour, coverage) and
    /// (motion, linear depth, coverage), all premultiplied.
    pub fn from_forward_targets(texels: &[f32], width: usize, height: usize) -> Self {
        let pixels = width * height;
        let (color, motion) = texels.split_at(4 * pixels);
        let surfaces: Vec<Texel> = color
            .chunks_exact(4)
            .zip(motion.chunks_exact(4))
            .map(|(c, m)| Texel {
                color: Vec3::new(c[0], c[1], c[2]),
                motion: Vec2::new(m[0], m[1]),
                coverage: c[3],
            })
            .collect();
        let surface_depth = motion
            .chunks_exact(4)
            .map(|m| {
                if m[3] > 0.0 {
                    m[2] / m[3]
                } else {
                    f32::INFINITY
                }
            })
            .collect();
        Self {
            width,
            height,
            texels: surfaces.clone(),
            surfaces,
            surface_depth,
        }
    }

    pub fn width(&self) -> usize {
        self.width
    }

    pub fn height(&self) -> usize {
        self.height
    }

    /// Draws `texel`, at linear `depth`, into the layer at `pixel`, drawn back to front: over
    /// what it holds, or, beyond the blended surfaces there, seen through them:
    ///   surfaces over (texel over what lies under them).
    pub fn draw(&mut self, pixel: usize, texel: Texel, depth: f32) {
        let held = self.texels[pixel];
        self.texels[pixel] = if depth > self.surface_depth[pixel] {
            let surfaces = self.surfaces[pixel];
            // What lies under the surfaces, seen through them: held - surfaces.
            surfaces
                + texel * (1.0 - surfaces.coverage)
                + (held - surfaces) * (1.0 - texel.coverage)
        } else {
            texel.over(held)
        };
    }

    /// Composites the layer over the frame's lit colours, hides the view-dependent light behind
    /// it as much as the rest, and adds the mask and motion layers and the lit colours as they
    /// were before.
    pub fn composite(self, layers: &mut FrameLayers) {
        let before = |from: &str, name: &str| LayerImage {
            name: name.to_owned(),
            ..layers.layer(from).clone()
        };
        let opaque = before(FINAL_IMAGE, FINAL_IMAGE_OPAQUE);
        let opaque_without_dynamic_shadows = before(
            FINAL_IMAGE_NO_DYNAMIC_SHADOWS,
            FINAL_IMAGE_OPAQUE_NO_DYNAMIC_SHADOWS,
        );
        for layer in layers
            .layers
            .iter_mut()
            .filter(|l| l.name == FINAL_IMAGE || l.name == FINAL_IMAGE_NO_DYNAMIC_SHADOWS)
        {
            for (c, texel) in layer.data.chunks_mut(3).zip(&self.texels) {
                let behind = 1.0 - texel.coverage;
                for (channel, own) in c.iter_mut().zip(texel.color.to_array()) {
                    *channel = own + behind * *channel;
                }
            }
        }
        if let Some(specular) = layers.get_mut(SPECULAR_LIGHT) {
            for (c, texel) in specular.data.chunks_mut(3).zip(&self.texels) {
                c.iter_mut().for_each(|v| *v *= 1.0 - texel.coverage);
            }
        }
        let motion = self
            .texels
            .iter()
            .flat_map(|t| {
                if t.coverage > 0.0 {
                    (t.motion / t.coverage).to_array()
                } else {
                    [0.0; 2]
                }
            })
            .collect();
        let coverage = self.texels.iter().map(|t| t.coverage).collect();
        let (width, height) = (self.width, self.height);
        let layer = |name: &str, channels: &[&str], data| LayerImage {
            name: name.to_owned(),
            channels: channels.iter().map(|c| (*c).to_owned()).collect(),
            width,
            height,
            data,
        };
        let mask = layer(TRANSLUCENCY_MASK, &["R"], coverage);
        let motion = layer(TRANSLUCENCY_MOTION, &["R", "G"], motion);
        layers
            .layers
            .extend([mask, motion, opaque, opaque_without_dynamic_shadows]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A one-pixel layer holding a pane of `pane` at linear depth 5, as the forward pass writes it.
    fn layer_with_pane(pane: Texel) -> TranslucentLayer {
        let targets = [
            pane.color.x,
            pane.color.y,
            pane.color.z,
            pane.coverage,
            pane.motion.x,
            pane.motion.y,
            5.0 * pane.coverage,
            pane.coverage,
        ];
        TranslucentLayer::from_forward_targets(&targets, 1, 1)
    }

    fn close(a: Texel, b: Texel) -> bool {
        (a.color - b.color).abs().max_element() < 1e-6
            && (a.motion - b.motion).abs().max_element() < 1e-6
            && (a.coverage - b.coverage).abs() < 1e-6
    }

    #[test]
    fn a_particle_is_seen_through_the_blended_surfaces_it_lies_beyond() {
        let pane = Texel::new(Vec3::new(0.2, 0.4, 0.6), [1.0, -2.0], 0.3);
        let smoke = Texel::new(Vec3::new(0.9, 0.8, 0.7), [4.0, 0.5], 0.6);
        let ember = Texel::new(Vec3::new(3.0, 1.0, 0.1), [-3.0, 2.0], 0.5);

        let mut layer = layer_with_pane(pane);
        layer.draw(0, smoke, 2.0);
        assert!(close(layer.texels[0], smoke.over(pane)), "in front");

        let mut layer = layer_with_pane(pane);
        layer.draw(0, smoke, 9.0);
        assert!(close(layer.texels[0], pane.over(smoke)), "beyond");
        // Back to front: a nearer particle beyond the pane lies over the first, under the pane;
        // one in front of the pane over everything.
        layer.draw(0, ember, 7.0);
        assert!(
            close(layer.texels[0], pane.over(ember.over(smoke))),
            "two beyond"
        );
        layer.draw(0, smoke, 1.0);
        let expected = smoke.over(pane.over(ember.over(smoke)));
        assert!(close(layer.texels[0], expected), "and one in front");

        // With no blended surface, every particle is drawn over.
        let mut layer = TranslucentLayer::new(1, 1);
        layer.draw(0, smoke, 9.0);
        layer.draw(0, ember, 7.0);
        assert!(close(layer.texels[0], ember.over(smoke)), "no pane");
    }
}
