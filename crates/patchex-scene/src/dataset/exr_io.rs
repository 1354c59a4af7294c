//! One frame as one single-part EXR whose channels are named "<Layer>.<Channel>", all f32,
//! the way Unreal's multi-layer exports are laid out.

use super::{FrameLayers, LayerImage};
use crate::error::{Error, Result};
use exr::prelude::*;
use std::path::Path;

pub fn write_exr(path: &Path, frame: &FrameLayers) -> Result<()> {
    let mut channels = SmallVec::<[AnyChannel<FlatSamples>; 4]>::new();
    for layer in &frame.layers {
        for (index, channel) in layer.channels.iter().enumerate() {
            let name = format!("{}.{}", layer.name, channel);
            channels.push(AnyChannel::new(
                name.as_str(),
                FlatSamples::F32(layer.plane(index)),
            ));
        }
    }
    let encoding = Encoding {
        compression: Compression::ZIP16,
        blocks: Blocks::ScanLines,
        // A fixed block order keeps the bytes identical from run to run.
        line_order: LineOrder::Increasing,
    };
    let layer = Layer::new(
        (frame.width, frame.height),
        LayerAttributes::default(),
        encoding,
        AnyChannels::sort(channels),
    );
    Image::from_layer(layer)
        .write()
        .to_file(path)
        .map_err(|e| Error::Exr {
            path: path.to_path_buf(),
            message: e.to_string(),
        })
}

/// A channel's suffix ("R") and its samples.
type NamedChannel = (String, Vec<f32>);

/// Reads every "<Layer>.<Channel>" group back into layers, channels in R, G, B, A order.
pub fn read_exr(path: &Path) -> Result<FrameLayers> {
    let fail = |message: String| Error::Exr {
        path: path.to_path_buf(),
        message,
    };
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .map_err(|e| fail(e.to_string()))?;
    let layer = &image.layer_data;
    let (width, height) = (layer.size.0, layer.size.1);
    let mut layers: Vec<LayerImage> = Vec::new();
    let mut grouped: Vec<(String, Vec<NamedChannel>)> = Vec::new();
    for channel in &layer.channel_data.list {
        let full_name = channel.name.to_string();
        let (layer_name, channel_name) = full_name
            .rsplit_once('.')
            .map(|(l, c)| (l.to_owned(), c.to_owned()))
            .unwrap_or_else(|| (String::new(), full_name.clone()));
        let samples: Vec<f32> = channel.sample_data.values_as_f32().collect();
        match grouped.iter_mut().find(|(name, _)| *name == layer_name) {
            Some((_, group)) => group.push((channel_name, samples)),
            None => grouped.push((layer_name, vec![(channel_name, samples)])),
        }
    }
    let order = |c: &str| {
        ["R", "G", "B", "A"]
            .iter()
            .position(|x| *x == c)
            .unwrap_or(4)
    };
    for (name, mut channels) in grouped {
        channels.sort_by(|a, b| order(&a.0).cmp(&order(&b.0)).then(a.0.cmp(&b.0)));
        let n = channels.len();
        let mut data = vec![0f32; width * height * n];
        for (c, (_, samples)) in channels.iter().enumerate() {
            if samples.len() != width * height {
                return Err(fail(format!(
                    "channel {name}.{} has the wrong size",
                    channels[c].0
                )));
            }
            for (pixel, &value) in samples.iter().enumerate() {
                data[pixel * n + c] = value;
            }
        }
        layers.push(LayerImage {
            name,
            channels: channels.into_iter().map(|(c, _)| c).collect(),
            width,
            height,
            data,
        });
    }
    // Present layers in the dataset's canonical order; unknown ones keep their file order at the end.
    let rank = |name: &str| {
        super::LAYERS
            .iter()
            .position(|spec| spec.name == name)
            .unwrap_or(usize::MAX)
    };
    layers.sort_by_key(|layer| rank(&layer.name));
    Ok(FrameLayers {
        width,
        height,
        layers,
    })
}
