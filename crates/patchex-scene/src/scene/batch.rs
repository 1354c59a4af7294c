//! World-space triangle batches as the GPU draws them: one vertex buffer, one index buffer and
//! a draw per (primitive, material).

use crate::asset::{Model, Pose, PosedVertex};
use bytemuck::{Pod, Zeroable};

/// Vertex layout of the G-buffer and shadow pipelines (see shaders/gbuffer.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct Vertex {
    pub position: [f32; 3],
    pub prev_position: [f32; 3],
    pub normal: [f32; 3],
    pub tangent: [f32; 4],
    pub uv: [f32; 2],
    pub color: [f32; 4],
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Draw {
    pub first_index: u32,
    pub index_count: u32,
    /// Index into the world's material table.
    pub material: u32,
    /// CustomStencil id written for these pixels; 0 for static geometry.
    pub stencil: u32,
}

#[derive(Default)]
pub struct MeshBatch {
    pub vertices: Vec<Vertex>,
    pub indices: Vec<u32>,
    pub draws: Vec<Draw>,
    /// Vertices the appended triangles refer to; equals `vertices.len()` once filled.
    pub vertex_count: u32,
}

impl MeshBatch {
    /// Appends the triangles of every mesh instance of `model`; the vertices themselves come
    /// from [`MeshBatch::append_vertices`], in the same order.
    pub fn append_triangles(
        &mut self,
        model: &Model,
        material_offset: u32,
        default_material: u32,
        stencil: u32,
    ) {
        let mut base_vertex = self.vertex_count;
        for (_, mesh_index) in Pose::mesh_instances(model) {
            for primitive in &model.meshes[mesh_index].primitives {
                let first_index = self.indices.len() as u32;
                self.indices
                    .extend(primitive.indices.iter().map(|&i| i + base_vertex));
                self.draws.push(Draw {
                    first_index,
                    index_count: primitive.indices.len() as u32,
                    material: primitive
                        .material
                        .map_or(default_material, |m| m as u32 + material_offset),
                    stencil,
                });
                base_vertex += primitive.positions.len() as u32;
            }
        }
        self.vertex_count = base_vertex;
    }

    /// Appends the vertices of `model` posed at the current (`current`) and previous
    /// (`previous`) instants, both produced by [`Pose::vertices`].
    pub fn append_vertices(
        &mut self,
        model: &Model,
        current: &[PosedVertex],
        previous: &[PosedVertex],
    ) {
        let attributes = Pose::mesh_instances(model)
            .into_iter()
            .flat_map(|(_, mesh_index)| {
                model.meshes[mesh_index]
                    .primitives
                    .iter()
                    .flat_map(|primitive| primitive.uvs.iter().zip(&primitive.colors))
            });
        for ((now, before), (uv, color)) in current.iter().zip(previous).zip(attributes) {
            self.vertices.push(Vertex {
                position: now.position.to_array(),
                prev_position: before.position.to_array(),
                normal: now.normal.to_array(),
                tangent: now.tangent.to_array(),
                uv: uv.to_array(),
                color: color.to_array(),
            });
        }
    }
}
