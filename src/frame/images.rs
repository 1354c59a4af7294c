//! The plugin's own images: what each set holds, in which format, and how a set grows with the
//! frame and retires its old images once no frame in flight can use them.

use ash::vk;
use gpu_allocator::vulkan::Allocator;

use crate::error::{bail, Result};
use crate::passes::{shadow_flow, CounterRange, Texture};
use crate::vk::device::Gpu;
use crate::vk::frame_ring::FrameRing;
use crate::vk::image::OwnedImage;

/// One image of an `ImageSet`.
struct ImageSpec {
    name: &'static str,
    format: vk::Format,
    /// Sized for a pyramid atlas (`shadow_flow::atlas_extent`) rather than the frame.
    atlas: bool,
    /// Cleared with vkCmdClearColorImage.
    cleared: bool,
    /// Copied into an engine image.
    copied_out: bool,
}

const fn frame_image(name: &'static str, format: vk::Format) -> ImageSpec {
    ImageSpec {
        name,
        format,
        atlas: false,
        cleared: false,
        copied_out: false,
    }
}

const fn atlas_image(name: &'static str, format: vk::Format) -> ImageSpec {
    ImageSpec {
        name,
        format,
        atlas: true,
        cleared: false,
        copied_out: false,
    }
}

/// Images made, grown and freed together, for frames up to `extent`.
/// `Kind` tells apart sets of one size, each with its own image indices.
pub struct ImageSet<const N: usize, Kind = ()> {
    pub extent: vk::Extent2D,
    pub images: [OwnedImage; N],
    kind: std::marker::PhantomData<Kind>,
}

impl<const N: usize, Kind> ImageSet<N, Kind> {
    /// Vulkan requires storage-image support for every format used here, but a device that
    /// lacks it must be refused at creation rather than fail later.
    fn check_formats(gpu: &Gpu, specs: &[ImageSpec; N]) -> Result<()> {
        let needed = vk::FormatFeatureFlags::STORAGE_IMAGE | vk::FormatFeatureFlags::SAMPLED_IMAGE;
        for spec in specs {
            let features = gpu.format_features(spec.format);
            if !features.contains(needed) {
                bail!(
                    ErrorMissingDeviceFeature,
                    "the device lacks {:?} for {:?}, the format of the {} image",
                    needed & !features,
                    spec.format,
                    spec.name
                );
            }
        }
        Ok(())
    }

    fn new(
        gpu: &Gpu,
        allocator: &mut Allocator,
        extent: vk::Extent2D,
        specs: &[ImageSpec; N],
    ) -> Result<Self> {
        let mut made: Vec<OwnedImage> = Vec::with_capacity(N);
        for spec in specs {
            let mut usage = vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::STORAGE;
            if spec.cleared {
                usage |= vk::ImageUsageFlags::TRANSFER_DST;
            }
            if spec.copied_out {
                usage |= vk::ImageUsageFlags::TRANSFER_SRC;
            }
            let size = if spec.atlas {
                shadow_flow::atlas_extent(extent)
            } else {
                extent
            };
            match OwnedImage::new(gpu, allocator, spec.name, spec.format, size, usage) {
                Ok(image) => made.push(image),
                Err(error) => {
                    for mut image in made {
                        image.destroy(gpu, allocator);
                    }
                    return Err(error);
                }
            }
        }
        let Ok(images) = made.try_into() else {
            unreachable!("one image per spec")
        };
        Ok(Self {
            extent,
            images,
            kind: std::marker::PhantomData,
        })
    }

    fn holds(&self, extent: vk::Extent2D) -> bool {
        self.extent.width >= extent.width && self.extent.height >= extent.height
    }

    fn size_bytes(&self) -> u64 {
        self.images.iter().map(|image| image.size_bytes()).sum()
    }
}

impl<const N: usize, Kind> std::ops::Index<usize> for ImageSet<N, Kind> {
    type Output = OwnedImage;
    fn index(&self, index: usize) -> &OwnedImage {
        &self.images[index]
    }
}

