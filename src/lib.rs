//! patchex: real-time frame extrapolation (PatchEX, Dixit and Sarangi 2024) for Vulkan engines.
//!
//! The C ABI lives in [`ffi`] and its types in [`abi`]; everything else is internal to the
//! plugin but public to the crate's own tests and tools.

pub mod abi;
pub mod camera;
pub mod context;
pub mod error;
pub mod ffi;
pub mod frame;
pub mod inputs;
pub mod loader;
pub mod network;
pub mod passes;
pub mod reference;
pub mod shaders;
pub mod spirv_options;
pub mod vk;
