//! One plugin context: the engine's device, the plugin's pipelines and images, the frame ring,
//! and the state between `submit` (frame t) and `extrapolate` (its target instants).

use std::mem::ManuallyDrop;
use std::path::PathBuf;
use std::sync::Arc;

use ash::vk;
use gpu_allocator::vulkan::Allocator;

use crate::abi::*;
use crate::camera::Camera;
use crate::error::{bail, PatchexResult, Result};
use crate::inputs::{self, GeometryInputs, SourceInputs, TargetInputs};
use crate::network::{self, TensorPrecision};
use crate::passes::inpaint::{self, Inpainting};
use crate::passes::segmentation::{self, SegmentationSettings};
use crate::passes::shadow_flow::{self, FlowSettings};
use crate::passes::warp::WarpSettings;
use crate::passes::{
    demodulate, diagnostics, lbp, pack_gbuffer, pack_output, remodulate, separate_shadows, warp,
    Pipelines, Texture, SANITIZE_COUNTER_BYTES,
};
use crate::vk::barriers::{self, EngineImageAccess};
use crate::vk::device::Gpu;
use crate::vk::frame_ring::{FrameRecord, FrameRing, RegionRecord};
use crate::vk::image::{ImageRole, ImportedImage, OwnedImage};

pub const MAX_FRAMES_IN_FLIGHT: u32 = 8;

/// Largest extent accepted at creation; 8K with margin.
pub const MAX_EXTENT: u32 = 16384;

/// Where each pass's counters sit in an extrapolation's range of the frame counters. Both
/// offsets are multiples of 256, the largest storage-buffer offset alignment Vulkan allows.
const WARP_COUNTERS_OFFSET: u64 = 0;
/// Submit: demodulation's; extrapolation: remodulation's.
const SANITIZE_COUNTERS_OFFSET: u64 = 256;
/// Holes of the shadow layer's two warps, kept apart from the frame's.
const SHADOW_WARP_COUNTERS_OFFSET: u64 = 512;
const SURFACE_LAYER_COUNTERS_OFFSET: u64 = 768;
/// The G-buffer packing's count of NaN and infinite geometry.
const GEOMETRY_COUNTERS_OFFSET: u64 = 1024;
const OBJECT_TABLE_OFFSET: u64 = 1280;
/// The networks' patch records (`inpaint::PATCH_SLOT_*`).
const PATCHES_OFFSET: u64 = (OBJECT_TABLE_OFFSET + segmentation::TABLE_BYTES).next_multiple_of(256);
pub const COUNTER_BYTES: u64 = PATCHES_OFFSET + inpaint::PATCH_SLOTS_BYTES;

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
struct ImageSet<const N: usize> {
    extent: vk::Extent2D,
    images: [OwnedImage; N],
}

impl<const N: usize> ImageSet<N> {
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
        Ok(Self { extent, images })
    }

    fn holds(&self, extent: vk::Extent2D) -> bool {
        self.extent.width >= extent.width && self.extent.height >= extent.height
    }

    fn size_bytes(&self) -> u64 {
        self.images.iter().map(|image| image.size_bytes()).sum()
    }
}

impl<const N: usize> std::ops::Index<usize> for ImageSet<N> {
    type Output = OwnedImage;
    fn index(&self, index: usize) -> &OwnedImage {
        &self.images[index]
    }
}

/// The plugin's working images, all at one extent (the largest frame seen so far).
type WorkImages = ImageSet<8>;

impl WorkImages {
    const SOURCE_SHADING: usize = 0;
    const SOURCE_GEOMETRY: usize = 1;
    const SOURCE_NORMAL_ID: usize = 2;
    const TARGET_GEOMETRY: usize = 3;
    const TARGET_NORMAL_ID: usize = 4;
    const WARPED: usize = 5;
    /// Region of each target pixel (segmentation::REGION_*).
    const REGIONS: usize = 6;
    const LBP: usize = 7;

    const SPECS: [ImageSpec; 8] = [
        frame_image("patchex source shading", vk::Format::R32G32B32A32_SFLOAT),
        frame_image("patchex source geometry", vk::Format::R32G32B32A32_SFLOAT),
        frame_image("patchex source normal+id", vk::Format::R16G16B16A16_SFLOAT),
        frame_image("patchex target geometry", vk::Format::R32G32B32A32_SFLOAT),
        frame_image("patchex target normal+id", vk::Format::R16G16B16A16_SFLOAT),
        frame_image("patchex warped shading", vk::Format::R32G32B32A32_SFLOAT),
        frame_image("patchex regions", vk::Format::R32_UINT),
        frame_image("patchex lbp", vk::Format::R32_SFLOAT),
    ];
}

/// For an output whose format a shader cannot store (`PACKED_OUTPUT_FORMATS`): the extrapolated
/// frame, and its texels packed in the output's format for the copy. Made at the first such
/// output.
type OutputStaging = ImageSet<2>;

impl OutputStaging {
    const FRAME: usize = 0;
    const PACKED: usize = 1;

    const SPECS: [ImageSpec; 2] = [
        frame_image("patchex output frame", vk::Format::R16G16B16A16_SFLOAT),
        ImageSpec {
            copied_out: true,
            ..frame_image("patchex packed output", vk::Format::R32_UINT)
        },
    ];
}

/// The shadow sub-task's images, made at the first frame with a shadow input.
type ShadowImages = ImageSet<15>;

impl ShadowImages {
    const LAYER: usize = 0;
    /// The layer moved by the flow.
    const WARPED_LAYER: usize = 1;
    /// The layer carried by the frame's own warp: where that warp puts frame t's shadow.
    const SURFACE_LAYER: usize = 2;
    const MASK: usize = 3;
    const MASK_PYRAMID: usize = 4;
    /// Frame t's and frame t-1's expansions, alternating (`Context::shadow_current`).
    const POLY: [usize; 2] = [5, 6];
    const POLY_XY: [usize; 2] = [7, 8];
    const EQUATIONS: usize = 9;
    const EQUATIONS_H2: usize = 10;
    const ROWS: usize = 11;
    const ROWS_H2: usize = 12;
    const FLOW_PYRAMID: usize = 13;
    const FLOW: usize = 14;