/// The plugin's working images, all at one extent (the largest frame seen so far): what frame t
/// leaves for its extrapolations. The warps read the target's G-buffer from the engine's images,
/// and write their shading into the frame image itself (the engine's output, or the output
/// staging's frame), where the later passes refine it in place, so no image holds either.
pub type WorkImages = ImageSet<4>;

impl WorkImages {
    /// Frame t's shading, in the output's own format: the extrapolated frame holds no more.
    pub const SOURCE_SHADING: usize = 0;
    /// Frame t's packed G-buffer (`pack_gbuffer`): linear depth, and normal with id.
    pub const SOURCE_DEPTH: usize = 1;
    pub const SOURCE_NORMAL_ID: usize = 2;
    /// The holes the G-buffer warp leaves to the fill (`warp::HoleList`); the shadow layer's
    /// warp lists its own there after the frame's fill.
    pub const HOLE_LIST: usize = 3;

    const SPECS: [ImageSpec; 4] = [
        frame_image("patchex source shading", vk::Format::R16G16B16A16_SFLOAT),
        frame_image("patchex source depth", vk::Format::R32_SFLOAT),
        frame_image("patchex source normal+id", vk::Format::R32_UINT),
        frame_image("patchex hole list", vk::Format::R32_UINT),
    ];
}

/// What the networks and the diagnostics read besides the frame, made at the first
/// extrapolation that runs either: a frame without them needs no region image.
pub type AnalysisImages = ImageSet<1, Analysis>;
pub struct Analysis;

impl AnalysisImages {
    /// Region of each target pixel (segmentation::REGION_*).
    pub const REGIONS: usize = 0;

    const SPECS: [ImageSpec; 1] = [frame_image("patchex regions", vk::Format::R32_UINT)];
}

/// What only the diagnostics show, made at the first extrapolation that asks for them.
pub type DiagnosticImages = ImageSet<1, Diagnostics>;
pub struct Diagnostics;

impl DiagnosticImages {
    /// The warped frame's LBP code / 255 (the networks make theirs as they gather).
    pub const LBP: usize = 0;

    const SPECS: [ImageSpec; 1] = [frame_image("patchex lbp", vk::Format::R16_SFLOAT)];
}

/// For an output whose format a shader cannot store (`PACKED_OUTPUT_FORMATS`): the extrapolated
/// frame, and its texels packed in the output's format for the copy. Made at the first such
/// output.
pub type OutputStaging = ImageSet<2>;

impl OutputStaging {
    pub const FRAME: usize = 0;
    pub const PACKED: usize = 1;

    const SPECS: [ImageSpec; 2] = [
        frame_image("patchex output frame", vk::Format::R16G16B16A16_SFLOAT),
        ImageSpec {
            copied_out: true,
            ..frame_image("patchex packed output", vk::Format::R32_UINT)
        },
    ];
}

/// The shadow sub-task's images, made at the first frame with a shadow input.
pub type ShadowImages = ImageSet<2, Shadows>;
pub struct Shadows;

impl ShadowImages {
    /// The share of light frame t's dynamic shadows take away, with their darkness in alpha.
    pub const LAYER: usize = 0;
    /// The layer as its flow moved it, which the frame's warp of the layer then turns into the
    /// shadows' share at the target: moved where the flow found a receiver, carried elsewhere.
    /// Cleared when there was no flow to move it by (frame t-1's shadows were not tracked).
    pub const SHADOW_SHARE: usize = 1;

    const SPECS: [ImageSpec; 2] = [
        // Shading, as the frame's: RGBA16F.
        frame_image("patchex shadow layer", vk::Format::R16G16B16A16_SFLOAT),
        ImageSpec {
            cleared: true,
            ..frame_image("patchex shadow share", vk::Format::R16G16B16A16_SFLOAT)
        },
    ];
}

/// What the sun's highlights need between the submit and the extrapolations, made at the first
/// frame with a sun.
pub type HighlightImages = ImageSet<1, Highlights>;
pub struct Highlights;

