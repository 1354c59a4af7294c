//! Renders a scene into a sequence folder: `frame_NNNN.exr` per frame plus `manifest.json`.

use super::reader::frame_file_name;
use super::{
    write_exr, DynamicObject, FrameInfo, FrameRole, Manifest, SkyInfo, SunInfo, LAYERS,
    MOTION_VECTOR, TRANSLUCENCY_LAYERS,
};
use crate::error::{io_error, Result};
use crate::gpu::Gpu;
use crate::render::{FrameRequest, Renderer};
use crate::scene::World;
use std::path::PathBuf;
use std::sync::Arc;

pub struct SequenceOptions {
    pub frames: usize,
    /// Target instants between two rendered frames: 1 for 2x frame generation (alpha 1/2), 2
    /// for 3x (alpha 1/3 and 2/3), and so on.
    pub targets_between: usize,
    pub width: u32,
    pub height: u32,
    pub out_dir: PathBuf,
}

/// Scene time of frame `index`: frames follow the scene's (doubled) frame rate.
pub fn frame_time(world: &World, index: usize) -> f32 {
    stream_time(world, index, 1)
}

/// Scene time of frame `index` of a stream with `targets_between` targets between rendered
/// frames: rendered frames keep the scene's rendered rate (half its doubled `fps`).
pub fn stream_time(world: &World, index: usize, targets_between: usize) -> f32 {
    let rendered_interval = 2.0 / world.description.fps;
    world.description.start_time + index as f32 * rendered_interval / (targets_between + 1) as f32
}

/// Renders every frame fully lit (targets too, as ground truth) and writes the sequence.
/// `progress` is called with (frames done, frames total) after each frame.
pub fn render_sequence(
    gpu: &Arc<Gpu>,
    world: &World,
    options: &SequenceOptions,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Manifest> {
    std::fs::create_dir_all(&options.out_dir).map_err(io_error(&options.out_dir))?;
    let mut renderer = Renderer::new(gpu, world, options.width, options.height)?;
    let aspect = options.width as f32 / options.height as f32;
    let mut frames = Vec::with_capacity(options.frames);
    let stride = options.targets_between.max(1) + 1;
    let time_of = |index| stream_time(world, index, stride - 1);
    for index in 0..options.frames {
        let time = time_of(index);
        // A target's motion vectors point to the rendered frame it is extrapolated from; a
        // rendered frame's to the frame before it. Frame 0 has no predecessor: it reuses its own
        // instant, so its motion is zero.
        let previous_time = match index % stride {
            0 => time_of(index.saturating_sub(1)),
            offset => time_of(index - offset),
        };
        let request = FrameRequest::at(world, time, previous_time, aspect, true);
        let mut layers = renderer.render(world, &request)?;
        if index == 0 {
            // Re-projecting onto the same instant leaves float noise; the contract says zero.
            if let Some(motion) = layers.get_mut(MOTION_VECTOR) {
                motion.data.fill(0.0);
            }
        }
        write_exr(&options.out_dir.join(frame_file_name(index)), &layers)?;
        let camera = &request.camera;
        frames.push(FrameInfo {
            index,
            time,
            role: if index % stride == 0 {
                FrameRole::Rendered
            } else {
                FrameRole::Target
            },
            view: camera.view.to_cols_array(),
            proj: camera.proj.to_cols_array(),
            view_proj: camera.view_proj().to_cols_array(),
            camera_position: camera.position.to_array(),
        });
        progress(index + 1, options.frames);
    }
    let lens = &world.description.camera;
    let manifest = Manifest {
        scene: world.description.name.clone(),
        width: options.width as usize,
        height: options.height as usize,
        fps: world.description.fps,
        targets_between: stride - 1,
        near: lens.near,
        far: lens.far,
        frames,
        dynamic_objects: world
            .characters
            .iter()
            .map(|character| DynamicObject {
                stencil: character.stencil,
                name: character.description.name.clone(),
                asset: character.description.asset.clone(),
            })
            .collect(),
        layers: LAYERS
            .iter()
            .map(|layer| layer.name)
            .chain(
                TRANSLUCENCY_LAYERS
                    .iter()
                    .copied()
                    .filter(|_| world.draws_translucency()),
            )
            .map(str::to_owned)
            .collect(),
        sun: Some(SunInfo {
            direction: world.sun.direction.to_array(),
            illuminance: world.sun.radiance.to_array(),
        }),
        sky: Some(SkyInfo {
            zenith: world.description.sun.sky_zenith,
            horizon: world.description.sun.sky_horizon,
        }),
    };
    let manifest_path = options.out_dir.join("manifest.json");
    let json = serde_json::to_string_pretty(&manifest).expect("the manifest is plain data");
    std::fs::write(&manifest_path, json + "\n").map_err(io_error(&manifest_path))?;
    Ok(manifest)
}