    const SPECS: [ImageSpec; 15] = [
        frame_image("patchex shadow layer", vk::Format::R32G32B32A32_SFLOAT),
        frame_image(
            "patchex moved shadow layer",
            vk::Format::R32G32B32A32_SFLOAT,
        ),
        frame_image(
            "patchex surface-warped shadow layer",
            vk::Format::R32G32B32A32_SFLOAT,
        ),
        frame_image("patchex shadow mask", vk::Format::R32_SFLOAT),
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
        atlas_image("patchex flow equations", vk::Format::R32G32B32A32_SFLOAT),
        atlas_image("patchex flow equations h2", vk::Format::R32_SFLOAT),
        atlas_image("patchex flow rows", vk::Format::R32G32B32A32_SFLOAT),
        atlas_image("patchex flow rows h2", vk::Format::R32_SFLOAT),
        atlas_image(
            "patchex shadow flow pyramid",
            vk::Format::R32G32B32A32_SFLOAT,
        ),
        ImageSpec {
            cleared: true,
            ..frame_image("patchex shadow flow", vk::Format::R32G32B32A32_SFLOAT)
        },
    ];

    fn flow_images(&self, current: usize) -> shadow_flow::FlowImages<'_> {
        shadow_flow::FlowImages {
            mask: &self[Self::MASK],
            mask_pyramid: &self[Self::MASK_PYRAMID],
            poly: Self::POLY.map(|index| &self[index]),
            poly_xy: Self::POLY_XY.map(|index| &self[index]),
            current,
            equations: &self[Self::EQUATIONS],
            equations_h2: &self[Self::EQUATIONS_H2],
            rows: &self[Self::ROWS],
            rows_h2: &self[Self::ROWS_H2],
            flow_pyramid: &self[Self::FLOW_PYRAMID],
            flow: &self[Self::FLOW],
        }
    }
}

/// 1x1 images bound where an optional input is absent; the shaders never read them.
struct Placeholders {
    float: OwnedImage,
    uint: OwnedImage,
}

/// Frame t, as the last submit left it.
struct SourceFrame {
    frame_index: u64,
    /// Which submit of the context it was (1, 2, ...): frame indices may restart after a reset,
    /// so the frame ring and image retirement count submits instead.
    serial: u64,
    extent: vk::Extent2D,
    camera: Camera,
    /// It came with a shadow input: its layer and flow are in the shadow images.
    has_shadows: bool,
}

/// Extension structs chained on a create info or an extrapolate call, validated.
#[derive(Default)]
pub struct Extensions {
    pub warp: Option<WarpSettings>,
    pub segmentation: Option<SegmentationSettings>,
    pub diagnostics: Option<PatchexImage>,
    pub shadow_diagnostics: Option<PatchexImage>,
    pub shadow: Option<PatchexShadowInput>,
    pub flow: Option<FlowSettings>,
    pub network_weights: Option<NetworkWeightPaths>,
    pub networks: Option<NetworkSwitches>,
    pub network_precision: Option<TensorPrecision>,
}

/// Weight files in place of the built-in networks (`PatchexNetworkWeights`).
#[derive(Clone, Debug, Default)]
pub struct NetworkWeightPaths {
    pub fi: Option<PathBuf>,
    pub near_be: Option<PathBuf>,
}

/// Which region's network runs (`PatchexNetworkSettings`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct NetworkSwitches {
    pub fi: bool,
    pub near_be: bool,
    /// The FI network over the whole frame instead of the patches (needs `fi`).
    pub whole_frame: bool,
    /// Frame pixels per network texel on each axis: 1, 2 or 4.
    pub divisor: u32,
}

impl Default for NetworkSwitches {
    fn default() -> Self {
        Self {
            fi: true,
            near_be: true,
            whole_frame: false,
            divisor: 1,
        }
    }
}

impl NetworkSwitches {
    /// Which of the FI and near-BE networks run: whole-frame runs FI alone.
    pub fn running(&self) -> [bool; 2] {
        [self.fi, self.near_be && !self.whole_frame]
    }
}

pub struct Context {
    gpu: Gpu,
    allocator: ManuallyDrop<Allocator>,
    pipelines: Arc<Pipelines>,
    ring: FrameRing,
    placeholders: Placeholders,
    work: Option<WorkImages>,
    shadows: Option<ShadowImages>,
    output_staging: Option<OutputStaging>,
    /// PATCHEX_PRESET_NETWORKS and PATCHEX_PRESET_FULL: the two inpainting networks.
    inpainting: Option<Inpainting>,
    /// Which of the alternating expansion images holds the last submitted frame's.
    shadow_current: usize,
    max_extent: vk::Extent2D,
    default_warp: WarpSettings,
    default_segmentation: SegmentationSettings,
    default_flow: FlowSettings,
    default_networks: NetworkSwitches,
    /// The preset runs the shadow sub-task on frames with a shadow input.
    with_shadows: bool,
    source: Option<SourceFrame>,
}

const NEEDS_SHADOW_PRESET: &str =
    "needs a context made with PATCHEX_PRESET_WARP_AND_SHADOWS or PATCHEX_PRESET_FULL";

