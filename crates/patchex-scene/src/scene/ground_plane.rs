//! The scene format's built-in `[ground]`: a flat square for kits without ground of their own,
//! plain or paved with procedural tiles.

use super::placement::SplitMix64;
use super::{GroundDescription, TilesDescription};
use crate::asset::{AlphaMode, Material, Mesh, Model, Node, Primitive, TextureData, TextureRole};
use glam::{Quat, Vec2, Vec3, Vec4};

/// The tile textures hold TILES_PER_SIDE x TILES_PER_SIDE tiles of TILE_TEXELS texels a side and
/// repeat across the ground.
const TILES_PER_SIDE: usize = 4;
const TILE_TEXELS: usize = 64;
const TEXTURE_SIDE: usize = TILES_PER_SIDE * TILE_TEXELS;
/// A groove's half width and its bevel, in texels.
const GROOVE_HALF_WIDTH: f32 = 1.5;
const BEVEL: f32 = 5.0;
/// Pitting on the tiles' faces: value noise on a lattice this many texels apart.
const PIT_SPACING: usize = 4;
const PIT_DEPTH: f32 = 0.12;
/// How steep the height field's slopes read in the normal map.
const BUMP_STRENGTH: f32 = 1.5;
const GROOVE_ROUGHNESS: f32 = 0.95;

/// A flat square, as a one-primitive model.
pub(crate) fn ground_model(ground: &GroundDescription) -> Model {
    let h = ground.size * 0.5;
    let corners = [(-h, -h), (h, -h), (h, h), (-h, h)];
    // The tile textures repeat every TILES_PER_SIDE tiles.
    let uv_per_metre = ground
        .tiles
        .as_ref()
        .map_or(1.0, |tiles| 1.0 / (tiles.size * TILES_PER_SIDE as f32));
    let primitive = Primitive {
        positions: corners
            .iter()
            .map(|&(x, z)| Vec3::new(x, ground.height, z))
            .collect(),
        normals: vec![Vec3::Y; 4],
        tangents: None,
        uvs: corners
            .iter()
            .map(|&(x, z)| Vec2::new(x, z) * uv_per_metre)
            .collect(),
        colors: vec![Vec4::ONE; 4],
        joints: None,
        weights: None,
        // Counter-clockwise seen from above.
        indices: vec![0, 2, 1, 0, 3, 2],
        material: Some(0),
        morph_targets: Vec::new(),
    };
    let mut material = Material {
        base_color: Vec3::from(ground.base_color).extend(1.0),
        metallic: 0.0,
        roughness: ground.roughness,
        alpha_mode: AlphaMode::Opaque,
        ..Material::default()
    };
    let mut textures = Vec::new();
    if let Some(tiles) = &ground.tiles {
        let maps = TileMaps::new(tiles, ground.roughness);
        textures = vec![maps.color, maps.normal, maps.metallic_roughness];
        material.base_color_texture = Some(0);
        material.normal_texture = Some(1);
        material.metallic_roughness_texture = Some(2);
        // The texture holds the roughness itself.
        material.roughness = 1.0;
    }
    one_primitive_model("ground", primitive, material, textures)
}

