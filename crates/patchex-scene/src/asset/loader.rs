//! Reads a .glb/.gltf file with the `gltf` crate into a [`Model`].

use super::animation::{AnimationClip, Channel, Interpolation, Property};
use super::{
    AlphaMode, Material, Mesh, Model, MorphTarget, Node, Primitive, Skin, TextureData, TextureRole,
};
use crate::error::{Error, Result};
use glam::{Mat4, Quat, Vec2, Vec3, Vec4};
use gltf::image::Format;
use std::collections::HashMap;
use std::path::Path;

pub fn load_model(path: &Path) -> Result<Model> {
    let fail = |message: String| Error::Gltf {
        path: path.to_path_buf(),
        message,
    };
    let (document, buffers, images) = gltf::import(path).map_err(|e| fail(e.to_string()))?;
    let buffer_data = |buffer: gltf::Buffer<'_>| Some(&buffers[buffer.index()].0[..]);

    let nodes = document
        .nodes()
        .map(|node| {
            let (translation, rotation, scale) = node.transform().decomposed();
            Node {
                name: node.name().unwrap_or_default().to_owned(),
                translation: Vec3::from(translation),
                rotation: Quat::from_array(rotation).normalize(),
                scale: Vec3::from(scale),
                children: node.children().map(|child| child.index()).collect(),
                mesh: node.mesh().map(|mesh| mesh.index()),
                skin: node.skin().map(|skin| skin.index()),
                weights: node.weights().map(<[f32]>::to_vec),
            }
        })
        .collect();
    let scene = document
        .default_scene()
        .or_else(|| document.scenes().next())
        .ok_or_else(|| fail("the file has no scene".into()))?;
    let roots = scene.nodes().map(|node| node.index()).collect();

    let mut textures = TextureTable::new(&images);
    let materials = document
        .materials()
        .map(|material| read_material(&material, &mut textures))
        .collect();
    let meshes = document
        .meshes()
        .map(|mesh| {
            let primitives = mesh
                .primitives()
                .filter(|primitive| primitive.mode() == gltf::mesh::Mode::Triangles)
                .filter_map(|primitive| read_primitive(&primitive, buffer_data))
                .collect();
            Mesh {
                primitives,
                weights: mesh.weights().map(<[f32]>::to_vec).unwrap_or_default(),
            }
        })
        .collect();
    let skins = document
        .skins()
        .map(|skin| {
            let joints: Vec<usize> = skin.joints().map(|joint| joint.index()).collect();
            let inverse_bind_matrices = skin
                .reader(buffer_data)
                .read_inverse_bind_matrices()
                .map(|matrices| matrices.map(|m| Mat4::from_cols_array_2d(&m)).collect())
                .unwrap_or_else(|| vec![Mat4::IDENTITY; joints.len()]);
            Skin {
                joints,
                inverse_bind_matrices,
            }
        })
        .collect();
    let animations = document
        .animations()
        .enumerate()
        .map(|(index, animation)| read_animation(&animation, index, buffer_data))
        .collect();

    Ok(Model {
        name: path
            .file_stem()
            .map(|stem| stem.to_string_lossy().into_owned())
            .unwrap_or_default(),
        nodes,
        roots,
        meshes,
        skins,
        animations,
        materials,
        textures: textures.textures,
    })
}

/// Converts each (image, role) pair once, so an image used as both colour and data gets the
/// right decoding for each use.
struct TextureTable<'a> {
    images: &'a [gltf::image::Data],
    by_key: HashMap<(usize, TextureRole), usize>,
    textures: Vec<TextureData>,
}

impl<'a> TextureTable<'a> {
    fn new(images: &'a [gltf::image::Data]) -> Self {
        Self {
            images,
            by_key: HashMap::new(),
            textures: Vec::new(),
        }
    }

    fn get(&mut self, texture: gltf::Texture<'_>, role: TextureRole) -> usize {
        let image_index = texture.source().index();
        if let Some(&index) = self.by_key.get(&(image_index, role)) {
            return index;
        }
        let image = &self.images[image_index];
        let rgba = to_rgba8(image);
        self.textures.push(TextureData::from_rgba8(
            image.width,
            image.height,
            rgba,
            role,
        ));
        let index = self.textures.len() - 1;
        self.by_key.insert((image_index, role), index);
        index
    }
}

