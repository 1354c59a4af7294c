//! A model posed at one instant: node world matrices from the hierarchy and an optional clip,
//! and the vertices of every mesh instance transformed (and skinned) on the CPU.

use super::animation::ChannelValue;
use super::{Model, Primitive};
use glam::{Mat3, Mat4, Vec3, Vec4};
use std::borrow::Cow;

/// Position, normal and tangent of one vertex in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PosedVertex {
    pub position: Vec3,
    pub normal: Vec3,
    /// w = handedness, 0 when the primitive has no tangents.
    pub tangent: Vec4,
}

pub struct Pose {
    /// Model-space matrix of each node; `None` for nodes outside the default scene.
    globals: Vec<Option<Mat4>>,
    /// Animated morph target weights per node; `None` keeps the node's or mesh's own.
    morph_weights: Vec<Option<Vec<f32>>>,
    root: Mat4,
}

impl Pose {
    /// Poses `model` under `root`, playing `clip` at `clip_time` (already looped) when given.
    pub fn new(model: &Model, root: Mat4, clip: Option<(usize, f32)>) -> Self {
        let mut nodes = model.nodes.clone();
        let mut morph_weights: Vec<Option<Vec<f32>>> =
            nodes.iter().map(|node| node.weights.clone()).collect();
        if let Some((clip_index, time)) = clip {
            for channel in &model.animations[clip_index].channels {
                let node = &mut nodes[channel.node];
                match channel.sample(time) {
                    ChannelValue::Translation(t) => node.translation = t,
                    ChannelValue::Rotation(r) => node.rotation = r,
                    ChannelValue::Scale(s) => node.scale = s,
                    ChannelValue::MorphWeights(w) => morph_weights[channel.node] = Some(w),
                }
            }
        }
        let mut globals = vec![None; nodes.len()];
        let mut stack: Vec<(usize, Mat4)> =
            model.roots.iter().map(|&r| (r, Mat4::IDENTITY)).collect();
        while let Some((index, parent)) = stack.pop() {
            let global = parent * nodes[index].local_matrix();
            globals[index] = Some(global);
            stack.extend(nodes[index].children.iter().map(|&child| (child, global)));
        }
        Self {
            globals,
            morph_weights,
            root,
        }
    }

    /// Mesh instances in a fixed order (node index, then primitive), shared by geometry
    /// building and posing so index buffers built once stay valid every frame.
    pub fn mesh_instances(model: &Model) -> Vec<(usize, usize)> {
        let pose = Pose::new(model, Mat4::IDENTITY, None);
        model
            .nodes
            .iter()
            .enumerate()
            .filter(|(index, node)| node.mesh.is_some() && pose.globals[*index].is_some())
            .map(|(index, node)| (index, node.mesh.expect("filtered on mesh")))
            .collect()
    }

    /// Appends the world-space vertices of every mesh instance, in [`Pose::mesh_instances`] order.
    pub fn vertices(&self, model: &Model, out: &mut Vec<PosedVertex>) {
        for (node_index, mesh_index) in Self::mesh_instances(model) {
            let node = &model.nodes[node_index];
            let joint_matrices = node.skin.map(|skin_index| {
                let skin = &model.skins[skin_index];
                skin.joints
                    .iter()
                    .zip(&skin.inverse_bind_matrices)
                    .map(|(&joint, inverse_bind)| {
                        self.root * self.globals[joint].unwrap_or(Mat4::IDENTITY) * *inverse_bind
                    })
                    .collect::<Vec<Mat4>>()
            });
            let node_world = self.root * self.globals[node_index].unwrap_or(Mat4::IDENTITY);
            let mesh = &model.meshes[mesh_index];
            let weights = self.morph_weights[node_index]
                .as_deref()
                .unwrap_or(&mesh.weights);
            for primitive in &mesh.primitives {
                let attributes = VertexAttributes::morphed(primitive, weights);
                match (&joint_matrices, &primitive.joints, &primitive.weights) {
                    (Some(matrices), Some(joints), Some(weights)) => {
                        let skin = SkinInputs {
                            joint_matrices: matrices,
                            joints,
                            weights,
                            unweighted: node_world,
                        };
                        skin_primitive(&attributes, &skin, out)
                    }
                    // glTF ignores a skinned node's own transform; rigid meshes use it.
                    _ => transform_primitive(&attributes, node_world, out),
                }
            }
        }
    }
}