/// A model of one node holding one primitive of one material.
pub(crate) fn one_primitive_model(
    name: &str,
    primitive: Primitive,
    material: Material,
    textures: Vec<TextureData>,
) -> Model {
    Model {
        name: name.into(),
        nodes: vec![Node {
            name: name.into(),
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
        materials: vec![material],
        textures,
    }
}

/// The tiles' base colour (a shade, tinted by the ground's colour), normal map and
/// metallic-roughness map, each TEXTURE_SIDE square and seamless when repeated.
struct TileMaps {
    color: TextureData,
    normal: TextureData,
    metallic_roughness: TextureData,
}

impl TileMaps {
    fn new(tiles: &TilesDescription, roughness: f32) -> Self {
        let mut rng = SplitMix64(0x7113);
        let tile_shades: Vec<f32> = (0..TILES_PER_SIDE * TILES_PER_SIDE)
            .map(|_| 1.0 + tiles.variation * (2.0 * rng.next_f32() - 1.0))
            .collect();
        let lattice = TEXTURE_SIDE / PIT_SPACING;
        let pits: Vec<f32> = (0..lattice * lattice).map(|_| rng.next_f32()).collect();
        let speckle: Vec<f32> = (0..TEXTURE_SIDE * TEXTURE_SIDE)
            .map(|_| rng.next_f32())
            .collect();

        let face = |x: usize, y: usize| {
            let edge = |c: usize| {
                let within = (c % TILE_TEXELS) as f32 + 0.5;
                within.min(TILE_TEXELS as f32 - within)
            };
            smoothstep(
                GROOVE_HALF_WIDTH,
                GROOVE_HALF_WIDTH + BEVEL,
                edge(x).min(edge(y)),
            )
        };
        let height = |x: usize, y: usize| {
            let pit = value_noise(
                &pits,
                lattice,
                x as f32 / PIT_SPACING as f32,
                y as f32 / PIT_SPACING as f32,
            );
            face(x, y) * (1.0 - PIT_DEPTH * pit)
        };
        let wrap = |c: isize| c.rem_euclid(TEXTURE_SIDE as isize) as usize;

        let (mut color, mut normal, mut metallic_roughness) = (Vec::new(), Vec::new(), Vec::new());
        for y in 0..TEXTURE_SIDE {
            for x in 0..TEXTURE_SIDE {
                let (xi, yi) = (x as isize, y as isize);
                let slope_x = height(wrap(xi + 1), y) - height(wrap(xi - 1), y);
                let slope_y = height(x, wrap(yi + 1)) - height(x, wrap(yi - 1));
                let n = Vec3::new(-slope_x, -slope_y, 2.0 / BUMP_STRENGTH).normalize();
                normal.extend([
                    unorm8(n.x * 0.5 + 0.5),
                    unorm8(n.y * 0.5 + 0.5),
                    unorm8(n.z * 0.5 + 0.5),
                    255,
                ]);

                let tile = (y / TILE_TEXELS) * TILES_PER_SIDE + x / TILE_TEXELS;
                let on_face = face(x, y);
                let grain = speckle[y * TEXTURE_SIDE + x] - 0.5;
                let shade =
                    0.8 * tile_shades[tile] * (0.55 + 0.45 * on_face) * (1.0 + 0.12 * grain);
                let encoded = unorm8(linear_to_srgb(shade.clamp(0.0, 1.0)));
                color.extend([encoded, encoded, encoded, 255]);

                let face_roughness = roughness * (1.0 + 0.4 * grain);
                let r = GROOVE_ROUGHNESS + (face_roughness - GROOVE_ROUGHNESS) * on_face;
                // glTF: roughness in green, metalness (none) in blue.
                metallic_roughness.extend([0, unorm8(r.clamp(0.03, 1.0)), 0, 255]);
            }
        }
        let side = TEXTURE_SIDE as u32;
        Self {
            color: TextureData::from_rgba8(side, side, color, TextureRole::Color),
            normal: TextureData::from_rgba8(side, side, normal, TextureRole::Data),
            metallic_roughness: TextureData::from_rgba8(
                side,
                side,
                metallic_roughness,
                TextureRole::Data,
            ),
        }
    }
}

/// Smooth value noise over a wrapping `lattice` x `lattice` grid of values.
fn value_noise(values: &[f32], lattice: usize, x: f32, y: f32) -> f32 {
    let (x0, y0) = (x.floor() as usize, y.floor() as usize);
    let (fx, fy) = (
        smoothstep(0.0, 1.0, x.fract()),
        smoothstep(0.0, 1.0, y.fract()),
    );
    let at = |i: usize, j: usize| values[(j % lattice) * lattice + i % lattice];
    let top = at(x0, y0) + (at(x0 + 1, y0) - at(x0, y0)) * fx;
    let bottom = at(x0, y0 + 1) + (at(x0 + 1, y0 + 1) - at(x0, y0 + 1)) * fx;
    top + (bottom - top) * fy
}

fn smoothstep(edge0: f32, edge1: f32, x: f32) -> f32 {
    let t = ((x - edge0) / (edge1 - edge0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

fn unorm8(value: f32) -> u8 {
    (value.clamp(0.0, 1.0) * 255.0).round() as u8
}

fn linear_to_srgb(value: f32) -> f32 {
    if value <= 0.003_130_8 {
        value * 12.92
    } else {
        1.055 * value.powf(1.0 / 2.4) - 0.055
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ground(tiles: Option<TilesDescription>) -> GroundDescription {
        GroundDescription {
            size: 10.0,
            height: 0.0,
            base_color: [0.5, 0.5, 0.5],
            roughness: 0.3,
            tiles,
        }
    }

    #[test]
    fn a_plain_ground_has_no_textures() {
        let model = ground_model(&ground(None));
        assert!(model.textures.is_empty());
        assert_eq!(model.materials[0].roughness, 0.3);
    }

    #[test]
    fn tiles_repeat_seamlessly_with_darker_rougher_grooves() {
        let model = ground_model(&ground(Some(TilesDescription {
            size: 0.5,
            variation: 0.25,
        })));
        let [color, normal, metallic_roughness] = &model.textures[..] else {
            panic!("three tile maps");
        };
        let texel = |map: &TextureData, x: usize, y: usize, c: usize| {
            map.mips[0][(y * TEXTURE_SIDE + x) * 4 + c]
        };
        // A groove runs along each tile's edge, so also along the texture's: the maps wrap.
        let (groove, face) = (0, TILE_TEXELS / 2);
        assert!(texel(color, groove, face, 0) < texel(color, face, face, 0));
        assert!(
            texel(metallic_roughness, groove, face, 1) > texel(metallic_roughness, face, face, 1)
        );
        // The bevel tilts the normal towards the groove's middle, on both of its sides.
        let bevel = (GROOVE_HALF_WIDTH + BEVEL / 2.0) as usize;
        let tilt = |x| texel(normal, x, face, 0) as i32 - 128;
        assert!(
            tilt(bevel) < 0 && tilt(TEXTURE_SIDE - bevel) > 0,
            "{} {}",
            tilt(bevel),
            tilt(TEXTURE_SIDE - bevel)
        );
        // The material defers its roughness to the map.
        assert_eq!(model.materials[0].roughness, 1.0);
    }
}
