//! Expands `[[scatter]]` entries into individual props with a seeded generator, so the same
//! scene file always gives the same forest.

use super::{PropDescription, ScatterDescription};

/// SplitMix64: tiny, well distributed, and stable across platforms and crate versions.
pub(crate) struct SplitMix64(pub u64);

impl SplitMix64 {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn next_f32(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
    }
}

pub(crate) fn scatter_props(scatter: &ScatterDescription) -> Vec<PropDescription> {
    let mut rng = SplitMix64(scatter.seed);
    (0..scatter.count)
        .map(|_| {
            let asset =
                scatter.assets[(rng.next_u64() % scatter.assets.len() as u64) as usize].clone();
            // Uniform over the ring's area, not its radius.
            let (r0, r1) = (scatter.radius_min, scatter.radius_max);
            let radius = (r0 * r0 + rng.next_f32() * (r1 * r1 - r0 * r0)).sqrt();
            let angle = rng.next_f32() * std::f32::consts::TAU;
            let [cx, cy, cz] = scatter.center;
            PropDescription {
                asset,
                position: [cx + radius * angle.cos(), cy, cz + radius * angle.sin()],
                yaw_deg: rng.next_f32() * 360.0,
                scale: scatter.scale_min + rng.next_f32() * (scatter.scale_max - scatter.scale_min),
                ground: false,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scatter_is_deterministic_and_stays_in_the_ring() {
        let scatter = ScatterDescription {
            assets: vec!["a.glb".into(), "b.glb".into()],
            count: 200,
            center: [10.0, 0.0, -5.0],
            radius_min: 2.0,
            radius_max: 6.0,
            scale_min: 0.5,
            scale_max: 1.5,
            seed: 7,
        };
        let first = scatter_props(&scatter);
        let second = scatter_props(&scatter);
        assert_eq!(first.len(), 200);
        for (a, b) in first.iter().zip(&second) {
            assert_eq!(a.position, b.position);
            assert_eq!(a.asset, b.asset);
            let r = ((a.position[0] - 10.0).powi(2) + (a.position[2] + 5.0).powi(2)).sqrt();
            assert!((2.0 - 1e-4..=6.0 + 1e-4).contains(&r), "radius {r}");
            assert!((0.5..=1.5).contains(&a.scale));
        }
        assert!(
            first.iter().any(|p| p.asset == "a.glb") && first.iter().any(|p| p.asset == "b.glb")
        );
    }
}