impl HighlightImages {
    /// Frame t's visibility of the sun, which the target's highlights read where the motion
    /// vectors say each pixel was.
    pub const VISIBILITY: usize = 0;

    const SPECS: [ImageSpec; 1] = [frame_image(
        "patchex sun visibility",
        vk::Format::R16_SFLOAT,
    )];
}

/// The sky's map (`PatchexSkyLight.radiance`), its mips side by side, kept from the submit for
/// the extrapolations' reflections; made at the first frame with a sky, at the largest map's
/// size.
pub type SkyImages = ImageSet<1, Sky>;
pub struct Sky;

impl SkyImages {
    pub const RADIANCE: usize = 0;

    const SPECS: [ImageSpec; 1] = [frame_image(
        "patchex sky radiance",
        vk::Format::R16G16B16A16_SFLOAT,
    )];
}

/// What frame t's translucency needs between the submit and the extrapolations, made at the
/// first frame with a translucency input.
pub type TranslucencyImages = ImageSet<2, Translucency>;
pub struct Translucency;

impl TranslucencyImages {
    /// What is drawn over the surfaces: premultiplied colour, and its coverage in alpha.
    pub const LAYER: usize = 0;
    /// Its own motion in pixels, zero where it has none.
    pub const MOTION: usize = 1;

    const SPECS: [ImageSpec; 2] = [
        frame_image(
            "patchex translucency layer",
            vk::Format::R16G16B16A16_SFLOAT,
        ),
        frame_image("patchex translucency motion", vk::Format::R16G16_SFLOAT),
    ];
}

/// The shadow flow's pyramid atlases, made at the first frame whose flow runs: a context whose
/// flow is off never holds them.
pub type FlowAtlases = ImageSet<7, Flow>;
pub struct Flow;

impl FlowAtlases {
    pub const MASK_PYRAMID: usize = 0;
    /// Frame t's and frame t-1's expansions, alternating (`Context::shadow_current`).
    pub const POLY: [usize; 2] = [1, 2];
    pub const POLY_XY: [usize; 2] = [3, 4];
    /// Each iteration's estimate and result, alternating (`shadow_flow::FlowImages`); the
    /// first holds the flow when it is done (`shadow_flow::FrameFlow`).
    pub const FLOW_PYRAMID: [usize; 2] = [5, 6];

    const SPECS: [ImageSpec; 7] = [
        atlas_image("patchex shadow mask pyramid", vk::Format::R32_SFLOAT),
        atlas_image(
            "patchex shadow expansion A",
            vk::Format::R32G32B32A32_SFLOAT,
        ),
        atlas_image(
            "patchex shadow expansion B",
            vk::Format::R32G32B32A32_SFLOAT,
        ),
        atlas_image("patchex shadow expansion xy A", vk::Format::R32_SFLOAT),
        atlas_image("patchex shadow expansion xy B", vk::Format::R32_SFLOAT),
        atlas_image("patchex shadow flow pyramid A", vk::Format::R32G32_SFLOAT),
        atlas_image("patchex shadow flow pyramid B", vk::Format::R32G32_SFLOAT),
    ];

    /// What the flow reads and writes: these atlases and frame t's `frame` mask, with the
    /// expansion's constants in `expansion` and `unread` bound where a pass reads nothing.
    pub fn flow_images<'a>(
        &'a self,
        current: usize,
        frame: shadow_flow::FrameMask<'a>,
        expansion: CounterRange,
        unread: Texture,
    ) -> shadow_flow::FlowImages<'a> {
        shadow_flow::FlowImages {
            frame,
            mask_pyramid: &self[Self::MASK_PYRAMID],
            poly: Self::POLY.map(|index| &self[index]),
            poly_xy: Self::POLY_XY.map(|index| &self[index]),
            current,
            flow_pyramid: Self::FLOW_PYRAMID.map(|index| &self[index]),
            mask_step: shadow_flow::mask_step(self.extent),
            expansion,
            unread,
        }
    }

    /// The flow the last submit measured for a frame of `extent`.
    pub fn frame_flow(&self, extent: vk::Extent2D) -> shadow_flow::FrameFlow<'_> {
        let atlas = &self[Self::FLOW_PYRAMID[0]];
        shadow_flow::FrameFlow::of(atlas, shadow_flow::mask_step(self.extent), extent)
    }
}