impl Context {
    /// # Safety
    /// The handles in `info` must be live objects of one Vulkan instance.
    pub unsafe fn new(info: &PatchexCreateInfo, defaults: Extensions) -> Result<Self> {
        let (with_networks, with_shadows) = match info.preset {
            PATCHEX_PRESET_WARP_ONLY => (false, false),
            PATCHEX_PRESET_NETWORKS => (true, false),
            PATCHEX_PRESET_WARP_AND_SHADOWS => (false, true),
            PATCHEX_PRESET_FULL => (true, true),
            other => bail!(
                ErrorInvalidArgument,
                "PatchexCreateInfo.preset {other} is not a preset: PATCHEX_PRESET_WARP_ONLY (0), \
                 PATCHEX_PRESET_NETWORKS (1), PATCHEX_PRESET_WARP_AND_SHADOWS (2) or \
                 PATCHEX_PRESET_FULL (3)"
            ),
        };
        if !with_networks
            && (defaults.network_weights.is_some()
                || defaults.networks.is_some()
                || defaults.network_precision.is_some())
        {
            bail!(
                ErrorInvalidArgument,
                "PatchexNetworkWeights, PatchexNetworkSettings and PatchexNetworkPrecision need \
                 PATCHEX_PRESET_NETWORKS or PATCHEX_PRESET_FULL"
            );
        }
        if !with_shadows && defaults.flow.is_some() {
            bail!(
                ErrorInvalidArgument,
                "PatchexShadowFlowSettings {NEEDS_SHADOW_PRESET}"
            );
        }
        // Read before any Vulkan object is made: a bad file costs nothing to refuse.
        let networks = if with_networks {
            let paths = defaults.network_weights.clone().unwrap_or_default();
            Some([
                network::load(paths.fi.as_deref(), network::SHIPPED_FI, "FI")?,
                network::load(
                    paths.near_be.as_deref(),
                    network::SHIPPED_NEAR_BE,
                    "near-BE",
                )?,
            ])
        } else {
            None
        };
        if !(1..=MAX_FRAMES_IN_FLIGHT).contains(&info.frames_in_flight) {
            bail!(
                ErrorInvalidArgument,
                "PatchexCreateInfo.frames_in_flight {} must be 1 to {MAX_FRAMES_IN_FLIGHT}",
                info.frames_in_flight
            );
        }
        if info.max_width == 0
            || info.max_height == 0
            || info.max_width > MAX_EXTENT
            || info.max_height > MAX_EXTENT
        {
            bail!(
                ErrorInvalidArgument,
                "PatchexCreateInfo max extent {}x{} must be 1 to {MAX_EXTENT} on each side",
                info.max_width,
                info.max_height
            );
        }
        let gpu = Gpu::load(info)?;
        WorkImages::check_formats(&gpu, &WorkImages::SPECS)?;
        OutputStaging::check_formats(&gpu, &OutputStaging::SPECS)?;
        ShadowImages::check_formats(&gpu, &ShadowImages::SPECS)?;
        let mut allocator = gpu.allocator()?;
        let pipelines = Pipelines::shared(&gpu)?;
        let ring = FrameRing::new(
            &gpu,
            &mut allocator,
            info.frames_in_flight as usize,
            &pipelines.set_layouts(),
            &pipelines.pool_sizes(),
        )?;
        let mut context = Self {
            gpu,
            allocator: ManuallyDrop::new(allocator),
            pipelines,
            ring,
            placeholders: Placeholders {
                float: OwnedImage::null(),
                uint: OwnedImage::null(),
            },
            work: None,
            shadows: None,
            output_staging: None,
            inpainting: None,
            shadow_current: 0,
            max_extent: vk::Extent2D {
                width: info.max_width,
                height: info.max_height,
            },
            default_warp: defaults.warp.unwrap_or_default(),
            default_segmentation: defaults.segmentation.unwrap_or_default(),
            default_flow: defaults.flow.unwrap_or_default(),
            default_networks: defaults.networks.unwrap_or_default(),
            with_shadows,
            source: None,
        };
        let one = vk::Extent2D {
            width: 1,
            height: 1,
        };
        let sampled = vk::ImageUsageFlags::SAMPLED;
        context.placeholders.float = OwnedImage::new(
            &context.gpu,
            &mut context.allocator,
            "patchex placeholder",
            vk::Format::R16G16B16A16_SFLOAT,
            one,
            sampled,
        )?;
        context.placeholders.uint = OwnedImage::new(
            &context.gpu,
            &mut context.allocator,
            "patchex placeholder uint",
            vk::Format::R8_UINT,
            one,
            sampled,
        )?;
        if let Some(networks) = networks {
            let instances = info.frames_in_flight as usize * PATCHEX_MAX_EXTRAPOLATIONS_PER_FRAME;
            context.inpainting = Some(Inpainting::new(
                &context.gpu,
                &mut context.allocator,
                networks,
                defaults.network_precision.unwrap_or_default(),
                instances,
                context.max_extent,
            )?);
        }
        Ok(context)
    }

    fn check_queue_family(&self, family: u32, what: &str) -> Result<()> {
        if family != self.gpu.queue_family_index {
            bail!(
                ErrorWrongQueueFamily,
                "{what}.queue_family_index is {family}, but the context records for family {}",
                self.gpu.queue_family_index
            );
        }
        Ok(())
    }

    fn reset_reason(&self, inputs: &SourceInputs) -> Result<PatchexResetReason> {
        let Some(previous) = &self.source else {
            return Ok(PATCHEX_RESET_FIRST_FRAME);
        };
        if inputs.reset {
            // A reset starts a new history, so the engine may restart its numbering with it.
            return Ok(PATCHEX_RESET_REQUESTED);
        }
        if inputs.frame_index <= previous.frame_index {
            bail!(
                ErrorOutOfOrder,
                "PatchexFrameDesc.frame_index {} does not increase (previous {}); set reset to \
                 start a new numbering",
                inputs.frame_index,
                previous.frame_index
            );
        }
        Ok(if inputs.frame_index != previous.frame_index + 1 {
            PATCHEX_RESET_FRAME_GAP
        } else {
            PATCHEX_RESET_NONE
        })
    }

    /// Grows the working images to hold `extent`; the old ones wait out the frames in flight.
    fn ensure_work_images(&mut self, extent: vk::Extent2D, serial: u64) -> Result<()> {
        if let Some(work) = grown(
            &self.gpu,
            &mut self.allocator,
            &self.work,
            extent,
            &WorkImages::SPECS,
        )? {
            if let Some(old) = self.work.replace(work) {
                retire(&mut self.ring, old, serial);
            }
        }
        Ok(())
    }

    /// Makes or grows the shadow images to the working images' extent. Returns whether they
    /// were (re)made, which loses frame t-1's expansion.
    fn ensure_shadow_images(&mut self, serial: u64) -> Result<bool> {
        let extent = self.work.as_ref().expect("made first").extent;
        let Some(shadows) = grown(
            &self.gpu,
            &mut self.allocator,
            &self.shadows,
            extent,
            &ShadowImages::SPECS,
        )?
        else {
            return Ok(false);
        };
        if let Some(old) = self.shadows.replace(shadows) {
            retire(&mut self.ring, old, serial);
        }
        Ok(true)
    }

    fn placeholder_textures(&self) -> (Texture, Texture) {
        (
            (&self.placeholders.float).into(),
            (&self.placeholders.uint).into(),
        )
    }

