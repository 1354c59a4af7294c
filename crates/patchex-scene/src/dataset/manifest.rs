//! manifest.json: resolution, timing, camera matrices and roles of every frame.

use serde::{Deserialize, Serialize};

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FrameRole {
    /// Even frames: what the engine renders in full.
    Rendered,
    /// Odd frames: the instants to extrapolate; rendered in full as ground truth.
    Target,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FrameInfo {
    pub index: usize,
    pub time: f32,
    pub role: FrameRole,
    /// World to view, column-major.
    pub view: [f32; 16],
    /// View to Vulkan clip space (y down, depth 0..1), column-major.
    pub proj: [f32; 16],
    /// proj * view, column-major.
    pub view_proj: [f32; 16],
    pub camera_position: [f32; 3],
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DynamicObject {
    pub stencil: u32,
    pub name: String,
    pub asset: String,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    pub scene: String,
    pub width: usize,
    pub height: usize,
    /// Frame rate of this (doubled) stream.
    pub fps: f32,
    pub near: f32,
    pub far: f32,
    pub frames: Vec<FrameInfo>,
    pub dynamic_objects: Vec<DynamicObject>,
    pub layers: Vec<String>,
}

impl FrameInfo {
    pub fn view_matrix(&self) -> glam::Mat4 {
        glam::Mat4::from_cols_array(&self.view)
    }

    pub fn proj_matrix(&self) -> glam::Mat4 {
        glam::Mat4::from_cols_array(&self.proj)
    }

    pub fn view_proj_matrix(&self) -> glam::Mat4 {
        glam::Mat4::from_cols_array(&self.view_proj)
    }
}