/// Every image the context owns besides the networks' tensors. Each set is made at the first
/// frame that needs it and grows with the frame.
pub struct FrameImages {
    pub work: Option<WorkImages>,
    pub analysis: Option<AnalysisImages>,
    pub diagnostics: Option<DiagnosticImages>,
    /// Made at the first frame with a shadow input.
    pub shadows: Option<ShadowImages>,
    /// Made at the first frame whose shadow flow runs.
    pub flow: Option<FlowAtlases>,
    /// Made at the first frame with a sun or a sky.
    pub highlights: Option<HighlightImages>,
    /// Made at the first frame with a sky.
    pub sky: Option<SkyImages>,
    /// Made at the first frame with a translucency input.
    pub translucency: Option<TranslucencyImages>,
    pub output_staging: Option<OutputStaging>,
    /// 1x1 images bound where an optional input is absent; the shaders never read them.
    placeholder_float: OwnedImage,
    placeholder_uint: OwnedImage,
}

impl FrameImages {
    /// Refuses a device that cannot store or sample a working format.
    pub fn check_formats(gpu: &Gpu) -> Result<()> {
        WorkImages::check_formats(gpu, &WorkImages::SPECS)?;
        AnalysisImages::check_formats(gpu, &AnalysisImages::SPECS)?;
        DiagnosticImages::check_formats(gpu, &DiagnosticImages::SPECS)?;
        OutputStaging::check_formats(gpu, &OutputStaging::SPECS)?;
        ShadowImages::check_formats(gpu, &ShadowImages::SPECS)?;
        FlowAtlases::check_formats(gpu, &FlowAtlases::SPECS)?;
        HighlightImages::check_formats(gpu, &HighlightImages::SPECS)?;
        TranslucencyImages::check_formats(gpu, &TranslucencyImages::SPECS)
    }

    /// The placeholders; every other set waits for its first frame.
    pub fn new(gpu: &Gpu, allocator: &mut Allocator) -> Result<Self> {
        let one = vk::Extent2D {
            width: 1,
            height: 1,
        };
        let sampled = vk::ImageUsageFlags::SAMPLED;
        let float = OwnedImage::new(
            gpu,
            allocator,
            "patchex placeholder",
            vk::Format::R16G16B16A16_SFLOAT,
            one,
            sampled,
        )?;
        // Also bound for a storage image its pass skips (the regions without analysis images).
        let uint = OwnedImage::new(
            gpu,
            allocator,
            "patchex placeholder uint",
            vk::Format::R32_UINT,
            one,
            sampled | vk::ImageUsageFlags::STORAGE,
        );
        let uint = match uint {
            Ok(uint) => uint,
            Err(error) => {
                let mut float = float;
                float.destroy(gpu, allocator);
                return Err(error);
            }
        };
        Ok(Self {
            work: None,
            analysis: None,
            diagnostics: None,
            shadows: None,
            flow: None,
            highlights: None,
            sky: None,
            translucency: None,
            output_staging: None,
            placeholder_float: float,
            placeholder_uint: uint,
        })
    }

    /// Grows the working images to hold `extent`; the old ones wait out the frames in flight.
    pub fn ensure_work(&mut self, growth: &mut Growth, extent: vk::Extent2D) -> Result<()> {
        grow(growth, &mut self.work, extent, &WorkImages::SPECS).map(drop)
    }

    /// Makes or grows the shadow images to the working images' extent. Returns whether they
    /// were (re)made, which loses frame t-1's expansion.
    pub fn ensure_shadows(&mut self, growth: &mut Growth) -> Result<bool> {
        let extent = self.work_extent();
        grow(growth, &mut self.shadows, extent, &ShadowImages::SPECS)
    }

