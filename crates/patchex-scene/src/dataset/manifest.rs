//! manifest.json: resolution, timing, camera matrices and roles of every frame.

use serde::{Deserialize, Serialize};

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FrameRole {
    /// Every (targets_between + 1)-th frame from 0: what the engine renders in full.
    Rendered,
    /// The frames between: the instants to extrapolate; rendered in full as ground truth.
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
    /// The scene's doubled frame rate: rendered frames come at fps / 2.
    pub fps: f32,
    /// Target instants between two rendered frames (frames of the stream are
    /// 2 / (fps * (targets_between + 1)) s apart). Older manifests have 1.
    #[serde(default = "one_target_between")]
    pub targets_between: usize,
    pub near: f32,
    pub far: f32,
    pub frames: Vec<FrameInfo>,
    pub dynamic_objects: Vec<DynamicObject>,
    pub layers: Vec<String>,
    /// The sun that lit every frame; older manifests have none.
    #[serde(default)]
    pub sun: Option<SunInfo>,
    /// The sky that lit every frame; older manifests have none.
    #[serde(default)]
    pub sky: Option<SkyInfo>,
}

/// The scene's sun, as an engine gives it to `PatchexSunLight`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SunInfo {
    /// Unit, world space, from a surface towards the sun.
    pub direction: [f32; 3],
    /// Colour times intensity: a white Lambertian surface facing the sun shows this over pi.
    pub illuminance: [f32; 3],
}

/// The scene's sky: radiance blended from the horizon's (at and below it) to the zenith's by
/// the square root of the direction's height (y up), as the renderer lights with it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SkyInfo {
    pub zenith: [f32; 3],
    pub horizon: [f32; 3],
}

impl SkyInfo {
    /// The sky's radiance towards unit `direction`.
    pub fn radiance(&self, direction: glam::Vec3) -> glam::Vec3 {
        let up = direction.y.clamp(0.0, 1.0).sqrt();
        glam::Vec3::from(self.horizon).lerp(glam::Vec3::from(self.zenith), up)
    }

    /// The sky as an engine gives it to `PatchexSkyLight`: an octahedral map of `side` texels
    /// a side, RGBA, row by row.
    pub fn octahedral_map(&self, side: usize) -> Vec<f32> {
        let mut map = Vec::with_capacity(side * side * 4);
        for j in 0..side {
            for i in 0..side {
                let [x, y] = [i, j].map(|k| 2.0 * (k as f32 + 0.5) / side as f32 - 1.0);
                let z = 1.0 - x.abs() - y.abs();
                let (x, y) = if z < 0.0 {
                    ((1.0 - y.abs()) * x.signum(), (1.0 - x.abs()) * y.signum())
                } else {
                    (x, y)
                };
                let radiance = self.radiance(glam::Vec3::new(x, y, z).normalize());
                map.extend_from_slice(&radiance.extend(1.0).to_array());
            }
        }
        map
    }
}

fn one_target_between() -> usize {
    1
}

impl Manifest {
    /// The rendered frame a target is extrapolated from, and its alpha.
    pub fn source_of(&self, target: usize) -> (usize, f32) {
        let stride = self.targets_between + 1;
        let offset = target % stride;
        (target - offset, offset as f32 / stride as f32)
    }
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
