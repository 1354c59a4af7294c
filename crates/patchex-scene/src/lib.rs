//! patchex-scene: a small headless deferred renderer on Vulkan (ash) that turns glTF scenes
//! into G-buffer sequences for frame extrapolation, and reads those sequences back.
//!
//! The pipeline per frame: characters are posed and skinned on the CPU (current and previous
//! instant), a sun shadow map of the characters is drawn (the static one is drawn once), the
//! G-buffer pass rasterizes world-space geometry, and a compute pass lights it and writes the
//! dataset layers. See README.md for the dataset contract.

pub mod asset;
pub mod dataset;
mod error;
pub mod gpu;
pub mod render;
pub mod scene;

pub use dataset::{Dataset, FrameLayers, LayerImage, Manifest};
pub use error::{Error, Result};
pub use gpu::{Gpu, GpuOptions};
pub use render::{FrameRequest, Renderer};
pub use scene::World;
