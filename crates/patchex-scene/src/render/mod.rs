//! The deferred renderer: sun shadow maps, the G-buffer pass, the forward pass of blended
//! surfaces and the resolve (lighting and layer output) pass, recorded into one command buffer
//! per frame; the host then draws the particles and composites the translucent layer.

mod forward_pass;
mod gbuffer_pass;
mod gpu_batch;
mod materials;
mod particle_pass;
mod pipelines;
pub mod post;
mod renderer;
mod resolve_pass;
mod shadow_pass;
mod targets;
mod timings;
mod translucent_layer;
mod uniforms;

pub use renderer::{FrameRequest, Renderer};
pub use timings::PassTimings;
