//! The scene format's built-in `[ground]`: a flat square for kits without ground of their own.

use super::GroundDescription;
use crate::asset::{AlphaMode, Material, Mesh, Model, Node, Primitive};
use glam::{Quat, Vec2, Vec3, Vec4};

/// A flat textureless square, as a one-primitive model.
pub(crate) fn ground_model(ground: &GroundDescription) -> Model {
    let h = ground.size * 0.5;
    let corners = [(-h, -h), (h, -h), (h, h), (-h, h)];
    let primitive = Primitive {
        positions: corners
            .iter()
            .map(|&(x, z)| Vec3::new(x, ground.height, z))
            .collect(),
        normals: vec![Vec3::Y; 4],
        tangents: None,
        uvs: corners.iter().map(|&(x, z)| Vec2::new(x, z)).collect(),
        colors: vec![Vec4::ONE; 4],
        joints: None,
        weights: None,
        // Counter-clockwise seen from above.
        indices: vec![0, 2, 1, 0, 3, 2],
        material: Some(0),
        morph_targets: Vec::new(),
    };
    Model {
        name: "ground".into(),
        nodes: vec![Node {
            name: "ground".into(),
            translation: Vec3::ZERO,
            rotation: Quat::IDENTITY,
            scale: Vec3::ONE,
            children: Vec::new(),
            mesh: Some(0),
            skin: None,
            weights: None,
        }],
        roots: vec![0],
        meshes: vec![Mesh {
            primitives: vec![primitive],
            weights: Vec::new(),
        }],
        skins: Vec::new(),
        animations: Vec::new(),
        materials: vec![Material {
            base_color: Vec3::from(ground.base_color).extend(1.0),
            metallic: 0.0,
            roughness: ground.roughness,
            alpha_mode: AlphaMode::Opaque,
            ..Material::default()
        }],
        textures: Vec::new(),
    }
}