    /// Records frame t's demodulation (or shadow separation), G-buffer packing and, with a
    /// shadow input, the shadow mask's flow into `cmd`.
    pub fn submit(
        &mut self,
        cmd: vk::CommandBuffer,
        desc: &PatchexFrameDesc,
        extensions: Extensions,
    ) -> Result<()> {
        self.check_queue_family(desc.queue_family_index, "PatchexFrameDesc")?;
        if !self.with_shadows && (extensions.shadow.is_some() || extensions.flow.is_some()) {
            bail!(
                ErrorInvalidArgument,
                "PatchexShadowInput and PatchexShadowFlowSettings {NEEDS_SHADOW_PRESET}"
            );
        }
        let inputs = inputs::source(&self.gpu, desc, self.max_extent)?;
        let shadow_inputs = extensions
            .shadow
            .map(|input| inputs::shadow(&self.gpu, &input, inputs.extent))
            .transpose()?;
        let flow_settings = extensions.flow.unwrap_or(self.default_flow);
        let reset_reason = self.reset_reason(&inputs)?;
        let (placeholder, placeholder_uint) = self.placeholder_textures();
        let mut access = EngineImageAccess::default();
        let color = access.read(&inputs.color)?;
        let base_color = access.read(&inputs.base_color)?;
        let material = access.read_optional(inputs.material.as_ref())?;
        let separation_inputs = match &shadow_inputs {
            Some(shadow) => Some(separate_shadows::SeparationInputs {
                color,
                color_without_dynamic_shadows: access
                    .read(&shadow.color_without_dynamic_shadows)?,
                mask: access.read(&shadow.mask)?,
                base_color,
                material,
                placeholder,
            }),
            None => None,
        };
        let pack_inputs =
            pack_inputs(&mut access, &inputs.geometry, placeholder, placeholder_uint)?;

        let serial = self.source.as_ref().map_or(1, |s| s.serial + 1);
        self.ring.collect(&self.gpu, &mut self.allocator, serial);
        self.ensure_work_images(inputs.extent, serial)?;
        // Frame t-1's expansion is usable when it was made, unbroken, on the same images.
        let mut track = reset_reason == PATCHEX_RESET_NONE
            && self
                .source
                .as_ref()
                .is_some_and(|s| s.has_shadows && s.extent == inputs.extent);
        if shadow_inputs.is_some() {
            track &= !self.ensure_shadow_images(serial)?;
            self.shadow_current = 1 - self.shadow_current;
        }

        // Everything is validated and allocated: from here on the call cannot fail.
        let slot = self.ring.slot_of(serial);
        let device = &self.gpu.device;
        let mut owned: Vec<&mut OwnedImage> = Vec::new();
        for set_images in [
            self.work.as_mut().map(|w| &mut w.images[..]),
            self.shadows.as_mut().map(|s| &mut s.images[..]),
        ]
        .into_iter()
        .flatten()
        {
            owned.extend(set_images.iter_mut());
        }
        owned.push(&mut self.placeholders.float);
        owned.push(&mut self.placeholders.uint);
        if let Some(inpainting) = self.inpainting.as_mut() {
            owned.extend(inpainting.images());
        }
        barriers::initialize_owned(device, cmd, &mut owned);
        let work = self.work.as_ref().expect("allocated above");
        access.acquire(device, cmd);
        self.ring.clear_counters(device, cmd, slot, 0);
        barriers::compute_to_compute(device, cmd, true);

        let sanitize_counters =
            self.ring
                .counter_range(slot, 0, SANITIZE_COUNTERS_OFFSET, SANITIZE_COUNTER_BYTES);
        let mut timed = TimedRegion::begin(&self.ring, device, cmd, slot, 0);
        timed.stage(PATCHEX_STAGE_PACK_SOURCE_GBUFFER, || {
            pack_gbuffer::record(
                self.pipelines.get(Pipelines::PACK_GBUFFER),
                device,
                cmd,
                self.ring.descriptor_set(slot, 0, Pipelines::PACK_GBUFFER),
                inputs.extent,
                &inputs.geometry.camera,
                &pack_inputs,
                &pack_gbuffer::PackOutputs {
                    geometry: &work[WorkImages::SOURCE_GEOMETRY],
                    normal_id: &work[WorkImages::SOURCE_NORMAL_ID],
                    counters: self.ring.counter_range(
                        slot,
                        0,
                        GEOMETRY_COUNTERS_OFFSET,
                        pack_gbuffer::COUNTER_BYTES,
                    ),
                },
            )
        });
        if separation_inputs.is_some() {
            // Separation reads the packed object ids.
            barriers::compute_to_compute(device, cmd, false);
        }
        timed.stage(PATCHEX_STAGE_DEMODULATE, || {
            match (&separation_inputs, &self.shadows) {
                (Some(separation), Some(shadows)) => separate_shadows::record(
                    self.pipelines.get(Pipelines::SEPARATE_SHADOWS),
                    device,
                    cmd,
                    self.ring
                        .descriptor_set(slot, 0, Pipelines::SEPARATE_SHADOWS),
                    inputs.extent,
                    separation,
                    &separate_shadows::SeparationOutputs {
                        source_normal_id: &work[WorkImages::SOURCE_NORMAL_ID],
                        shading: &work[WorkImages::SOURCE_SHADING],
                        shadow_layer: &shadows[ShadowImages::LAYER],
                        flow_mask: &shadows[ShadowImages::MASK],
                    },
                    &sanitize_counters,
                ),
                _ => demodulate::record(
                    self.pipelines.get(Pipelines::DEMODULATE),
                    device,
                    cmd,
                    self.ring.descriptor_set(slot, 0, Pipelines::DEMODULATE),
                    inputs.extent,
                    &demodulate::DemodulateInputs {
                        color,
                        base_color,
                        material,
                        placeholder,
                    },
                    &work[WorkImages::SOURCE_SHADING],
                    &sanitize_counters,
                ),
            }
        });
        if let (Some(_), Some(shadows)) = (&separation_inputs, &self.shadows) {
            barriers::compute_to_compute(device, cmd, false);
            let p = Pipelines::get;
            let pipelines = &self.pipelines;
            timed.stage(PATCHEX_STAGE_SHADOW_FLOW, || {
                shadow_flow::record(
                    &shadow_flow::FlowPipelines {
                        pyramid: p(pipelines, Pipelines::SHADOW_PYRAMID),
                        poly: p(pipelines, Pipelines::SHADOW_POLY),
                        matrices: p(pipelines, Pipelines::SHADOW_FLOW_MATRICES),
                        rows: p(pipelines, Pipelines::SHADOW_FLOW_ROWS),
                        solve: p(pipelines, Pipelines::SHADOW_FLOW_SOLVE),
                        upsample: p(pipelines, Pipelines::SHADOW_FLOW_UPSAMPLE),
                    },
                    [
                        Pipelines::SHADOW_PYRAMID,
                        Pipelines::SHADOW_POLY,
                        Pipelines::SHADOW_FLOW_MATRICES,
                        Pipelines::SHADOW_FLOW_ROWS,
                        Pipelines::SHADOW_FLOW_SOLVE,
                        Pipelines::SHADOW_FLOW_UPSAMPLE,
                    ]
                    .map(|index| self.ring.descriptor_set(slot, 0, index)),
                    device,
                    cmd,
                    inputs.extent,
                    &flow_settings,
                    &shadows.flow_images(self.shadow_current),
                    track,
                )
            });
        }
        let stages = timed.stages;
        barriers::compute_to_host(device, cmd);
        access.release(device, cmd);

        let shadow_history = match (&separation_inputs, track) {
            (None, _) => PATCHEX_SHADOW_HISTORY_NONE,
            (Some(_), false) => PATCHEX_SHADOW_HISTORY_STARTED,
            (Some(_), true) => PATCHEX_SHADOW_HISTORY_TRACKED,
        };
        self.ring.slots[slot].record = Some(FrameRecord {
            frame_index: inputs.frame_index,
            serial,
            extent: inputs.extent,
            reset_reason,
            shadow_history,
            submit: RegionRecord {
                stages,
                alpha: 0.0,
                camera_cut: false,
                whole_frame: false,
            },
            extrapolations: Vec::new(),
        });
        self.source = Some(SourceFrame {
            frame_index: inputs.frame_index,
            serial,
            extent: inputs.extent,
            camera: inputs.geometry.camera,
            has_shadows: shadow_inputs.is_some(),
        });
        Ok(())
    }

