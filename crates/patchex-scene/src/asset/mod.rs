//! glTF 2.0 content: loading into plain data, animation sampling and CPU posing/skinning.

mod animation;
mod loader;
mod model;
mod pose;
mod texture;

pub use animation::{AnimationClip, Channel, ChannelValue, Interpolation, Property};
pub use loader::load_model;
pub use model::{AlphaMode, Material, Mesh, Model, MorphTarget, Node, Primitive, Skin};
pub use pose::{Pose, PosedVertex};
pub use texture::{TextureData, TextureRole};
