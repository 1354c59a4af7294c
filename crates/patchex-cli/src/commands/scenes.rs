//! `patchex scenes --seed N --out DIR`: writes the generated scene set
//! (`patchex_scene::variation`) as scene files, and `split.toml` naming each split's scenes.

use super::{write_output, CommandResult};
use clap::Args;
use patchex_scene::scene::variation::{generate_set, Split};
use std::path::PathBuf;

#[derive(Args)]
pub struct ScenesArgs {
    /// The set's seed: the same seed always writes the same files.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Output folder for the scene files and split.toml.
    #[arg(long, default_value = "scenes/generated")]
    out: PathBuf,
}

pub fn run(args: ScenesArgs) -> CommandResult {
    let scenes = generate_set(args.seed);
    for scene in &scenes {
        write_output(&args.out.join(format!("{}.toml", scene.name)), &scene.text)?;
    }
    let mut split = format!(
        "# The generated set's splits (`patchex scenes --seed {}`): train on training, decide on\n\
         # validation, report on test.\n",
        args.seed
    );
    for which in [Split::Training, Split::Validation, Split::Test] {
        let names: Vec<String> = scenes
            .iter()
            .filter(|s| s.split == which)
            .map(|s| format!("\"{}\"", s.name))
            .collect();
        split += &format!("{} = [{}]\n", which.name(), names.join(", "));
    }
    write_output(&args.out.join("split.toml"), split)?;
    println!("{} scenes -> {}", scenes.len(), args.out.display());
    Ok(())
}