    /// Records one extrapolation from the last submitted frame into `cmd`; `RenderInstead` when
    /// the target is a camera cut.
    pub fn extrapolate(
        &mut self,
        cmd: vk::CommandBuffer,
        desc: &PatchexExtrapolateDesc,
        extensions: Extensions,
    ) -> Result<PatchexResult> {
        self.check_queue_family(desc.queue_family_index, "PatchexExtrapolateDesc")?;
        let Some(source) = &self.source else {
            bail!(
                ErrorNoSourceFrame,
                "patchex_extrapolate called before any patchex_submit_gbuffers"
            );
        };
        let inputs: TargetInputs = inputs::target(&self.gpu, desc, self.max_extent)?;
        if inputs.extent != source.extent {
            bail!(
                ErrorMismatchedExtent,
                "PatchexExtrapolateDesc extent {}x{} differs from the submitted frame's {}x{}",
                inputs.extent.width,
                inputs.extent.height,
                source.extent.width,
                source.extent.height
            );
        }
        let slot = self.ring.slot_of(source.serial);
        let done = self.ring.slots[slot]
            .record
            .as_ref()
            .map_or(0, |r| r.extrapolations.len());
        if done >= PATCHEX_MAX_EXTRAPOLATIONS_PER_FRAME {
            bail!(
                ErrorTooManyExtrapolations,
                "frame {} already has {PATCHEX_MAX_EXTRAPOLATIONS_PER_FRAME} extrapolations",
                source.frame_index
            );
        }
        let (placeholder, placeholder_uint) = self.placeholder_textures();
        let mut access = EngineImageAccess::default();
        let motion = access.read(&inputs.motion_vectors)?;
        let pack_inputs = pack_gbuffer::PackInputs {
            motion: Some(motion),
            ..pack_inputs(&mut access, &inputs.geometry, placeholder, placeholder_uint)?
        };
        let base_color = access.read(&inputs.base_color)?;
        let material = access.read_optional(inputs.material.as_ref())?;
        let output = access.write(&inputs.output)?;
        let diagnostics_image = match &extensions.diagnostics {
            Some(image) => Some(access.write(&ImportedImage::import_required(
                &self.gpu,
                image,
                &ImageRole::diagnostics("PatchexDiagnostics.image"),
                inputs.extent,
            )?)?),
            None => None,
        };

        let shadow_diagnostics_image = match &extensions.shadow_diagnostics {
            Some(image) => Some(access.write(&ImportedImage::import_required(
                &self.gpu,
                image,
                &ImageRole::diagnostics("PatchexShadowDiagnostics.image"),
                inputs.extent,
            )?)?),
            None => None,
        };
        if self.inpainting.is_none() && extensions.networks.is_some() {
            bail!(
                ErrorInvalidArgument,
                "PatchexNetworkSettings needs a context made with PATCHEX_PRESET_NETWORKS or \
                 PATCHEX_PRESET_FULL"
            );
        }
        let run_networks = extensions.networks.unwrap_or(self.default_networks);
        let warp_settings = extensions.warp.unwrap_or(self.default_warp);
        let segmentation_settings = extensions.segmentation.unwrap_or(self.default_segmentation);
        let jitter_delta = (inputs.geometry.camera.jitter - source.camera.jitter).into();
        let warp_params = warp_settings.params(
            inputs.extent,
            &inputs.geometry.camera,
            jitter_delta,
            inputs.geometry.motion_vector_scale,
        );

        if inputs.output.written_by_copy {
            let extent = self.work.as_ref().expect("made by the submit").extent;
            if let Some(staging) = grown(
                &self.gpu,
                &mut self.allocator,
                &self.output_staging,
                extent,
                &OutputStaging::SPECS,
            )? {
                if let Some(old) = self.output_staging.replace(staging) {
                    retire(&mut self.ring, old, source.serial);
                }
            }
        }

        // Everything is validated and allocated: from here on the call cannot fail.
        let region = 1 + done;
        let device = &self.gpu.device;
        let work = self
            .work
            .as_ref()
            .expect("a submitted frame allocated the work images");
        let object_table =
            self.ring
                .counter_range(slot, region, OBJECT_TABLE_OFFSET, segmentation::TABLE_BYTES);
        let staging = match self.output_staging.as_mut() {
            Some(staging) if inputs.output.written_by_copy => {
                let [frame, packed] = &mut staging.images;
                barriers::initialize_owned(device, cmd, &mut [frame, packed]);
                Some(&*staging)
            }
            _ => None,
        };
        access.acquire(device, cmd);
        self.ring.clear_counters(device, cmd, slot, region);
        let mut timed = TimedRegion::begin(&self.ring, device, cmd, slot, region);
        barriers::compute_to_compute(device, cmd, true);

        timed.stage(PATCHEX_STAGE_PACK_TARGET_GBUFFER, || {
            pack_gbuffer::record(
                self.pipelines.get(Pipelines::PACK_GBUFFER),
                device,
                cmd,
                self.ring
                    .descriptor_set(slot, region, Pipelines::PACK_GBUFFER),
                inputs.extent,
                &inputs.geometry.camera,
                &pack_inputs,
                &pack_gbuffer::PackOutputs {
                    geometry: &work[WorkImages::TARGET_GEOMETRY],
                    normal_id: &work[WorkImages::TARGET_NORMAL_ID],
                    counters: self.ring.counter_range(
                        slot,
                        region,
                        GEOMETRY_COUNTERS_OFFSET,
                        pack_gbuffer::COUNTER_BYTES,
                    ),
                },
            )
        });
        barriers::compute_to_compute(device, cmd, false);
        // Every warp of this extrapolation reads the geometry of both instants.
        let record_warp = |pipeline: usize,
                           set: usize,
                           params: &warp::Params,
                           source_shading: &OwnedImage,
                           motion: Texture,
                           output: &OwnedImage,
                           counters_offset: u64| {
            warp::record(
                self.pipelines.get(pipeline),
                device,
                cmd,
                self.ring.descriptor_set(slot, region, set),
                params,
                &warp::WarpInputs {
                    source_shading,
                    source_geometry: &work[WorkImages::SOURCE_GEOMETRY],
                    source_normal_id: &work[WorkImages::SOURCE_NORMAL_ID],
                    target_geometry: &work[WorkImages::TARGET_GEOMETRY],
                    target_normal_id: &work[WorkImages::TARGET_NORMAL_ID],
                    motion,
                },
                output,
                &self
                    .ring
                    .counter_range(slot, region, counters_offset, warp::COUNTER_BYTES),
            )
        };
        let warp_index = Pipelines::warp(warp_settings.kind);
        timed.stage(PATCHEX_STAGE_WARP, || {
            record_warp(
                warp_index,
                warp_index,
                &warp_params,
                &work[WorkImages::SOURCE_SHADING],
                motion,
                &work[WorkImages::WARPED],
                WARP_COUNTERS_OFFSET,
            )
        });
        let shadows = self.shadows.as_ref().filter(|_| source.has_shadows);
        if let Some(shadows) = shadows {
            // The shadow layer through the frame's own warp (where that warp put frame t's
            // shadow), and moved by the mask's flow scaled to the target instant.
            let params =
                warp_settings.shadow_params(inputs.extent, &inputs.geometry.camera, inputs.alpha);
            let layer = &shadows[ShadowImages::LAYER];
            timed.stage(PATCHEX_STAGE_SHADOW_WARP, || {
                record_warp(
                    warp_index,
                    Pipelines::surface_layer_set(warp_index),
                    &warp_params,
                    layer,
                    motion,
                    &shadows[ShadowImages::SURFACE_LAYER],
                    SURFACE_LAYER_COUNTERS_OFFSET,
                );
                record_warp(
                    Pipelines::WARP_OCCLUSION_MOTION,
                    Pipelines::SHADOW_WARP_SET,
                    &params,
                    layer,
                    (&shadows[ShadowImages::FLOW]).into(),
                    &shadows[ShadowImages::WARPED_LAYER],
                    SHADOW_WARP_COUNTERS_OFFSET,
                );
            });
        }
        timed.stage(PATCHEX_STAGE_SEGMENT, || {
            segmentation::record(
                &segmentation::SegmentationPipelines {
                    object_bounds: self.pipelines.get(Pipelines::OBJECT_BOUNDS),
                    grow_regions: self.pipelines.get(Pipelines::GROW_REGIONS),
                    region_masks: self.pipelines.get(Pipelines::REGION_MASKS),
                },
                [
                    Pipelines::OBJECT_BOUNDS,
                    Pipelines::GROW_REGIONS,
                    Pipelines::REGION_MASKS,
                ]
                .map(|index| self.ring.descriptor_set(slot, region, index)),
                device,
                cmd,
                inputs.extent,
                &segmentation_settings,
                &segmentation::SegmentationInputs {
                    target_normal_id: &work[WorkImages::TARGET_NORMAL_ID],
                    motion,
                    motion_scale: inputs.geometry.motion_vector_scale,
                },
                &object_table,
                &work[WorkImages::REGIONS],
            )
        });
        timed.stage(PATCHEX_STAGE_LBP, || {
            lbp::record(
                self.pipelines.get(Pipelines::LBP),
                device,
                cmd,
                self.ring.descriptor_set(slot, region, Pipelines::LBP),
                inputs.extent,
                &work[WorkImages::WARPED],
                &work[WorkImages::LBP],
            )
        });
        barriers::compute_to_compute(device, cmd, false);
        if let Some(inpainting) = &self.inpainting {
            let patches =
                self.ring
                    .counter_range(slot, region, PATCHES_OFFSET, inpaint::PATCH_SLOTS_BYTES);
            timed.stage(PATCHEX_STAGE_INFERENCE, || {
                inpaint::record_plan(
                    self.pipelines.get(Pipelines::PLAN_PATCHES),
                    device,
                    cmd,
                    self.ring
                        .descriptor_set(slot, region, Pipelines::PLAN_PATCHES),
                    inputs.extent,
                    inpainting.levels(run_networks.running()),
                    run_networks.whole_frame,
                    run_networks.divisor,
                    &object_table,
                    &patches,
                );
                barriers::compute_to_indirect(device, cmd);
                let instance = slot * PATCHEX_MAX_EXTRAPOLATIONS_PER_FRAME + done;
                let runs = [inpaint::PATCH_SLOT_FI, inpaint::PATCH_SLOT_NEAR_BE]
                    .into_iter()
                    .zip(&inpainting.networks)
                    .map(|(patch_slot, (pipelines, tensors))| inpaint::NetworkRun {
                        pipelines,
                        instance,
                        tensors,
                        patch: inpaint::patch_record(&patches, patch_slot),
                    })
                    .collect::<Vec<_>>();
                inpaint::record(
                    &self.gpu,
                    cmd,
                    &inpaint::FrameInputs {
                        warped: (&work[WorkImages::WARPED]).into(),
                        material,
                        lbp: (&work[WorkImages::LBP]).into(),
                        placeholder,
                        frame_extent: inputs.extent,
                    },
                    &runs,
                );
            });
            barriers::compute_to_compute(device, cmd, false);
            timed.stage(PATCHEX_STAGE_BLEND, || {
                inpaint::record_blend(
                    self.pipelines.get(Pipelines::BLEND_PATCHES),
                    device,
                    cmd,
                    self.ring
                        .descriptor_set(slot, region, Pipelines::BLEND_PATCHES),
                    &inpaint::BlendInputs {
                        regions: &work[WorkImages::REGIONS],
                        networks: inpainting.tensors(),
                        whole_frame: run_networks.whole_frame,
                    },
                    &patches,
                    &work[WorkImages::WARPED],
                )
            });
            barriers::compute_to_compute(device, cmd, false);
        }
        timed.stage(PATCHEX_STAGE_REMODULATE, || {
            remodulate::record(
                self.pipelines.get(Pipelines::REMODULATE),
                device,
                cmd,
                self.ring
                    .descriptor_set(slot, region, Pipelines::REMODULATE),
                inputs.extent,
                &remodulate::RemodulateInputs {
                    shading: (&work[WorkImages::WARPED]).into(),
                    base_color,
                    material,
                    shadow_layers: shadows.map(|s| {
                        [ShadowImages::WARPED_LAYER, ShadowImages::SURFACE_LAYER]
                            .map(|index| (&s[index]).into())
                    }),
                    target_normal_id: (&work[WorkImages::TARGET_NORMAL_ID]).into(),
                    placeholder,
                },
                staging.map_or(output, |s| (&s[OutputStaging::FRAME]).into()),
                &self.ring.counter_range(
                    slot,
                    region,
                    SANITIZE_COUNTERS_OFFSET,
                    SANITIZE_COUNTER_BYTES,
                ),
            )
        });
        if let Some(staging) = staging {
            let encoding = pack_output::encoding(inputs.output.format)
                .expect("every copied output format has an encoding");
            barriers::compute_to_compute(device, cmd, false);
            timed.stage(PATCHEX_STAGE_PACK_OUTPUT, || {
                pack_output::record(
                    self.pipelines.get(Pipelines::PACK_OUTPUT),
                    device,
                    cmd,
                    self.ring
                        .descriptor_set(slot, region, Pipelines::PACK_OUTPUT),
                    inputs.extent,
                    &pack_output::Packing {
                        encoding,
                        frame: &staging[OutputStaging::FRAME],
                        packed: &staging[OutputStaging::PACKED],
                        output: &inputs.output,
                    },
                )
            });
        }
        let shadow_diagnostics = shadow_diagnostics_image.zip(shadows);
        if diagnostics_image.is_some() || shadow_diagnostics.is_some() {
            timed.stage(PATCHEX_STAGE_DIAGNOSTICS, || {
                if let Some(image) = diagnostics_image {
                    diagnostics::record(
                        self.pipelines.get(Pipelines::WRITE_DIAGNOSTICS),
                        device,
                        cmd,
                        self.ring
                            .descriptor_set(slot, region, Pipelines::WRITE_DIAGNOSTICS),
                        inputs.extent,
                        &diagnostics::DiagnosticsInputs {
                            warped: &work[WorkImages::WARPED],
                            regions: &work[WorkImages::REGIONS],
                            lbp: &work[WorkImages::LBP],
                        },
                        image,
                    );
                }
                if let Some((image, shadows)) = shadow_diagnostics {
                    diagnostics::record_shadows(
                        self.pipelines.get(Pipelines::WRITE_SHADOW_DIAGNOSTICS),
                        device,
                        cmd,
                        self.ring
                            .descriptor_set(slot, region, Pipelines::WRITE_SHADOW_DIAGNOSTICS),
                        inputs.extent,
                        &diagnostics::ShadowDiagnosticsInputs {
                            flow: &shadows[ShadowImages::FLOW],
                            shadow_layer: &shadows[ShadowImages::LAYER],
                            warped_layer: &shadows[ShadowImages::WARPED_LAYER],
                        },
                        image,
                    );
                }
            });
        }
        let stages = timed.stages;
        barriers::compute_to_host(device, cmd);
        access.release(device, cmd);

        let record = self.ring.slots[slot]
            .record
            .as_mut()
            .expect("the submit recorded this slot");
        let camera_cut = inputs.geometry.camera.is_cut_from(&source.camera);
        record.extrapolations.push(RegionRecord {
            stages,
            alpha: inputs.alpha,
            camera_cut,
            whole_frame: self.inpainting.is_some() && run_networks.whole_frame,
        });
        Ok(if camera_cut {
            PatchexResult::RenderInstead
        } else {
            PatchexResult::Success
        })
    }

