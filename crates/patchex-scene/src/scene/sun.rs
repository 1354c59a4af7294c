//! The directional sun and the orthographic projection of its shadow maps.

use super::projection::{look_at, orthographic};
use super::{SceneDescription, SunDescription, Vertex};
use glam::{Mat4, Vec3};

#[derive(Clone, Copy, Debug)]
pub struct SunLight {
    /// Unit vector from the surface toward the sun.
    pub direction: Vec3,
    pub radiance: Vec3,
    pub light_view_proj: Mat4,
    pub shadow_resolution: u32,
    /// World size of one shadow-map texel, for biasing.
    pub texel_size: f32,
    /// Depth bias in light clip units (one texel's worth of depth).
    pub depth_bias: f32,
}

impl SunLight {
    /// `center` and `radius` give the square (seen from the sun) that the shadow maps cover.
    pub fn new(description: &SunDescription, center: Vec3, radius: f32) -> Self {
        let (azimuth, elevation) = (
            description.azimuth_deg.to_radians(),
            description.elevation_deg.to_radians(),
        );
        let direction = Vec3::new(
            elevation.cos() * azimuth.sin(),
            elevation.sin(),
            elevation.cos() * azimuth.cos(),
        );
        let up = if direction.y.abs() > 0.999 {
            Vec3::Z
        } else {
            Vec3::Y
        };
        let depth_range = 4.0 * radius;
        let view = look_at(center + direction * (2.0 * radius), center, up);
        let proj = orthographic(-radius, radius, -radius, radius, 0.0, depth_range);
        let texel_size = 2.0 * radius / description.shadow_resolution as f32;
        Self {
            direction,
            radiance: Vec3::from(description.color) * description.intensity,
            light_view_proj: proj * view,
            shadow_resolution: description.shadow_resolution,
            texel_size,
            depth_bias: 1.5 * texel_size / depth_range,
        }
    }
}

/// The square the shadow maps cover: the scene file's, or the characters' walking area grown
/// by a margin (so their shadows stay sharp), limited to the static geometry's extent.
pub(crate) fn shadow_region(
    description: &SceneDescription,
    static_vertices: &[Vertex],
) -> (Vec3, f32) {
    if let (Some(center), Some(radius)) =
        (description.sun.shadow_center, description.sun.shadow_radius)
    {
        return (Vec3::from(center), radius);
    }
    let bounds = |points: &mut dyn Iterator<Item = Vec3>| {
        points.fold(None, |acc: Option<(Vec3, Vec3)>, p| {
            Some(acc.map_or((p, p), |(lo, hi)| (lo.min(p), hi.max(p))))
        })
    };
    let static_bounds = bounds(&mut static_vertices.iter().map(|v| Vec3::from(v.position)));
    let walk_bounds = bounds(
        &mut description
            .character
            .iter()
            .flat_map(|c| c.path.iter().copied().map(Vec3::from)),
    );
    let half_diagonal = |(lo, hi): (Vec3, Vec3)| (hi - lo).length() * 0.5;
    match (static_bounds, walk_bounds) {
        (Some(s), Some((lo, hi))) => {
            let margin = Vec3::splat(8.0);
            let walk = (lo - margin, hi + margin);
            (
                ((walk.0 + walk.1) * 0.5),
                half_diagonal(walk).min(half_diagonal(s).max(1.0)),
            )
        }
        (Some(s), None) => ((s.0 + s.1) * 0.5, half_diagonal(s).max(1.0)),
        (None, Some(w)) => ((w.0 + w.1) * 0.5, half_diagonal(w) + 8.0),
        (None, None) => (Vec3::ZERO, 10.0),
    }
}
