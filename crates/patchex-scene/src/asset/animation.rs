//! Animation clips: keyframe channels on node translation, rotation, scale and morph target
//! weights, sampled with glTF's STEP, LINEAR and CUBICSPLINE interpolation.

use glam::{Quat, Vec3, Vec4};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Property {
    Translation,
    Rotation,
    Scale,
    MorphWeights,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolation {
    Step,
    Linear,
    CubicSpline,
}

pub struct Channel {
    pub node: usize,
    pub property: Property,
    pub interpolation: Interpolation,
    pub times: Vec<f32>,
    /// Floats per value: 3 for translation and scale, 4 for a rotation (xyzw), one per
    /// morph target for weights.
    pub width: usize,
    /// One value per key, or (in-tangent, value, out-tangent) per key for CUBICSPLINE.
    pub values: Vec<f32>,
}

pub struct AnimationClip {
    pub name: String,
    pub duration: f32,
    pub channels: Vec<Channel>,
}

/// A sampled channel value, ready to replace the node's rest value.
#[derive(Clone, Debug, PartialEq)]
pub enum ChannelValue {
    Translation(Vec3),
    Rotation(Quat),
    Scale(Vec3),
    MorphWeights(Vec<f32>),
}

impl AnimationClip {
    /// Maps a playback time to clip time, looping over the clip's duration.
    pub fn looped_time(&self, time: f32) -> f32 {
        if self.duration <= 0.0 {
            0.0
        } else {
            time.rem_euclid(self.duration)
        }
    }
}

impl Channel {
    pub fn sample(&self, time: f32) -> ChannelValue {
        let raw = self.sample_raw(time);
        let vec3 = || Vec3::from_slice(&raw);
        match self.property {
            Property::Translation => ChannelValue::Translation(vec3()),
            Property::Scale => ChannelValue::Scale(vec3()),
            Property::Rotation => {
                ChannelValue::Rotation(Quat::from_vec4(Vec4::from_slice(&raw)).normalize())
            }
            Property::MorphWeights => ChannelValue::MorphWeights(raw),
        }
    }

    /// Value `slot` (0 in-tangent, 1 value, 2 out-tangent for cubic splines) of `key`.
    fn element(&self, key: usize, slot: usize) -> &[f32] {
        let index = match self.interpolation {
            Interpolation::CubicSpline => key * 3 + slot,
            _ => key,
        };
        &self.values[index * self.width..(index + 1) * self.width]
    }

    fn value(&self, key: usize) -> Vec<f32> {
        self.element(key, 1).to_vec()
    }

    fn sample_raw(&self, time: f32) -> Vec<f32> {
        let last = self.times.len() - 1;
        if time <= self.times[0] {
            return self.value(0);
        }
        if time >= self.times[last] {
            return self.value(last);
        }
        // First key strictly after `time`; the clamps above keep it in 1..=last.
        let next = self.times.partition_point(|&key_time| key_time <= time);
        let previous = next - 1;
        let span = self.times[next] - self.times[previous];
        let t = if span > 0.0 {
            (time - self.times[previous]) / span
        } else {
            0.0
        };
        match self.interpolation {
            Interpolation::Step => self.value(previous),
            Interpolation::Linear if self.property == Property::Rotation => {
                let qa = Quat::from_vec4(Vec4::from_slice(self.element(previous, 1)));
                let qb = Quat::from_vec4(Vec4::from_slice(self.element(next, 1)));
                qa.slerp(qb, t).to_array().to_vec()
            }
            Interpolation::Linear => {
                let (a, b) = (self.element(previous, 1), self.element(next, 1));
                a.iter().zip(b).map(|(a, b)| a + (b - a) * t).collect()
            }
            Interpolation::CubicSpline => {
                // Hermite spline of glTF 2.0 appendix C; tangents are scaled by the key span.
                let (t2, t3) = (t * t, t * t * t);
                let (p0, m0) = (self.element(previous, 1), self.element(previous, 2));
                let (p1, m1) = (self.element(next, 1), self.element(next, 0));
                (0..self.width)
                    .map(|i| {
                        p0[i] * (2.0 * t3 - 3.0 * t2 + 1.0)
                            + m0[i] * span * (t3 - 2.0 * t2 + t)
                            + p1[i] * (-2.0 * t3 + 3.0 * t2)
                            + m1[i] * span * (t3 - t2)
                    })
                    .collect()
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn channel(interpolation: Interpolation, values: Vec<Vec3>) -> Channel {
        Channel {
            node: 0,
            property: Property::Translation,
            interpolation,
            times: vec![0.0, 1.0, 3.0],
            width: 3,
            values: values.iter().flat_map(|v| v.to_array()).collect(),
        }
    }

    #[test]
    fn linear_interpolates_between_keys_and_clamps_outside() {
        let c = channel(
            Interpolation::Linear,
            vec![
                Vec3::ZERO,
                Vec3::new(2.0, 0.0, 0.0),
                Vec3::new(2.0, 4.0, 0.0),
            ],
        );
        assert_eq!(
            c.sample(0.5),
            ChannelValue::Translation(Vec3::new(1.0, 0.0, 0.0))
        );
        assert_eq!(
            c.sample(2.0),
            ChannelValue::Translation(Vec3::new(2.0, 2.0, 0.0))
        );
        assert_eq!(c.sample(-1.0), ChannelValue::Translation(Vec3::ZERO));
        assert_eq!(
            c.sample(9.0),
            ChannelValue::Translation(Vec3::new(2.0, 4.0, 0.0))
        );
    }

    #[test]
    fn step_holds_the_previous_key() {
        let c = channel(
            Interpolation::Step,
            vec![Vec3::ZERO, Vec3::ONE, Vec3::splat(5.0)],
        );
        assert_eq!(c.sample(0.99), ChannelValue::Translation(Vec3::ZERO));
        assert_eq!(c.sample(1.5), ChannelValue::Translation(Vec3::ONE));
    }

    #[test]
    fn cubic_spline_with_zero_tangents_passes_through_keys_and_midpoint() {
        let key = |v: f32| [Vec3::ZERO, Vec3::splat(v), Vec3::ZERO];
        let values = [key(0.0), key(1.0), key(3.0)].concat();
        let c = channel(Interpolation::CubicSpline, values);
        assert_eq!(c.sample(1.0), ChannelValue::Translation(Vec3::splat(1.0)));
        // Smoothstep between keys 1 and 3 at the middle of the span gives the mean.
        assert_eq!(c.sample(2.0), ChannelValue::Translation(Vec3::splat(2.0)));
    }

    #[test]
    fn morph_weights_interpolate_per_target() {
        let c = Channel {
            node: 0,
            property: Property::MorphWeights,
            interpolation: Interpolation::Linear,
            times: vec![0.0, 2.0],
            width: 2,
            values: vec![0.0, 1.0, 1.0, 0.0],
        };
        assert_eq!(c.sample(0.5), ChannelValue::MorphWeights(vec![0.25, 0.75]));
    }

    #[test]
    fn looped_time_wraps_into_the_clip() {
        let clip = AnimationClip {
            name: "walk".into(),
            duration: 2.0,
            channels: Vec::new(),
        };
        assert!((clip.looped_time(5.5) - 1.5).abs() < 1e-6);
        assert!((clip.looped_time(-0.5) - 1.5).abs() < 1e-6);
    }
}
