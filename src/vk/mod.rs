//! Vulkan on the engine's terms: its device through its own function pointers, its images
//! borrowed per call, and the plugin's own resources.

pub mod access;
pub mod barriers;
pub mod buffer;
pub mod device;
pub mod frame_ring;
pub mod image;
pub mod pipeline;
pub mod recorder;
pub mod timestamps;
