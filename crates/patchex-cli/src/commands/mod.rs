pub mod inspect;
pub mod render;
pub mod sheet;

/// Errors of any subcommand, shown to the user as one line.
pub type CommandResult = Result<(), Box<dyn std::error::Error>>;