fn to_rgba8(image: &gltf::image::Data) -> Vec<u8> {
    let p = &image.pixels;
    let u16_to_u8 = |lo: u8, hi: u8| (u16::from_le_bytes([lo, hi]) >> 8) as u8;
    let f32_to_u8 = |b: &[u8]| {
        let value = f32::from_le_bytes([b[0], b[1], b[2], b[3]]);
        (value.clamp(0.0, 1.0) * 255.0 + 0.5) as u8
    };
    match image.format {
        Format::R8G8B8A8 => p.clone(),
        Format::R8G8B8 => p
            .chunks_exact(3)
            .flat_map(|c| [c[0], c[1], c[2], 255])
            .collect(),
        Format::R8G8 => p
            .chunks_exact(2)
            .flat_map(|c| [c[0], c[1], 0, 255])
            .collect(),
        Format::R8 => p.iter().flat_map(|&v| [v, v, v, 255]).collect(),
        Format::R16 => p
            .chunks_exact(2)
            .flat_map(|c| {
                let v = u16_to_u8(c[0], c[1]);
                [v, v, v, 255]
            })
            .collect(),
        Format::R16G16 => p
            .chunks_exact(4)
            .flat_map(|c| [u16_to_u8(c[0], c[1]), u16_to_u8(c[2], c[3]), 0, 255])
            .collect(),
        Format::R16G16B16 => p
            .chunks_exact(6)
            .flat_map(|c| {
                [
                    u16_to_u8(c[0], c[1]),
                    u16_to_u8(c[2], c[3]),
                    u16_to_u8(c[4], c[5]),
                    255,
                ]
            })
            .collect(),
        Format::R16G16B16A16 => p.chunks_exact(2).map(|c| u16_to_u8(c[0], c[1])).collect(),
        Format::R32G32B32FLOAT => p
            .chunks_exact(12)
            .flat_map(|c| {
                [
                    f32_to_u8(&c[0..4]),
                    f32_to_u8(&c[4..8]),
                    f32_to_u8(&c[8..12]),
                    255,
                ]
            })
            .collect(),
        Format::R32G32B32A32FLOAT => p.chunks_exact(4).map(f32_to_u8).collect(),
    }
}

fn read_material(material: &gltf::Material<'_>, textures: &mut TextureTable<'_>) -> Material {
    let pbr = material.pbr_metallic_roughness();
    let alpha_mode = match material.alpha_mode() {
        gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
        gltf::material::AlphaMode::Mask => AlphaMode::Mask(material.alpha_cutoff().unwrap_or(0.5)),
        gltf::material::AlphaMode::Blend => AlphaMode::Blend,
    };
    Material {
        base_color: Vec4::from(pbr.base_color_factor()),
        base_color_texture: pbr
            .base_color_texture()
            .map(|info| textures.get(info.texture(), TextureRole::Color)),
        metallic: pbr.metallic_factor(),
        roughness: pbr.roughness_factor(),
        metallic_roughness_texture: pbr
            .metallic_roughness_texture()
            .map(|info| textures.get(info.texture(), TextureRole::Data)),
        normal_texture: material
            .normal_texture()
            .map(|info| textures.get(info.texture(), TextureRole::Data)),
        normal_scale: material.normal_texture().map_or(1.0, |info| info.scale()),
        emissive: Vec3::from(material.emissive_factor())
            * material.emissive_strength().unwrap_or(1.0),
        emissive_texture: material
            .emissive_texture()
            .map(|info| textures.get(info.texture(), TextureRole::Color)),
        alpha_mode,
        specular: 0.5,
    }
}

