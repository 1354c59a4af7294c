//! SPIR-V compiled from `shaders/*.wgsl` by build.rs.

pub(crate) const GBUFFER: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/gbuffer.spv"));
pub(crate) const SHADOW: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/shadow.spv"));
pub(crate) const RESOLVE: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/resolve.spv"));
pub(crate) const FORWARD: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/forward.spv"));
