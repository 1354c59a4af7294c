//! Animation clips: keyframe channels on node translation, rotation and scale, sampled with
//! glTF's STEP, LINEAR and CUBICSPLINE interpolation.

use glam::{Quat, Vec3, Vec4};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Property {
    Translation,
    Rotation,
    Scale,
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
    /// One value per key, or (in-tangent, value, out-tangent) per key for CUBICSPLINE.
    /// Translation and scale use xyz; rotation is a quaternion in xyzw.
    pub values: Vec<Vec4>,
}

pub struct AnimationClip {
    pub name: String,
    pub duration: f32,
    pub channels: Vec<Channel>,
}

/// A sampled channel value, ready to replace the node's rest transform component.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ChannelValue {
    Translation(Vec3),
    Rotation(Quat),
    Scale(Vec3),
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
        match self.property {
            Property::Translation => ChannelValue::Translation(raw.truncate()),
            Property::Scale => ChannelValue::Scale(raw.truncate()),
            Property::Rotation => ChannelValue::Rotation(Quat::from_vec4(raw).normalize()),
        }
    }

    fn value(&self, key: usize) -> Vec4 {
        match self.interpolation {
            Interpolation::CubicSpline => self.values[key * 3 + 1],
            _ => self.values[key],
        }
    }

    fn sample_raw(&self, time: f32) -> Vec4 {
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
            Interpolation::Linear => {
                let (a, b) = (self.value(previous), self.value(next));
                if self.property == Property::Rotation {
                    let qa = Quat::from_vec4(a);
                    let qb = Quat::from_vec4(b);
                    Vec4::from(qa.slerp(qb, t))
                } else {
                    a.lerp(b, t)
                }
            }
            Interpolation::CubicSpline => {
                // Hermite spline of glTF 2.0 appendix C; tangents are scaled by the key span.
                let p0 = self.values[previous * 3 + 1];
                let m0 = self.values[previous * 3 + 2] * span;
                let p1 = self.values[next * 3 + 1];
                let m1 = self.values[next * 3] * span;
                let (t2, t3) = (t * t, t * t * t);
                p0 * (2.0 * t3 - 3.0 * t2 + 1.0)
                    + m0 * (t3 - 2.0 * t2 + t)
                    + p1 * (-2.0 * t3 + 3.0 * t2)
                    + m1 * (t3 - t2)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn channel(interpolation: Interpolation, values: Vec<Vec4>) -> Channel {
        Channel {
            node: 0,
            property: Property::Translation,
            interpolation,
            times: vec![0.0, 1.0, 3.0],
            values,
        }
    }

    #[test]
    fn linear_interpolates_between_keys_and_clamps_outside() {
        let c = channel(
            Interpolation::Linear,
            vec![
                Vec4::ZERO,
                Vec4::new(2.0, 0.0, 0.0, 0.0),
                Vec4::new(2.0, 4.0, 0.0, 0.0),
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
            vec![Vec4::ZERO, Vec4::ONE, Vec4::new(5.0, 5.0, 5.0, 0.0)],
        );
        assert_eq!(c.sample(0.99), ChannelValue::Translation(Vec3::ZERO));
        assert_eq!(c.sample(1.5), ChannelValue::Translation(Vec3::ONE));
    }

    #[test]
    fn cubic_spline_with_zero_tangents_passes_through_keys_and_midpoint() {
        let key = |v: f32| [Vec4::ZERO, Vec4::splat(v), Vec4::ZERO];
        let values = [key(0.0), key(1.0), key(3.0)].concat();
        let c = channel(Interpolation::CubicSpline, values);
        assert_eq!(c.sample(1.0), ChannelValue::Translation(Vec3::splat(1.0)));
        // Smoothstep between keys 1 and 3 at the middle of the span gives the mean.
        assert_eq!(c.sample(2.0), ChannelValue::Translation(Vec3::splat(2.0)));
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