    /// Fills `out` for `frame_index`; `NotReady` while the GPU has not finished it.
    pub fn frame_stats(
        &self,
        frame_index: u64,
        out: &mut PatchexFrameStats,
    ) -> Result<PatchexResult> {
        // After a reset that restarted the numbering, the newest frame of that index answers.
        let Some((slot, record)) = self
            .ring
            .slots
            .iter()
            .enumerate()
            .filter_map(|(slot, s)| Some((slot, s.record.as_ref()?)))
            .filter(|(_, r)| r.frame_index == frame_index)
            .max_by_key(|(_, r)| r.serial)
        else {
            bail!(
                ErrorFrameNotFound,
                "frame {frame_index} is not among the last {} submitted frames",
                self.ring.slots.len()
            );
        };
        let mut ready = true;
        let mut read_times = |region: usize,
                              stages: &[u32],
                              gpu_ms: &mut [f32; PATCHEX_STAGE_SLOTS]|
         -> Result<()> {
            let Some(timer) = &self.ring.timer else {
                return Ok(());
            };
            for &stage in stages {
                match timer.read_ms(&self.gpu.device, self.ring.query(slot, region, stage))? {
                    Some(ms) => gpu_ms[stage as usize] = ms,
                    None => ready = false,
                }
            }
            Ok(())
        };
        let mut submit_gpu_ms = [0.0; PATCHEX_STAGE_SLOTS];
        read_times(0, &record.submit.stages, &mut submit_gpu_ms)?;
        let mut extrapolations =
            [PatchexExtrapolationStats::default(); PATCHEX_MAX_EXTRAPOLATIONS_PER_FRAME];
        let pixels = (record.extent.width * record.extent.height) as f32;
        for (index, (region_record, stats)) in record
            .extrapolations
            .iter()
            .zip(&mut extrapolations)
            .enumerate()
        {
            let region = 1 + index;
            read_times(region, &region_record.stages, &mut stats.gpu_ms)?;
            let counters = self.ring.counter_offset(slot, region);
            stats.alpha = region_record.alpha;
            stats.hole_fraction =
                self.ring
                    .counters
                    .read_u32(counters + warp::HOLE_PIXELS_OFFSET) as f32
                    / pixels;
            stats.offscreen_fraction =
                self.ring
                    .counters
                    .read_u32(counters + warp::OFFSCREEN_PIXELS_OFFSET) as f32
                    / pixels;
            let segmented =
                segmentation::read_back(&self.ring.counters, counters + OBJECT_TABLE_OFFSET);
            stats.sanitized_pixels = self
                .ring
                .counters
                .read_u32(counters + SANITIZE_COUNTERS_OFFSET);
            stats.invalid_geometry_pixels = self
                .ring
                .counters
                .read_u32(counters + GEOMETRY_COUNTERS_OFFSET);
            stats.largest_motion = f32::from_bits(
                self.ring
                    .counters
                    .read_u32(counters + warp::LARGEST_MOTION_OFFSET),
            );
            stats.stages_run = stage_bits(&region_record.stages);
            // The networks' stages were recorded, but dispatch nothing on empty patches.
            let patch_extent = |patch_slot: u64| {
                inpaint::read_patch_extent(
                    &self.ring.counters,
                    counters + PATCHES_OFFSET + patch_slot * inpaint::PATCH_SLOT_BYTES,
                )
            };
            let ran = |patch_slot| patch_extent(patch_slot).iter().all(|&side| side > 0);
            let (fi_ran, near_be_ran) = (
                ran(inpaint::PATCH_SLOT_FI),
                ran(inpaint::PATCH_SLOT_NEAR_BE),
            );
            if !fi_ran && !near_be_ran {
                stats.stages_run &= !(1 << PATCHEX_STAGE_INFERENCE | 1 << PATCHEX_STAGE_BLEND);
            }
            if region_record.camera_cut {
                stats.render_instead_reasons |= PATCHEX_RENDER_INSTEAD_CAMERA_CUT;
            }
            if stats.hole_fraction > PATCHEX_MAX_TRUSTED_HOLE_FRACTION {
                stats.render_instead_reasons |= PATCHEX_RENDER_INSTEAD_DISOCCLUSION;
            }
            stats.fi_fraction = segmented.fi_pixels as f32 / pixels;
            stats.near_be_fraction = segmented.near_be_pixels as f32 / pixels;
            stats.repaired_fraction = if region_record.whole_frame {
                fi_ran as u32 as f32
            } else {
                (fi_ran as u32 * segmented.fi_pixels
                    + near_be_ran as u32 * segmented.near_be_pixels) as f32
                    / pixels
            };
            stats.object_count = segmented.rects.len() as u32;
            for (reported, rect) in stats.rects.iter_mut().zip(&segmented.rects) {
                *reported = *rect;
            }
        }
        *out = PatchexFrameStats {
            header: out.header,
            frame_index,
            width: record.extent.width,
            height: record.extent.height,
            reset_reason: record.reset_reason,
            timings_valid: self.ring.timer.is_some() as u32,
            submit_gpu_ms,
            source_sanitized_pixels: self
                .ring
                .counters
                .read_u32(self.ring.counter_offset(slot, 0) + SANITIZE_COUNTERS_OFFSET),
            source_invalid_geometry_pixels: self
                .ring
                .counters
                .read_u32(self.ring.counter_offset(slot, 0) + GEOMETRY_COUNTERS_OFFSET),
            extrapolation_count: record.extrapolations.len() as u32,
            extrapolations,
            device_memory_bytes: self.device_memory_bytes(),
            submit_stages_run: stage_bits(&record.submit.stages),
            shadow_history: record.shadow_history,
        };
        Ok(if ready {
            PatchexResult::Success
        } else {
            PatchexResult::NotReady
        })
    }

