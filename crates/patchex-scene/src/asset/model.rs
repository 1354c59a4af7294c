//! Plain-data form of a glTF file, independent of the `gltf` crate's borrowed views.

use super::{AnimationClip, TextureData};
use glam::{Mat4, Quat, Vec2, Vec3, Vec4};

pub struct Model {
    pub name: String,
    pub nodes: Vec<Node>,
    /// Root nodes of the file's default scene.
    pub roots: Vec<usize>,
    pub meshes: Vec<Mesh>,
    pub skins: Vec<Skin>,
    pub animations: Vec<AnimationClip>,
    pub materials: Vec<Material>,
    pub textures: Vec<TextureData>,
}

impl Model {
    pub fn animation_index(&self, name: &str) -> Option<usize> {
        self.animations.iter().position(|clip| clip.name == name)
    }

    pub fn animation_names(&self) -> Vec<&str> {
        self.animations
            .iter()
            .map(|clip| clip.name.as_str())
            .collect()
    }
}

#[derive(Clone)]
pub struct Node {
    pub name: String,
    pub translation: Vec3,
    pub rotation: Quat,
    pub scale: Vec3,
    pub children: Vec<usize>,
    pub mesh: Option<usize>,
    pub skin: Option<usize>,
    /// Morph target weights of this instance; the mesh's defaults apply when `None`.
    pub weights: Option<Vec<f32>>,
}

impl Node {
    pub fn local_matrix(&self) -> Mat4 {
        Mat4::from_scale_rotation_translation(self.scale, self.rotation, self.translation)
    }
}

pub struct Mesh {
    pub primitives: Vec<Primitive>,
    /// Default morph target weights.
    pub weights: Vec<f32>,
}

/// Per-vertex displacements of one morph target.
pub struct MorphTarget {
    pub positions: Option<Vec<Vec3>>,
    pub normals: Option<Vec<Vec3>>,
    pub tangents: Option<Vec<Vec3>>,
}

/// One triangle list with a single material. Optional attributes are filled with glTF's
/// defaults at load time, so every vector has one entry per vertex.
pub struct Primitive {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    /// w = handedness; `None` when the file has no tangents (the shader derives them).
    pub tangents: Option<Vec<Vec4>>,
    pub uvs: Vec<Vec2>,
    pub colors: Vec<Vec4>,
    pub joints: Option<Vec<[u16; 4]>>,
    pub weights: Option<Vec<Vec4>>,
    pub indices: Vec<u32>,
    pub material: Option<usize>,
    pub morph_targets: Vec<MorphTarget>,
}

pub struct Skin {
    pub joints: Vec<usize>,
    pub inverse_bind_matrices: Vec<Mat4>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AlphaMode {
    Opaque,
    /// Fragments below the cutoff are discarded.
    Mask(f32),
    /// Blended over what lies behind by its alpha: drawn after lighting, in the forward pass.
    Blend,
}

/// PBR metallic-roughness material. Texture indices point into [`Model::textures`].
#[derive(Clone, Debug)]
pub struct Material {
    pub base_color: Vec4,
    pub base_color_texture: Option<usize>,
    pub metallic: f32,
    pub roughness: f32,
    pub metallic_roughness_texture: Option<usize>,
    pub normal_texture: Option<usize>,
    pub normal_scale: f32,
    /// Emissive factor already multiplied by KHR_materials_emissive_strength.
    pub emissive: Vec3,
    pub emissive_texture: Option<usize>,
    pub alpha_mode: AlphaMode,
    /// Unreal's specular scalar; glTF's default dielectric F0 of 0.04 is 0.08 * 0.5.
    pub specular: f32,
}

impl Default for Material {
    fn default() -> Self {
        Self {
            base_color: Vec4::ONE,
            base_color_texture: None,
            metallic: 1.0,
            roughness: 1.0,
            metallic_roughness_texture: None,
            normal_texture: None,
            normal_scale: 1.0,
            emissive: Vec3::ZERO,
            emissive_texture: None,
            alpha_mode: AlphaMode::Opaque,
            specular: 0.5,
        }
    }
}
