//! A loaded scene: static geometry baked to world space once, characters posed per instant,
//! and the sun. The camera rigs are evaluated in `camera_rig.rs`.

use super::batch::MeshBatch;
use super::description::{CameraRig, CharacterDescription, PropDescription, SceneDescription};
use super::ground::GroundSurface;
use super::ground_plane::ground_model;
use super::path::PathMotion;
use super::placement::scatter_props;
use super::sun::{shadow_region, SunLight};
use super::Vertex;
use crate::asset::{load_model, AlphaMode, Material, Model, Pose, PosedVertex, TextureData};
use crate::error::{io_error, Error, Result};
use glam::{Mat4, Quat, Vec3};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// A skinned, animated dynamic object with its own CustomStencil id.
pub struct Character {
    pub description: CharacterDescription,
    pub model: usize,
    pub clip: Option<usize>,
    /// 1-based, in the order of the scene file.
    pub stencil: u32,
    path: PathMotion,
}

pub struct World {
    pub description: SceneDescription,
    pub models: Vec<Model>,
    /// All materials; index 0 is glTF's default material. Texture indices point into `textures`.
    pub materials: Vec<Material>,
    pub textures: Vec<TextureData>,
    pub static_batch: MeshBatch,
    /// Triangles and draws of all characters; vertices come from [`World::dynamic_vertices`].
    pub dynamic_batch: MeshBatch,
    pub characters: Vec<Character>,
    pub sun: SunLight,
    /// Surface of the props marked `ground`, which characters stand on.
    pub ground: Option<GroundSurface>,
    /// Asset path of each model, relative to the assets folder.
    pub model_assets: Vec<String>,
}

/// Loads each asset file once and moves its materials and textures into the world's tables.
struct ModelCache {
    assets_dir: PathBuf,
    models: Vec<Model>,
    model_assets: Vec<String>,
    material_offsets: Vec<u32>,
    by_asset: HashMap<String, usize>,
    materials: Vec<Material>,
    textures: Vec<TextureData>,
}

impl ModelCache {
    fn get(&mut self, asset: &str) -> Result<usize> {
        if let Some(&index) = self.by_asset.get(asset) {
            return Ok(index);
        }
        let model = load_model(&self.assets_dir.join(asset))?;
        Ok(self.insert(asset.to_owned(), model))
    }

    fn insert(&mut self, asset: String, mut model: Model) -> usize {
        let texture_offset = self.textures.len();
        self.textures.append(&mut model.textures);
        self.material_offsets.push(self.materials.len() as u32);
        for material in &model.materials {
            let shift = |t: Option<usize>| t.map(|t| t + texture_offset);
            self.materials.push(Material {
                base_color_texture: shift(material.base_color_texture),
                metallic_roughness_texture: shift(material.metallic_roughness_texture),
                normal_texture: shift(material.normal_texture),
                emissive_texture: shift(material.emissive_texture),
                ..material.clone()
            });
        }
        self.models.push(model);
        self.model_assets.push(asset.clone());
        self.by_asset.insert(asset, self.models.len() - 1);
        self.models.len() - 1
    }
}

impl World {
    /// Reads a scene file; assets resolve against `assets_dir`, or else the `assets` folder
    /// beside the nearest folder above the scene file that has one (`scenes/x.toml` and
    /// `scenes/generated/x.toml` both find the repository's).
    pub fn load(scene_path: &Path, assets_dir: Option<&Path>) -> Result<Self> {
        let text = std::fs::read_to_string(scene_path).map_err(io_error(scene_path))?;
        let description: SceneDescription = toml::from_str(&text).map_err(|e| Error::Scene {
            path: scene_path.to_path_buf(),
            message: e.to_string(),
        })?;
        let assets_dir = match assets_dir {
            Some(dir) => dir.to_path_buf(),
            None => {
                let scene_dir = scene_path
                    .parent()
                    .filter(|dir| !dir.as_os_str().is_empty())
                    .unwrap_or(Path::new("."));
                let scene_dir = std::fs::canonicalize(scene_dir).map_err(io_error(scene_dir))?;
                scene_dir
                    .ancestors()
                    .skip(1)
                    .map(|folder| folder.join("assets"))
                    .find(|assets| assets.is_dir())
                    .unwrap_or_else(|| scene_dir.join("..").join("assets"))
            }
        };
        Self::from_description(description, &assets_dir).map_err(|e| match e {
            Error::Scene { message, .. } => Error::Scene {
                path: scene_path.to_path_buf(),
                message,
            },
            other => other,
        })
    }

