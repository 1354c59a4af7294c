//! Scene files (TOML) and the world they describe: environment, characters, camera and sun,
//! each evaluated at any instant.

mod batch;
mod camera;
mod camera_rig;
mod description;
mod glass;
mod ground;
mod ground_plane;
mod particles;
mod path;
mod placement;
mod projection;
mod sun;
pub mod variation;
mod wall;
mod world;

pub use batch::{Draw, MeshBatch, Vertex};
pub use camera::CameraState;
pub use description::{
    CameraDescription, CameraRig, CharacterDescription, GroundDescription, PropDescription,
    ScatterDescription, SceneDescription, ShakeDescription, SunDescription, TilesDescription,
};
pub use glass::GlassDescription;
pub use ground::GroundSurface;
pub use particles::{EmitterDescription, Particle};
pub use path::PathMotion;
pub use sun::SunLight;
pub use wall::{WallDescription, WindowsDescription};
pub use world::{Character, World};
