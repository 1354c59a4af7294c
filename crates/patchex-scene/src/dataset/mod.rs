//! The dataset format (see the crate README): writing sequences, and reading them back.

mod exr_io;
mod frame;
mod layers;
mod manifest;
mod reader;
mod writer;

pub use exr_io::{read_exr, write_exr};
pub use frame::{FrameLayers, LayerImage};
pub use layers::*;
pub use manifest::{DynamicObject, FrameInfo, FrameRole, Manifest, SkyInfo, SunInfo};
pub use reader::Dataset;
pub use writer::{frame_time, render_sequence, SequenceOptions};
