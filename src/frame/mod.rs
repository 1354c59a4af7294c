//! What each call records, read top to bottom: `submit` (frame t), `extrapolate` (one target
//! instant: its checks and allocation, then `plan`, its stages in order) and `stats` (what they
//! measured). The images, counters and settings they share sit beside them.

pub mod counters;
pub mod extrapolate;
pub mod images;
pub mod plan;
pub mod settings;
pub mod stats;
pub mod submit;
