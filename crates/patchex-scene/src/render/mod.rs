//! The deferred renderer: sun shadow maps, the G-buffer pass and the resolve (lighting and
//! layer output) pass, recorded into one command buffer per frame.

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
mod uniforms;

pub use renderer::{FrameRequest, Renderer};
pub use timings::PassTimings;
