pub mod bench;
pub mod calibrate;
pub mod demo;
pub mod eval;
pub mod inspect;
pub mod interpolate;
pub mod metrics;
pub mod patches;
pub mod picture;
pub mod plugin_driver;
pub mod render;
pub mod sheet;

/// Errors of any subcommand, shown to the user as one line.
pub type CommandResult = Result<(), Box<dyn std::error::Error>>;