    /// Makes or grows the flow's atlases to the working images' extent. Returns whether they
    /// were (re)made, which loses frame t-1's expansion.
    pub fn ensure_flow(&mut self, growth: &mut Growth) -> Result<bool> {
        let extent = self.work_extent();
        grow(growth, &mut self.flow, extent, &FlowAtlases::SPECS)
    }

    /// Makes or grows the highlights' images to the working images' extent.
    pub fn ensure_highlights(&mut self, growth: &mut Growth) -> Result<()> {
        let extent = self.work_extent();
        grow(
            growth,
            &mut self.highlights,
            extent,
            &HighlightImages::SPECS,
        )
        .map(drop)
    }

    /// Makes or grows the kept sky map to hold `extent` (its mips side by side).
    pub fn ensure_sky(&mut self, growth: &mut Growth, extent: vk::Extent2D) -> Result<()> {
        grow(growth, &mut self.sky, extent, &SkyImages::SPECS).map(drop)
    }

    /// Makes or grows the translucency's images to the working images' extent.
    pub fn ensure_translucency(&mut self, growth: &mut Growth) -> Result<()> {
        let extent = self.work_extent();
        grow(
            growth,
            &mut self.translucency,
            extent,
            &TranslucencyImages::SPECS,
        )
        .map(drop)
    }

    /// Makes or grows the analysis images to the working images' extent.
    pub fn ensure_analysis(&mut self, growth: &mut Growth) -> Result<()> {
        let extent = self.work_extent();
        grow(growth, &mut self.analysis, extent, &AnalysisImages::SPECS).map(drop)
    }

    /// Makes or grows the diagnostics' images to the working images' extent.
    pub fn ensure_diagnostics(&mut self, growth: &mut Growth) -> Result<()> {
        let extent = self.work_extent();
        grow(
            growth,
            &mut self.diagnostics,
            extent,
            &DiagnosticImages::SPECS,
        )
        .map(drop)
    }

    /// Makes or grows the output staging to the working images' extent.
    pub fn ensure_output_staging(&mut self, growth: &mut Growth) -> Result<()> {
        let extent = self.work_extent();
        grow(
            growth,
            &mut self.output_staging,
            extent,
            &OutputStaging::SPECS,
        )
        .map(drop)
    }

    /// The other sets follow the working images, which the submit makes first.
    fn work_extent(&self) -> vk::Extent2D {
        self.work.as_ref().expect("made by the submit").extent
    }

    /// The placeholders for a float and an unsigned-integer texture.
    pub fn placeholders(&self) -> (Texture, Texture) {
        // Never read, so they move no bytes.
        let unread = |image: &OwnedImage| Texture {
            bytes: 0,
            ..image.into()
        };
        (
            unread(&self.placeholder_float),
            unread(&self.placeholder_uint),
        )
    }

    /// The images a submit uses, for their first layout transition.
    pub fn submit_images(&mut self) -> impl Iterator<Item = &mut OwnedImage> {
        let work = self.work.iter_mut().flat_map(|w| w.images.iter_mut());
        let shadows = self.shadows.iter_mut().flat_map(|s| s.images.iter_mut());
        let flow = self.flow.iter_mut().flat_map(|f| f.images.iter_mut());
        let highlights = self.highlights.iter_mut().flat_map(|h| h.images.iter_mut());
        let sky = self.sky.iter_mut().flat_map(|s| s.images.iter_mut());
        let translucency = self
            .translucency
            .iter_mut()
            .flat_map(|t| t.images.iter_mut());
        work.chain(shadows)
            .chain(flow)
            .chain(highlights)
            .chain(sky)
            .chain(translucency)
            .chain([&mut self.placeholder_float, &mut self.placeholder_uint])
    }

