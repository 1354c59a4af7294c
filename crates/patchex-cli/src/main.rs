//! `patchex`: the project's command line tool. Each subcommand lives in its own module under
//! `commands/`; add one by adding a variant here and a module there.

mod commands;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser)]
#[command(name = "patchex", version, about = "PatchEX frame extrapolation tools")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// The main job: render a scene, extrapolate every target instant through the plugin,
    /// and write picture strips and a quality/GPU-time table.
    Demo(commands::demo::DemoArgs),
    /// Measure the speed-against-accuracy trade: every configuration on the test scenes at
    /// 360p to 1080p; writes a table of quality against GPU time per stage and a plot.
    Bench(commands::bench::BenchArgs),
    /// Check this machine's GPU and driver: every configuration against the plain-Rust
    /// reference on frames it renders, under validation where installed; exit code 0 on pass.
    Selftest(commands::selftest::SelftestArgs),
    /// Fit k_x and k_y of the near-background growth (Algorithm 1) from temporal-variation
    /// analysis of datasets, and print the correlation of extension with motion.
    Calibrate(commands::calibrate::CalibrateArgs),
    /// Score every method against the rendered ground truth of datasets: PSNR, SSIM and FLIP
    /// over the frame, holes, FI and near-BE, and GPU time; writes tables and picture strips.
    Eval(commands::eval::EvalArgs),
    /// Write the inpainting networks' training patches from datasets (for training/train.py).
    Patches(commands::patches::PatchesArgs),
    /// Render a scene file into a G-buffer dataset sequence.
    Render(commands::render::RenderArgs),
    /// Write the generated scene set: seeded variations of settings, characters, cameras and
    /// sun, split into training, validation and test scenes.
    Scenes(commands::scenes::ScenesArgs),
    /// Make a contact sheet PNG of one dataset frame: colour and every G-buffer layer.
    Sheet(commands::sheet::SheetArgs),
    /// Print what a glTF asset contains: meshes, bounds, animation clips.
    Inspect(commands::inspect::InspectArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Demo(args) => commands::demo::run(args),
        Command::Bench(args) => commands::bench::run(args),
        Command::Selftest(args) => commands::selftest::run(args),
        Command::Calibrate(args) => commands::calibrate::run(args),
        Command::Eval(args) => commands::eval::run(args),
        Command::Patches(args) => commands::patches::run(args),
        Command::Render(args) => commands::render::run(args),
        Command::Scenes(args) => commands::scenes::run(args),
        Command::Sheet(args) => commands::sheet::run(args),
        Command::Inspect(args) => commands::inspect::run(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("error: {error}");
            ExitCode::FAILURE
        }
    }
}
