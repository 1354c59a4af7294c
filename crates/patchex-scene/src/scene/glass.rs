//! The scene format's `[[glass]]`: upright panes of tinted glass (shop windows, shelters,
//! screens), a blended material drawn by the forward pass over whatever lies behind them.

use super::ground_plane::one_primitive_model;
use crate::asset::{AlphaMode, Material, Model, Primitive};
use glam::{Mat4, Quat, Vec2, Vec3, Vec4};
use serde::Deserialize;

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GlassDescription {
    /// The middle of the pane's bottom edge.
    pub position: [f32; 3],
    /// Width and height, in metres.
    pub size: [f32; 2],
    /// Turns the pane about the vertical; at 0 it faces +z.
    #[serde(default)]
    pub yaw_deg: f32,
    /// The tint: the light the glass scatters back, as a base colour.
    pub color: [f32; 3],
    /// How much of what lies behind the glass hides, 0 to 1 (glTF's base colour alpha).
    pub opacity: f32,
    #[serde(default = "default_roughness")]
    pub roughness: f32,
}

pub(crate) fn default_roughness() -> f32 {
    0.05
}

impl GlassDescription {
    /// The pane as a one-quad model in its own frame, and where it stands.
    pub(crate) fn model(&self) -> (Model, Mat4) {
        let material = Material {
            base_color: Vec3::from(self.color).extend(self.opacity),
            metallic: 0.0,
            roughness: self.roughness,
            alpha_mode: AlphaMode::Blend,
            ..Material::default()
        };
        (
            one_primitive_model("glass", upright_quad(self.size), material, Vec::new()),
            self.transform(),
        )
    }

    /// Where the pane stands.
    pub(crate) fn transform(&self) -> Mat4 {
        upright_transform(self.position, self.yaw_deg)
    }
}

/// A `width` x `height` quad standing on the middle of its bottom edge, facing +z.
pub(crate) fn upright_quad([w, h]: [f32; 2]) -> Primitive {
    let corners = [(-0.5 * w, 0.0), (0.5 * w, 0.0), (0.5 * w, h), (-0.5 * w, h)];
    Primitive {
        positions: corners.iter().map(|&(x, y)| Vec3::new(x, y, 0.0)).collect(),
        normals: vec![Vec3::Z; 4],
        tangents: None,
        uvs: corners.iter().map(|&(x, y)| Vec2::new(x, y)).collect(),
        colors: vec![Vec4::ONE; 4],
        joints: None,
        weights: None,
        // Counter-clockwise seen from +z.
        indices: vec![0, 1, 2, 0, 2, 3],
        material: Some(0),
        morph_targets: Vec::new(),
    }
}

/// Stands an upright quad at `position`, turned `yaw_deg` about the vertical.
pub(crate) fn upright_transform(position: [f32; 3], yaw_deg: f32) -> Mat4 {
    Mat4::from_rotation_translation(
        Quat::from_rotation_y(yaw_deg.to_radians()),
        Vec3::from(position),
    )
}