fn normal_matrix(matrix: Mat4) -> Mat3 {
    Mat3::from_mat4(matrix).inverse().transpose()
}

/// A primitive's rest attributes with its morph targets applied.
struct VertexAttributes<'a> {
    positions: Cow<'a, [Vec3]>,
    normals: Cow<'a, [Vec3]>,
    tangents: Option<Cow<'a, [Vec4]>>,
}

impl<'a> VertexAttributes<'a> {
    fn morphed(primitive: &'a Primitive, weights: &[f32]) -> Self {
        let mut attributes = Self {
            positions: Cow::Borrowed(&primitive.positions),
            normals: Cow::Borrowed(&primitive.normals),
            tangents: primitive.tangents.as_deref().map(Cow::Borrowed),
        };
        for (target, &weight) in primitive.morph_targets.iter().zip(weights) {
            if weight == 0.0 {
                continue;
            }
            if let Some(deltas) = &target.positions {
                add_scaled(attributes.positions.to_mut(), deltas, weight);
            }
            if let Some(deltas) = &target.normals {
                add_scaled(attributes.normals.to_mut(), deltas, weight);
            }
            if let (Some(tangents), Some(deltas)) = (&mut attributes.tangents, &target.tangents) {
                // Tangent targets displace xyz; the handedness in w stays.
                for (tangent, delta) in tangents.to_mut().iter_mut().zip(deltas) {
                    *tangent += (*delta * weight).extend(0.0);
                }
            }
        }
        attributes
    }

    fn len(&self) -> usize {
        self.positions.len()
    }
}

fn add_scaled(values: &mut [Vec3], deltas: &[Vec3], weight: f32) {
    for (value, delta) in values.iter_mut().zip(deltas) {
        *value += *delta * weight;
    }
}

fn posed(
    attributes: &VertexAttributes<'_>,
    index: usize,
    matrix: Mat4,
    normals: Mat3,
) -> PosedVertex {
    let tangent = attributes.tangents.as_ref().map_or(Vec4::ZERO, |tangents| {
        let t = tangents[index];
        (Mat3::from_mat4(matrix) * t.truncate())
            .normalize_or_zero()
            .extend(t.w)
    });
    PosedVertex {
        position: matrix.transform_point3(attributes.positions[index]),
        normal: (normals * attributes.normals[index]).normalize_or_zero(),
        tangent,
    }
}

fn transform_primitive(attributes: &VertexAttributes<'_>, world: Mat4, out: &mut Vec<PosedVertex>) {
    let normals = normal_matrix(world);
    out.extend((0..attributes.len()).map(|i| posed(attributes, i, world, normals)));
}

struct SkinInputs<'a> {
    joint_matrices: &'a [Mat4],
    joints: &'a [[u16; 4]],
    weights: &'a [Vec4],
    /// Transform of vertices whose weights are all zero: the mesh node's own.
    unweighted: Mat4,
}