fn read_primitive<'a, 's>(
    primitive: &'a gltf::Primitive<'a>,
    buffer_data: impl Clone + Fn(gltf::Buffer<'a>) -> Option<&'s [u8]>,
) -> Option<Primitive> {
    let reader = primitive.reader(buffer_data);
    let positions: Vec<Vec3> = reader.read_positions()?.map(Vec3::from).collect();
    let count = positions.len();
    let indices: Vec<u32> = match reader.read_indices() {
        Some(indices) => indices.into_u32().collect(),
        None => (0..count as u32).collect(),
    };
    let normals = match reader.read_normals() {
        Some(normals) => normals.map(Vec3::from).collect(),
        None => smooth_normals(&positions, &indices),
    };
    let morph_targets = reader
        .read_morph_targets()
        .map(|(positions, normals, tangents)| MorphTarget {
            positions: positions.map(|p| p.map(Vec3::from).collect()),
            normals: normals.map(|n| n.map(Vec3::from).collect()),
            tangents: tangents.map(|t| t.map(Vec3::from).collect()),
        })
        .collect();
    Some(Primitive {
        morph_targets,
        normals,
        tangents: reader
            .read_tangents()
            .map(|tangents| tangents.map(Vec4::from).collect()),
        uvs: reader
            .read_tex_coords(0)
            .map(|uvs| uvs.into_f32().map(Vec2::from).collect())
            .unwrap_or_else(|| vec![Vec2::ZERO; count]),
        colors: reader
            .read_colors(0)
            .map(|colors| colors.into_rgba_f32().map(Vec4::from).collect())
            .unwrap_or_else(|| vec![Vec4::ONE; count]),
        joints: reader
            .read_joints(0)
            .map(|joints| joints.into_u16().collect()),
        weights: reader
            .read_weights(0)
            .map(|weights| weights.into_f32().map(Vec4::from).collect()),
        positions,
        indices,
        material: primitive.material().index(),
    })
}

/// Area-weighted vertex normals for primitives that ship without any.
fn smooth_normals(positions: &[Vec3], indices: &[u32]) -> Vec<Vec3> {
    let mut normals = vec![Vec3::ZERO; positions.len()];
    for triangle in indices.chunks_exact(3) {
        let [a, b, c] = [triangle[0], triangle[1], triangle[2]].map(|i| i as usize);
        let face = (positions[b] - positions[a]).cross(positions[c] - positions[a]);
        for vertex in [a, b, c] {
            normals[vertex] += face;
        }
    }
    normals
        .into_iter()
        .map(|n| n.try_normalize().unwrap_or(Vec3::Y))
        .collect()
}

fn read_animation<'a, 's>(
    animation: &gltf::Animation<'a>,
    index: usize,
    buffer_data: impl Clone + Fn(gltf::Buffer<'a>) -> Option<&'s [u8]>,
) -> AnimationClip {
    use gltf::animation::util::ReadOutputs;
    let mut channels = Vec::new();
    for channel in animation.channels() {
        let reader = channel.reader(buffer_data.clone());
        let (Some(inputs), Some(outputs)) = (reader.read_inputs(), reader.read_outputs()) else {
            continue;
        };
        let times: Vec<f32> = inputs.collect();
        if times.is_empty() {
            continue;
        }
        let interpolation = match channel.sampler().interpolation() {
            gltf::animation::Interpolation::Step => Interpolation::Step,
            gltf::animation::Interpolation::Linear => Interpolation::Linear,
            gltf::animation::Interpolation::CubicSpline => Interpolation::CubicSpline,
        };
        let (property, values): (Property, Vec<f32>) = match outputs {
            ReadOutputs::Translations(t) => (Property::Translation, t.flatten().collect()),
            ReadOutputs::Scales(s) => (Property::Scale, s.flatten().collect()),
            ReadOutputs::Rotations(r) => (Property::Rotation, r.into_f32().flatten().collect()),
            ReadOutputs::MorphTargetWeights(w) => (Property::MorphWeights, w.into_f32().collect()),
        };
        let values_per_key = if interpolation == Interpolation::CubicSpline {
            3
        } else {
            1
        };
        let width = values.len() / (times.len() * values_per_key);
        if width == 0 || width * times.len() * values_per_key != values.len() {
            continue;
        }
        channels.push(Channel {
            node: channel.target().node().index(),
            property,
            interpolation,
            times,
            width,
            values,
        });
    }
    let duration = channels
        .iter()
        .filter_map(|channel| channel.times.last().copied())
        .fold(0.0f32, f32::max);
    AnimationClip {
        name: animation
            .name()
            .map(str::to_owned)
            .unwrap_or_else(|| format!("animation{index}")),
        duration,
        channels,
    }
}
