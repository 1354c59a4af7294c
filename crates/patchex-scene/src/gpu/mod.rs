//! Thin helpers over `ash`: device creation with optional validation, memory, one-shot
//! command submission and the embedded SPIR-V.

mod commands;
mod context;
mod memory;
pub(crate) mod shaders;
mod validation;

pub(crate) use commands::{image_barrier, ImageTransition};
pub use context::{Gpu, GpuOptions};
pub(crate) use memory::{Buffer, Image, ImageDesc};
