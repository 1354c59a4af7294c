//! What each call records, read top to bottom: `submit` (frame t) and `extrapolate` (one
//! target instant) check and allocate, then record the stages `plan` lists; `stats` reads what
//! they measured. The images, counters and settings they share sit beside them.

pub mod counters;
pub mod extrapolate;
pub mod images;
pub mod plan;
pub mod settings;
pub mod stats;
pub mod submit;
