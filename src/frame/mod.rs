//! What each call records, read top to bottom: `submit` (frame t), `extrapolate` (one target
//! instant) and `stats` (what they measured). The images, counters and settings they share sit
//! beside them.

pub mod counters;
pub mod extrapolate;
pub mod images;
pub mod settings;
pub mod stats;
pub mod submit;