    fn device_memory_bytes(&self) -> u64 {
        self.work.as_ref().map_or(0, |w| w.size_bytes())
            + self.shadows.as_ref().map_or(0, |s| s.size_bytes())
            + self.output_staging.as_ref().map_or(0, |s| s.size_bytes())
            + self.ring.retired_bytes()
            + self.ring.counters.size_bytes()
            + self.placeholders.float.size_bytes()
            + self.placeholders.uint.size_bytes()
            + self.inpainting.as_ref().map_or(0, |i| i.size_bytes())
    }
}

/// A set of images holding `extent`, or `None` when `current` already does. A new set is at
/// least as large as the current one on both sides.
fn grown<const N: usize>(
    gpu: &Gpu,
    allocator: &mut Allocator,
    current: &Option<ImageSet<N>>,
    extent: vk::Extent2D,
    specs: &[ImageSpec; N],
) -> Result<Option<ImageSet<N>>> {
    let old = current.as_ref().map(|set| set.extent);
    if current.as_ref().is_some_and(|set| set.holds(extent)) {
        return Ok(None);
    }
    let size = vk::Extent2D {
        width: extent.width.max(old.map_or(0, |e| e.width)),
        height: extent.height.max(old.map_or(0, |e| e.height)),
    };
    ImageSet::new(gpu, allocator, size, specs).map(Some)
}