fn skin_primitive(
    attributes: &VertexAttributes<'_>,
    skin: &SkinInputs<'_>,
    out: &mut Vec<PosedVertex>,
) {
    for index in 0..attributes.len() {
        let weight = skin.weights[index];
        let blended = skin.joints[index]
            .iter()
            .zip(weight.to_array())
            .filter(|(_, w)| *w > 0.0)
            .fold(Mat4::ZERO, |sum, (&joint, w)| {
                sum + skin
                    .joint_matrices
                    .get(joint as usize)
                    .copied()
                    .unwrap_or(skin.unweighted)
                    * w
            });
        let total = weight.x + weight.y + weight.z + weight.w;
        let matrix = if total > 0.0 {
            blended * (1.0 / total)
        } else {
            skin.unweighted
        };
        out.push(posed(attributes, index, matrix, normal_matrix(matrix)));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::asset::{
        AnimationClip, Channel, Interpolation, Mesh, MorphTarget, Node, Property, Skin,
    };
    use glam::{Quat, Vec2};

    fn node(children: Vec<usize>, mesh: Option<usize>, skin: Option<usize>) -> Node {
        Node {
            name: String::new(),
            translation: Vec3::ZERO,
            rotation: Quat::IDENTITY,
            scale: Vec3::ONE,
            children,
            mesh,
            skin,
            weights: None,
        }
    }

    /// Two joints one metre apart along y; vertex 0 bound to joint 0, vertex 1 to joint 1.
    fn two_bone_model() -> Model {
        let mut joint1 = node(vec![], None, None);
        joint1.translation = Vec3::Y;
        let primitive = Primitive {
            positions: vec![Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0)],
            normals: vec![Vec3::X, Vec3::X],
            tangents: None,
            uvs: vec![Vec2::ZERO; 2],
            colors: vec![Vec4::ONE; 2],
            joints: Some(vec![[0, 0, 0, 0], [1, 0, 0, 0]]),
            weights: Some(vec![Vec4::X, Vec4::X]),
            indices: vec![],
            material: None,
            morph_targets: vec![MorphTarget {
                positions: Some(vec![Vec3::ZERO, Vec3::new(0.0, 0.0, 2.0)]),
                normals: None,
                tangents: None,
            }],
        };
        Model {
            name: "bones".into(),
            nodes: vec![
                node(vec![1], None, None),
                joint1,
                node(vec![], Some(0), Some(0)),
            ],
            roots: vec![0, 2],
            meshes: vec![Mesh {
                primitives: vec![primitive],
                weights: vec![0.0],
            }],
            skins: vec![Skin {
                joints: vec![0, 1],
                inverse_bind_matrices: vec![Mat4::IDENTITY, Mat4::from_translation(-Vec3::Y)],
            }],
            animations: vec![AnimationClip {
                name: "bend".into(),
                duration: 1.0,
                channels: vec![Channel {
                    node: 1,
                    property: Property::Rotation,
                    interpolation: Interpolation::Linear,
                    times: vec![0.0, 1.0],
                    width: 4,
                    values: [
                        Quat::IDENTITY,
                        Quat::from_rotation_z(std::f32::consts::FRAC_PI_2),
                    ]
                    .iter()
                    .flat_map(|q| q.to_array())
                    .collect(),
                }],
            }],
            materials: vec![],
            textures: vec![],
        }
    }

    #[test]
    fn bind_pose_reproduces_rest_positions_under_the_root() {
        let model = two_bone_model();
        let root = Mat4::from_translation(Vec3::new(10.0, 0.0, 0.0));
        let mut out = Vec::new();
        Pose::new(&model, root, None).vertices(&model, &mut out);
        assert!(out[0].position.abs_diff_eq(Vec3::new(10.0, 0.0, 0.0), 1e-6));
        assert!(out[1].position.abs_diff_eq(Vec3::new(10.0, 1.0, 0.0), 1e-6));
    }

    #[test]
    fn rotating_a_joint_moves_only_its_vertices_and_normals() {
        let model = two_bone_model();
        let mut out = Vec::new();
        Pose::new(&model, Mat4::IDENTITY, Some((0, 1.0))).vertices(&model, &mut out);
        // Vertex 1 sits at joint 1's origin, so rotation keeps its position but turns its normal.
        assert!(out[0].position.abs_diff_eq(Vec3::ZERO, 1e-6));
        assert!(out[0].normal.abs_diff_eq(Vec3::X, 1e-6));
        assert!(out[1].position.abs_diff_eq(Vec3::Y, 1e-6));
        assert!(out[1].normal.abs_diff_eq(Vec3::Y, 1e-6));
    }

    #[test]
    fn morph_weights_displace_vertices_before_skinning() {
        let mut model = two_bone_model();
        let mut out = Vec::new();
        Pose::new(&model, Mat4::IDENTITY, None).vertices(&model, &mut out);
        assert!(
            out[1].position.abs_diff_eq(Vec3::Y, 1e-6),
            "default weight 0 leaves the rest pose"
        );
        model.nodes[2].weights = Some(vec![0.5]);
        out.clear();
        Pose::new(&model, Mat4::IDENTITY, None).vertices(&model, &mut out);
        assert!(out[1].position.abs_diff_eq(Vec3::new(0.0, 1.0, 1.0), 1e-6));
    }
}