    pub fn size_bytes(&self) -> u64 {
        self.work.as_ref().map_or(0, |w| w.size_bytes())
            + self.analysis.as_ref().map_or(0, |a| a.size_bytes())
            + self.diagnostics.as_ref().map_or(0, |d| d.size_bytes())
            + self.shadows.as_ref().map_or(0, |s| s.size_bytes())
            + self.flow.as_ref().map_or(0, |f| f.size_bytes())
            + self.highlights.as_ref().map_or(0, |h| h.size_bytes())
            + self.sky.as_ref().map_or(0, |s| s.size_bytes())
            + self.translucency.as_ref().map_or(0, |t| t.size_bytes())
            + self.output_staging.as_ref().map_or(0, |s| s.size_bytes())
            + self.placeholder_float.size_bytes()
            + self.placeholder_uint.size_bytes()
    }

    pub fn destroy(&mut self, gpu: &Gpu, allocator: &mut Allocator) {
        let work = self.work.take().map(|w| w.images);
        let analysis = self.analysis.take().map(|a| a.images);
        let diagnostics = self.diagnostics.take().map(|d| d.images);
        let shadows = self.shadows.take().map(|s| s.images);
        let flow = self.flow.take().map(|f| f.images);
        let highlights = self.highlights.take().map(|h| h.images);
        let sky = self.sky.take().map(|s| s.images);
        let translucency = self.translucency.take().map(|t| t.images);
        let staging = self.output_staging.take().map(|s| s.images);
        for mut image in work
            .into_iter()
            .flatten()
            .chain(analysis.into_iter().flatten())
            .chain(diagnostics.into_iter().flatten())
            .chain(shadows.into_iter().flatten())
            .chain(flow.into_iter().flatten())
            .chain(highlights.into_iter().flatten())
            .chain(sky.into_iter().flatten())
            .chain(translucency.into_iter().flatten())
            .chain(staging.into_iter().flatten())
        {
            image.destroy(gpu, allocator);
        }
        self.placeholder_float.destroy(gpu, allocator);
        self.placeholder_uint.destroy(gpu, allocator);
    }
}

/// What growing an image set takes: the device, its allocator, and the ring that keeps the
/// images a set replaces until no frame in flight can use them; `serial` is the submit the
/// growth is for.
pub struct Growth<'a> {
    pub gpu: &'a Gpu,
    pub allocator: &'a mut Allocator,
    pub ring: &'a mut FrameRing,
    pub serial: u64,
}

/// Makes `set` hold `extent`, at least as large as before on both sides, and hands the images it
/// replaces to the ring at `growth.serial` (the previous submit is the last whose commands may
/// use them). Returns whether the set was (re)made.
fn grow<const N: usize, Kind>(
    growth: &mut Growth,
    set: &mut Option<ImageSet<N, Kind>>,
    extent: vk::Extent2D,
    specs: &[ImageSpec; N],
) -> Result<bool> {
    let old = set.as_ref().map(|set| set.extent);
    if set.as_ref().is_some_and(|set| set.holds(extent)) {
        return Ok(false);
    }
    let size = vk::Extent2D {
        width: extent.width.max(old.map_or(0, |e| e.width)),
        height: extent.height.max(old.map_or(0, |e| e.height)),
    };
    let grown = ImageSet::new(growth.gpu, growth.allocator, size, specs)?;
    for image in set.replace(grown).into_iter().flat_map(|old| old.images) {
        growth.ring.retire(growth.serial.saturating_sub(1), image);
    }
    Ok(true)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vk::image::texel_bytes;

    #[test]
    fn every_working_format_has_a_texel_size() {
        let specs = WorkImages::SPECS
            .iter()
            .chain(&AnalysisImages::SPECS)
            .chain(&DiagnosticImages::SPECS)
            .chain(&OutputStaging::SPECS)
            .chain(&ShadowImages::SPECS)
            .chain(&FlowAtlases::SPECS)
            .chain(&HighlightImages::SPECS)
            .chain(&SkyImages::SPECS)
            .chain(&TranslucencyImages::SPECS);
        for spec in specs {
            assert!(
                texel_bytes(spec.format, vk::ImageAspectFlags::COLOR) > 0,
                "{}",
                spec.name
            );
        }
    }
}