/// Hands `set`'s images to the ring at submit `serial`: the previous submit is the last whose
/// commands may use them.
fn retire<const N: usize>(ring: &mut FrameRing, set: ImageSet<N>, serial: u64) {
    for image in set.images {
        ring.retire(serial.saturating_sub(1), image);
    }
}

/// The stages that ran, as bits 1 << PATCHEX_STAGE_*.
fn stage_bits(stages: &[PatchexStage]) -> u32 {
    stages.iter().fold(0, |bits, stage| bits | 1 << stage)
}

/// Registers the reads of one instant's geometry and returns them as the pack pass's inputs.
/// Frame t's G-buffer packing inputs; the target's add its motion vectors.
fn pack_inputs(
    access: &mut EngineImageAccess,
    geometry: &GeometryInputs,
    placeholder: Texture,
    placeholder_uint: Texture,
) -> Result<pack_gbuffer::PackInputs> {
    Ok(pack_gbuffer::PackInputs {
        depth: access.read(&geometry.depth)?,
        normal: access.read(&geometry.normal)?,
        normal_encoding: geometry.normal_encoding,
        stencil: access.read_optional(geometry.stencil.as_ref())?,
        motion: None,
        placeholder,
        placeholder_uint,
    })
}

impl Drop for Context {
    fn drop(&mut self) {
        let gpu = &self.gpu;
        let work = self.work.take().map(|w| w.images);
        let shadows = self.shadows.take().map(|s| s.images);
        let staging = self.output_staging.take().map(|s| s.images);
        for mut image in work
            .into_iter()
            .flatten()
            .chain(shadows.into_iter().flatten())
            .chain(staging.into_iter().flatten())
        {
            image.destroy(gpu, &mut self.allocator);
        }
        self.placeholders.float.destroy(gpu, &mut self.allocator);
        self.placeholders.uint.destroy(gpu, &mut self.allocator);
        if let Some(mut inpainting) = self.inpainting.take() {
            inpainting.destroy(gpu, &mut self.allocator);
        }
        self.ring.destroy(gpu, &mut self.allocator);
        // SAFETY: every allocation was freed above; the allocator is not used again.
        unsafe { ManuallyDrop::drop(&mut self.allocator) };
    }
}

/// Timestamps around each stage of one region, and the list of stages that ran.
struct TimedRegion<'a> {
    ring: &'a FrameRing,
    device: &'a ash::Device,
    cmd: vk::CommandBuffer,
    slot: usize,
    region: usize,
    stages: Vec<u32>,
}

impl<'a> TimedRegion<'a> {
    fn begin(
        ring: &'a FrameRing,
        device: &'a ash::Device,
        cmd: vk::CommandBuffer,
        slot: usize,
        region: usize,
    ) -> Self {
        if let Some(timer) = &ring.timer {
            let (first, count) = ring.region_queries(slot, region);
            timer.reset(device, cmd, first, count);
        }
        Self {
            ring,
            device,
            cmd,
            slot,
            region,
            stages: Vec::new(),
        }
    }

    fn stage(&mut self, stage: PatchexStage, record: impl FnOnce()) {
        let query = self.ring.query(self.slot, self.region, stage);
        if let Some(timer) = &self.ring.timer {
            timer.write(self.device, self.cmd, query, false);
        }
        record();
        if let Some(timer) = &self.ring.timer {
            timer.write(self.device, self.cmd, query, true);
        }
        self.stages.push(stage);
    }
}
