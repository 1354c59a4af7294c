//! A [`MeshBatch`] in GPU buffers, drawable by the shadow and G-buffer passes.

use crate::error::Result;
use crate::gpu::{Buffer, Gpu};
use crate::scene::{Draw, MeshBatch, Vertex};
use ash::vk;
use std::sync::Arc;

pub(crate) struct GpuBatch {
    pub vertices: Buffer,
    pub indices: Buffer,
    pub draws: Vec<Draw>,
}

impl GpuBatch {
    /// Uploads `batch`'s triangles; vertices are uploaded now when present, or later by
    /// [`GpuBatch::write_vertices`] for batches re-posed every frame.
    pub fn new(gpu: &Arc<Gpu>, batch: &MeshBatch) -> Result<Self> {
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
        Ok(Self {
            vertices,
            indices,
            draws: batch.draws.clone(),
        })
    }

    pub fn write_vertices(&self, vertices: &[Vertex]) {
        self.vertices.write(0, bytemuck::cast_slice(vertices));
    }

    pub fn is_empty(&self) -> bool {
        self.draws.is_empty()
    }

    /// Binds the buffers and issues every draw, calling `before_draw` first (for push constants).
    pub fn draw(
        &self,
        gpu: &Gpu,
        command_buffer: vk::CommandBuffer,
        mut before_draw: impl FnMut(&Draw),
    ) {
        if self.is_empty() {
            return;
        }
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
            for draw in &self.draws {
                before_draw(draw);
                gpu.device.cmd_draw_indexed(
                    command_buffer,
                    draw.index_count,
                    1,
                    draw.first_index,
                    0,
                    0,
                );
            }
        }
    }
}