    pub fn from_description(description: SceneDescription, assets_dir: &Path) -> Result<Self> {
        let mut cache = ModelCache {
            assets_dir: assets_dir.to_path_buf(),
            models: Vec::new(),
            model_assets: Vec::new(),
            material_offsets: Vec::new(),
            by_asset: HashMap::new(),
            materials: vec![Material::default()],
            textures: Vec::new(),
        };

        let mut static_batch = MeshBatch::default();
        let mut props: Vec<PropDescription> = description.environment.clone();
        props.extend(description.scatter.iter().flat_map(scatter_props));
        // (model, transform, whether characters stand on it)
        let mut instances: Vec<(usize, Mat4, bool)> = Vec::new();
        if let Some(ground) = &description.ground {
            let index = cache.insert("(ground)".into(), ground_model(ground));
            instances.push((index, Mat4::IDENTITY, false));
        }
        for (index, glass) in description.glass.iter().enumerate() {
            let (model, transform) = glass.model();
            let index = cache.insert(format!("(glass {index})"), model);
            instances.push((index, transform, false));
        }
        for (index, wall) in description.wall.iter().enumerate() {
            let (model, transform) = wall.model();
            let wall_model = cache.insert(format!("(wall {index})"), model);
            instances.push((wall_model, transform, false));
            // Every window of a wall is the same pane: one model, placed once per window.
            let panes = wall.panes();
            if let Some(first) = panes.first() {
                let pane_model = cache.insert(format!("(wall {index} window)"), first.model().0);
                for pane in &panes {
                    instances.push((pane_model, pane.transform(), false));
                }
            }
        }
        for prop in &props {
            let model = cache.get(&prop.asset)?;
            let transform = Mat4::from_scale_rotation_translation(
                Vec3::splat(prop.scale),
                Quat::from_rotation_y(prop.yaw_deg.to_radians()),
                Vec3::from(prop.position),
            );
            instances.push((model, transform, prop.ground));
        }
        let mut ground_triangles = Vec::new();
        for &(model_index, transform, is_ground) in &instances {
            let model = &cache.models[model_index];
            let first_index = static_batch.indices.len();
            static_batch.append_triangles(model, cache.material_offsets[model_index], 0, 0);
            let mut posed = Vec::new();
            Pose::new(model, transform, None).vertices(model, &mut posed);
            static_batch.append_vertices(model, &posed, &posed);
            if is_ground {
                let corner = |i: u32| Vec3::from(static_batch.vertices[i as usize].position);
                ground_triangles.extend(
                    static_batch.indices[first_index..]
                        .chunks_exact(3)
                        .map(|t| [corner(t[0]), corner(t[1]), corner(t[2])]),
                );
            }
        }
        let ground = (!ground_triangles.is_empty()).then(|| GroundSurface::new(ground_triangles));

        let mut characters = Vec::new();
        let mut dynamic_batch = MeshBatch::default();
        for (index, character) in description.character.iter().enumerate() {
            let model_index = cache.get(&character.asset)?;
            let model = &cache.models[model_index];
            let clip = match &character.clip {
                Some(name) => Some(model.animation_index(name).ok_or_else(|| Error::Scene {
                    path: PathBuf::new(),
                    message: format!(
                        "character {:?}: {} has no clip {name:?} (clips: {})",
                        character.name,
                        character.asset,
                        model.animation_names().join(", ")
                    ),
                })?),
                None => None,
            };
            let stencil = index as u32 + 1;
            dynamic_batch.append_triangles(model, cache.material_offsets[model_index], 0, stencil);
            characters.push(Character {
                description: character.clone(),
                model: model_index,
                clip,
                stencil,
                path: PathMotion::new(&character.path),
            });
        }
        if let CameraRig::Follow { character, .. } = &description.camera.rig {
            if !characters.iter().any(|c| &c.description.name == character) {
                return Err(Error::Scene {
                    path: PathBuf::new(),
                    message: format!("the camera follows {character:?}, which is not a character"),
                });
            }
        }

        let (center, radius) = shadow_region(&description, &static_batch.vertices);
        let sun = SunLight::new(&description.sun, center, radius);
        Ok(Self {
            description,
            models: cache.models,
            materials: cache.materials,
            textures: cache.textures,
            static_batch,
            dynamic_batch,
            characters,
            sun,
            ground,
            model_assets: cache.model_assets,
        })
    }

    /// Root transform of a character: on its path, facing the way it walks.
    pub fn character_transform(&self, character: &Character, time: f32) -> Mat4 {
        let d = &character.description;
        let (mut position, heading) = character.path.at(d.walk_speed * time);
        if let Some(height) = self
            .ground
            .as_ref()
            .and_then(|g| g.height_at(position.x, position.z))
        {
            position.y += height;
        }
        let walking = d.walk_speed > 0.0 && d.path.len() >= 2;
        let yaw = if walking {
            heading.x.atan2(heading.z)
        } else {
            d.yaw_deg.to_radians()
        } + d.yaw_offset_deg.to_radians();
        Mat4::from_scale_rotation_translation(
            Vec3::splat(d.scale),
            Quat::from_rotation_y(yaw),
            position,
        )
    }

    fn pose_character(&self, character: &Character, time: f32, out: &mut Vec<PosedVertex>) {
        let model = &self.models[character.model];
        let clip = character.clip.map(|clip| {
            let d = &character.description;
            (
                clip,
                model.animations[clip].looped_time(time * d.clip_speed + d.clip_offset),
            )
        });
        Pose::new(model, self.character_transform(character, time), clip).vertices(model, out);
    }

    /// Whether frames draw anything after lighting: particles, or surfaces of blended materials.
    pub fn draws_translucency(&self) -> bool {
        let blended = |batch: &MeshBatch| {
            batch
                .draws
                .iter()
                .any(|d| self.materials[d.material as usize].alpha_mode == AlphaMode::Blend)
        };
        !self.description.particles.is_empty()
            || blended(&self.static_batch)
            || blended(&self.dynamic_batch)
    }

    /// Every emitter's particles alive at `time`, with their positions at `previous_time`.
    pub fn particles(&self, time: f32, previous_time: f32) -> Vec<super::Particle> {
        self.description
            .particles
            .iter()
            .flat_map(|emitter| emitter.particles(time, previous_time))
            .collect()
    }

    /// Vertices of all characters at `time`, with their positions at `previous_time` for
    /// motion vectors, in the order of `dynamic_batch`'s triangles.
    pub fn dynamic_vertices(&self, time: f32, previous_time: f32) -> Vec<Vertex> {
        let mut batch = MeshBatch::default();
        let (mut current, mut previous) = (Vec::new(), Vec::new());
        for character in &self.characters {
            current.clear();
            previous.clear();
            self.pose_character(character, time, &mut current);
            self.pose_character(character, previous_time, &mut previous);
            batch.append_vertices(&self.models[character.model], &current, &previous);
        }
        batch.vertices
    }
}
