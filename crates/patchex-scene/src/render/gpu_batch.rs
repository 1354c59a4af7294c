//! A [`MeshBatch`] in GPU buffers. Its draws are split by how they are drawn: opaque and
//! alpha-tested ones into the shadow maps and the G-buffer, blended ones in the forward pass.

use crate::asset::{AlphaMode, Material};
use crate::error::Result;
use crate::gpu::{Buffer, Gpu};
use crate::scene::{Draw, MeshBatch, Vertex};
use ash::vk;
use glam::Vec3;
use std::sync::Arc;

pub(crate) struct GpuBatch {
    pub vertices: Buffer,
    pub indices: Buffer,
    /// Draws into the shadow maps and the G-buffer.
    pub opaque: Vec<Draw>,
    /// Draws of blended materials, with the centre of their triangles' corners for sorting
    /// back to front (the origin for batches whose vertices come every frame).
    pub blended: Vec<(Draw, Vec3)>,
}

impl GpuBatch {
    /// Uploads `batch`'s triangles; vertices are uploaded now when present, or later by
    /// [`GpuBatch::write_vertices`] for batches re-posed every frame.
    pub fn new(gpu: &Arc<Gpu>, batch: &MeshBatch, materials: &[Material]) -> Result<Self> {
        let vertex_bytes = batch.vertex_count as u64 * std::mem::size_of::<Vertex>() as u64;
        let vertices = Buffer::new(
            gpu,
            vertex_bytes,
            vk::BufferUsageFlags::VERTEX_BUFFER,
            "vertices",
        )?;
        vertices.write(0, bytemuck::cast_slice(&batch.vertices));
        let indices = Buffer::with_data(
            gpu,
            bytemuck::cast_slice(&batch.indices),
            vk::BufferUsageFlags::INDEX_BUFFER,
            "indices",
        )?;
        let (blended, opaque): (Vec<Draw>, Vec<Draw>) = batch
            .draws
            .iter()
            .partition(|draw| materials[draw.material as usize].alpha_mode == AlphaMode::Blend);
        let centre = |draw: &Draw| {
            let corners = &batch.indices
                [draw.first_index as usize..(draw.first_index + draw.index_count) as usize];
            let sum: Vec3 = corners
                .iter()
                .filter_map(|&i| batch.vertices.get(i as usize))
                .map(|v| Vec3::from(v.position))
                .sum();
            sum / corners.len().max(1) as f32
        };
        Ok(Self {
            vertices,
            indices,
            opaque,
            blended: blended.iter().map(|d| (*d, centre(d))).collect(),
        })
    }

    pub fn write_vertices(&self, vertices: &[Vertex]) {
        self.vertices.write(0, bytemuck::cast_slice(vertices));
    }

    pub fn is_empty(&self) -> bool {
        self.opaque.is_empty() && self.blended.is_empty()
    }

    pub fn bind(&self, gpu: &Gpu, command_buffer: vk::CommandBuffer) {
        // SAFETY: recording; buffers are alive for as long as the batch.
        unsafe {
            gpu.device
                .cmd_bind_vertex_buffers(command_buffer, 0, &[self.vertices.handle], &[0]);
            gpu.device.cmd_bind_index_buffer(
                command_buffer,
                self.indices.handle,
                0,
                vk::IndexType::UINT32,
            );
        }
    }

    /// Binds the buffers and issues every opaque draw, calling `before_draw` first (for push
    /// constants).
    pub fn draw_opaque(
        &self,
        gpu: &Gpu,
        command_buffer: vk::CommandBuffer,
        mut before_draw: impl FnMut(&Draw),
    ) {
        if self.opaque.is_empty() {
            return;
        }
        self.bind(gpu, command_buffer);
        for draw in &self.opaque {
            before_draw(draw);
            draw_indexed(gpu, command_buffer, draw);
        }
    }
}

/// Issues `draw` from the batch bound last.
pub(crate) fn draw_indexed(gpu: &Gpu, command_buffer: vk::CommandBuffer, draw: &Draw) {
    // SAFETY: recording, with the draw's batch bound.
    unsafe {
        gpu.device
            .cmd_draw_indexed(command_buffer, draw.index_count, 1, draw.first_index, 0, 0);
    }
}
