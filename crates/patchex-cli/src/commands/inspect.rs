//! `patchex inspect ASSET`: what a glTF file holds, for writing scene files.

use super::CommandResult;
use clap::Args;
use glam::{Mat4, Vec3};
use patchex_scene::asset::{load_model, Pose};
use std::path::PathBuf;

#[derive(Args)]
pub struct InspectArgs {
    /// A .glb or .gltf file.
    asset: PathBuf,
}

pub fn run(args: InspectArgs) -> CommandResult {
    let model = load_model(&args.asset)?;
    let mut vertices = Vec::new();
    Pose::new(&model, Mat4::IDENTITY, None).vertices(&model, &mut vertices);
    let triangles: usize = Pose::mesh_instances(&model)
        .iter()
        .flat_map(|&(_, mesh)| &model.meshes[mesh].primitives)
        .map(|primitive| primitive.indices.len() / 3)
        .sum();
    let (lo, hi) = vertices.iter().fold((Vec3::MAX, Vec3::MIN), |(lo, hi), v| {
        (lo.min(v.position), hi.max(v.position))
    });
    println!("{}", args.asset.display());
    println!(
        "  nodes {}, meshes {}, skins {}, materials {}, textures {}",
        model.nodes.len(),
        model.meshes.len(),
        model.skins.len(),
        model.materials.len(),
        model.textures.len()
    );
    println!(
        "  rest pose: {} vertices, {triangles} triangles",
        vertices.len()
    );
    println!("  bounds: min {lo:.3}, max {hi:.3}");
    for clip in &model.animations {
        println!(
            "  clip {:?}: {:.2} s, {} channels",
            clip.name,
            clip.duration,
            clip.channels.len()
        );
    }
    Ok(())
}
