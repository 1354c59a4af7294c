//! Plain-Rust versions of every GPU pass: the oracle the tests compare the shaders against.
//! Each function mirrors its shader line for line, takes the same generated `Params`, and
//! rounds where the GPU stores to a 16-bit float image.

pub mod demodulate;
pub mod gbuffer;
pub mod lbp;
pub mod pack_gbuffer;
pub mod remodulate;
pub mod segmentation;
pub mod warp;

/// One instant's inputs, as plain images: the reference side of what an engine submits.
pub struct FrameInputs<'a> {
    pub color: Option<&'a Image>,
    pub base_color: &'a Image,
    pub material: Option<&'a Image>,
    pub depth: &'a Image,
    pub normal: &'a Image,
    pub stencil: Option<&'a Image>,
    pub motion: Option<&'a Image>,
    pub camera: &'a crate::camera::Camera,
    pub normal_encoding: u32,
    pub motion_vector_scale: [f32; 2],
}

/// Every intermediate result of one extrapolation.
pub struct Extrapolation {
    /// The engine's output image.
    pub output: Image,
    pub warped: warp::Warped,
    pub segmented: segmentation::Segmented,
    pub lbp: Image,
    /// Pixels of frame t and of the target whose inputs (or result) were sanitised.
    pub source_sanitized: u32,
    pub target_sanitized: u32,
}

/// The whole extrapolation, pass by pass, as the plugin records it.
pub fn extrapolate(
    source: &FrameInputs,
    target: &FrameInputs,
    warp: &crate::passes::warp::WarpSettings,
    segmentation: &crate::passes::segmentation::SegmentationSettings,
) -> Extrapolation {
    use crate::passes::pack_gbuffer::params as pack_params;
    let extent = ash::vk::Extent2D {
        width: source.base_color.width as u32,
        height: source.base_color.height as u32,
    };
    let pack = |frame: &FrameInputs| {
        let params = pack_params(
            frame.camera,
            extent,
            frame.normal_encoding,
            frame.stencil.is_some(),
        );
        pack_gbuffer::pack_gbuffer(frame.depth, frame.normal, frame.stencil, &params)
    };
    let (shading, source_sanitized) = demodulate::demodulate(
        source.color.expect("frame t has colour"),
        source.base_color,
        source.material,
    );
    let (source_packed, target_packed) = (pack(source), pack(target));
    let jitter_delta = (target.camera.jitter - source.camera.jitter).into();
    let params = warp.params(
        extent,
        target.camera,
        jitter_delta,
        target.motion_vector_scale,
    );
    let motion = target.motion.expect("the target has motion vectors");
    let warped = warp::warp(
        warp.kind,
        &warp::WarpSources {
            shading: &shading,
            geometry: &source_packed.geometry,
            normal_id: &source_packed.normal_id,
        },
        &warp::WarpTarget {
            geometry: &target_packed.geometry,
            normal_id: &target_packed.normal_id,
            motion,
        },
        &params,
    );
    let segmented = segmentation::segment(
        &target_packed.normal_id,
        motion,
        target.motion_vector_scale,
        segmentation.growth,
    );
    let lbp = lbp::lbp(&warped.warped);
    let (output, target_sanitized) =
        remodulate::remodulate(&warped.warped, target.base_color, target.material);
    Extrapolation {
        output,
        warped,
        segmented,
        lbp,
        source_sanitized,
        target_sanitized,
    }
}

/// A float image in row-major order with interleaved channels.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    pub width: usize,
    pub height: usize,
    pub channels: usize,
    pub data: Vec<f32>,
}

impl Image {
    pub fn new(width: usize, height: usize, channels: usize) -> Self {
        Self {
            width,
            height,
            channels,
            data: vec![0.0; width * height * channels],
        }
    }

    pub fn from_fn(
        width: usize,
        height: usize,
        channels: usize,
        mut f: impl FnMut(usize, usize) -> Vec<f32>,
    ) -> Self {
        let mut image = Self::new(width, height, channels);
        for y in 0..height {
            for x in 0..width {
                image.set(x, y, &f(x, y));
            }
        }
        image
    }

    pub fn at(&self, x: usize, y: usize) -> &[f32] {
        let start = (y * self.width + x) * self.channels;
        &self.data[start..start + self.channels]
    }

    /// Texel at signed coordinates clamped to the image, as the shaders clamp.
    pub fn clamped(&self, x: i32, y: i32) -> &[f32] {
        let x = x.clamp(0, self.width as i32 - 1) as usize;
        let y = y.clamp(0, self.height as i32 - 1) as usize;
        self.at(x, y)
    }

    pub fn set(&mut self, x: usize, y: usize, value: &[f32]) {
        let start = (y * self.width + x) * self.channels;
        self.data[start..start + self.channels].copy_from_slice(&value[..self.channels]);
    }
}

/// What storing to a 16-bit float image does to a value.
pub fn round_to_f16(value: f32) -> f32 {
    half::f16::from_f32(value).to_f32()
}
