//! A minimal headless Vulkan engine, standing in for a game engine in patchex's tests and tools.
//! It owns its instance, device, queue, command buffers, fences and images, exactly the objects
//! patchex must borrow and never own. With validation on, the Khronos layer runs with
//! synchronization validation and every warning or error it reports is collected, so a test can
//! fail on any of them.

mod engine;
mod image;
pub mod intercept;
mod plugin;
pub mod texel;

pub use engine::{Engine, EngineOptions, FrameLoop, ThreadPool};
pub use image::{EngineImage, ImageRef};
