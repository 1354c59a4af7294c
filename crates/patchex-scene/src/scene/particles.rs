//! Particle emitters: smoke, sparks and embers with motion of their own, each particle a
//! camera-facing soft disc whose state is a closed-form function of time, so that any instant
//! and its motion to an earlier one are exact.

use glam::Vec3;
use serde::Deserialize;

/// One emitter of a scene file (`[[particles]]`).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EmitterDescription {
    /// Where particles are born, in metres.
    pub origin: [f32; 3],
    /// Radius of the ball around `origin` they are born in.
    #[serde(default)]
    pub origin_spread: f32,
    /// Particles born per second.
    pub rate: f32,
    /// Seconds each particle lives.
    pub lifetime: f32,
    /// Mean velocity at birth, m/s.
    pub velocity: [f32; 3],
    /// Each particle's velocity differs from the mean by up to this much in every axis, m/s.
    #[serde(default)]
    pub velocity_spread: f32,
    /// Constant acceleration (buoyancy, wind, gravity), m/s^2.
    #[serde(default)]
    pub acceleration: [f32; 3],
    /// Radius at birth and at death, metres.
    pub radius: [f32; 2],
    /// Linear radiance of the particle's own colour, already lit (or emitted).
    pub color: [f32; 3],
    /// Opacity at the middle of its life; particles fade in and out.
    pub opacity: f32,
    pub seed: u64,
}

/// A particle at one instant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Particle {
    pub position: Vec3,
    /// Where the same particle was at the earlier instant asked for.
    pub previous_position: Vec3,
    pub radius: f32,
    pub opacity: f32,
    pub color: Vec3,
}

impl EmitterDescription {
    /// The particles alive at `time`, with their positions at `previous_time`.
    pub fn particles(&self, time: f32, previous_time: f32) -> Vec<Particle> {
        if !(self.rate > 0.0 && self.lifetime > 0.0) {
            return Vec::new();
        }
        let first = ((time - self.lifetime) * self.rate).floor() as i64 + 1;
        let last = (time * self.rate).floor() as i64;
        (first..=last)
            .filter_map(|birth_index| self.particle(birth_index, time, previous_time))
            .collect()
    }

    fn particle(&self, birth_index: i64, time: f32, previous_time: f32) -> Option<Particle> {
        let birth = birth_index as f32 / self.rate;
        let life = (time - birth) / self.lifetime;
        if !(0.0..=1.0).contains(&life) {
            return None;
        }
        let mut random = ParticleRandom::new(self.seed, birth_index);
        let start = Vec3::from(self.origin) + self.origin_spread * random.in_ball();
        let velocity = Vec3::from(self.velocity) + self.velocity_spread * random.in_cube();
        let acceleration = Vec3::from(self.acceleration);
        // Closed form, so the earlier position is exact even before the particle was born.
        let at = |t: f32| {
            let age = t - birth;
            start + velocity * age + 0.5 * acceleration * age * age
        };
        let [born, dies] = self.radius;
        Some(Particle {
            position: at(time),
            previous_position: at(previous_time),
            radius: born + (dies - born) * life,
            // Fades in and out: 4x(1-x) peaks at 1 halfway through its life.
            opacity: self.opacity * 4.0 * life * (1.0 - life),
            color: Vec3::from(self.color) * (0.85 + 0.3 * random.unit()),
        })
    }
}

/// A particle's own random numbers: the same for a birth index at every instant.
struct ParticleRandom(u64);

impl ParticleRandom {
    fn new(seed: u64, birth_index: i64) -> Self {
        Self(seed ^ (birth_index as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15))
    }

    /// SplitMix64, in [0, 1).
    fn unit(&mut self) -> f32 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
    }

    fn in_cube(&mut self) -> Vec3 {
        Vec3::new(self.unit(), self.unit(), self.unit()) * 2.0 - 1.0
    }

    fn in_ball(&mut self) -> Vec3 {
        loop {
            let v = self.in_cube();
            if v.length_squared() <= 1.0 {
                return v;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn smoke() -> EmitterDescription {
        EmitterDescription {
            origin: [0.0, 0.0, 0.0],
            origin_spread: 0.2,
            rate: 10.0,
            lifetime: 2.0,
            velocity: [0.0, 1.0, 0.0],
            velocity_spread: 0.2,
            acceleration: [0.5, 0.0, 0.0],
            radius: [0.2, 0.8],
            color: [0.5, 0.5, 0.5],
            opacity: 0.6,
            seed: 7,
        }
    }

    #[test]
    fn a_steady_emitter_holds_rate_times_lifetime_particles() {
        let alive = smoke().particles(5.0, 4.9).len();
        assert!((19..=21).contains(&alive), "{alive} particles alive");
    }

    #[test]
    fn a_particle_is_the_same_at_every_instant_it_is_asked_about() {
        let emitter = smoke();
        let earlier = emitter.particles(5.0, 4.95);
        let later = emitter.particles(5.05, 5.0);
        // Every particle of the later instant that was alive before moved from where it was.
        let moved = later
            .iter()
            .filter(|p| earlier.iter().any(|q| q.position == p.previous_position))
            .count();
        assert!(
            moved + 1 >= later.len(),
            "{moved} of {} tracked",
            later.len()
        );
    }
}
