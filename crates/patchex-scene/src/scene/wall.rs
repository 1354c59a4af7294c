//! The scene format's `[[wall]]`: an upright opaque wall with a grid of windows glazed onto its
//! front (a facade, a greenhouse's side). Unlike a free-standing pane, the glass lies on an
//! opaque surface that moves exactly as it does, and at a distance a window is a few pixels
//! across.

use super::glass::{self, upright_quad, upright_transform, GlassDescription};
use super::ground_plane::one_primitive_model;
use crate::asset::{AlphaMode, Material, Model};
use glam::{Mat4, Quat, Vec3};
use serde::Deserialize;

/// How far in front of the wall its windows' glass lies, in metres: enough that depth testing
/// never lets the wall through the glass, too little to show as parallax.
const GLAZING_OFFSET: f32 = 0.01;

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WallDescription {
    /// The middle of the wall's bottom edge.
    pub position: [f32; 3],
    /// Width and height, in metres.
    pub size: [f32; 2],
    /// Turns the wall about the vertical; at 0 its front faces +z.
    #[serde(default)]
    pub yaw_deg: f32,
    pub color: [f32; 3],
    #[serde(default = "default_wall_roughness")]
    pub roughness: f32,
    pub windows: WindowsDescription,
}

/// A grid of equal windows spread evenly over the wall's front.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WindowsDescription {
    pub columns: u32,
    pub rows: u32,
    /// Each window's width and height, in metres.
    pub size: [f32; 2],
    /// The glass's tint, opacity and roughness, as `[[glass]]`'s.
    pub color: [f32; 3],
    pub opacity: f32,
    #[serde(default = "glass::default_roughness")]
    pub roughness: f32,
}

fn default_wall_roughness() -> f32 {
    0.8
}

impl WallDescription {
    /// The wall as a one-quad opaque model in its own frame, and where it stands.
    pub(crate) fn model(&self) -> (Model, Mat4) {
        let material = Material {
            base_color: Vec3::from(self.color).extend(1.0),
            metallic: 0.0,
            roughness: self.roughness,
            alpha_mode: AlphaMode::Opaque,
            ..Material::default()
        };
        (
            one_primitive_model("wall", upright_quad(self.size), material, Vec::new()),
            upright_transform(self.position, self.yaw_deg),
        )
    }

    /// The windows' panes, in the world.
    pub(crate) fn panes(&self) -> Vec<GlassDescription> {
        let [width, height] = self.size;
        let windows = &self.windows;
        let turn = Quat::from_rotation_y(self.yaw_deg.to_radians());
        let mut panes = Vec::new();
        for row in 0..windows.rows {
            for column in 0..windows.columns {
                let x = ((column as f32 + 0.5) / windows.columns as f32 - 0.5) * width;
                let y = (row as f32 + 0.5) / windows.rows as f32 * height - 0.5 * windows.size[1];
                let at = Vec3::from(self.position) + turn * Vec3::new(x, y, GLAZING_OFFSET);
                panes.push(GlassDescription {
                    position: at.to_array(),
                    size: windows.size,
                    yaw_deg: self.yaw_deg,
                    color: windows.color,
                    opacity: windows.opacity,
                    roughness: windows.roughness,
                });
            }
        }
        panes
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn windows_lie_on_the_wall_front_within_its_outline() {
        let wall: WallDescription = toml::from_str(
            "position = [1.0, 0.0, 2.0]\nsize = [4.0, 3.0]\nyaw_deg = 90.0\n\
             color = [0.5, 0.5, 0.5]\nwindows = { columns = 4, rows = 2, size = [0.5, 0.6], \
             color = [0.7, 0.8, 0.9], opacity = 0.4 }",
        )
        .expect("a wall parses");
        let (_, to_world) = wall.model();
        let to_wall = to_world.inverse();
        let panes = wall.panes();
        assert_eq!(panes.len(), 8);
        for pane in &panes {
            assert_eq!(pane.yaw_deg, wall.yaw_deg);
            // In the wall's frame: just before its front, and inside its outline.
            let bottom = to_wall.transform_point3(Vec3::from(pane.position));
            assert!((bottom.z - GLAZING_OFFSET).abs() < 1e-5, "{bottom}");
            assert!(
                bottom.x.abs() + 0.5 * pane.size[0] <= 2.0 + 1e-5,
                "{bottom}"
            );
            assert!(
                bottom.y >= 0.0 && bottom.y + pane.size[1] <= 3.0 + 1e-5,
                "{bottom}"
            );
        }
    }
}
