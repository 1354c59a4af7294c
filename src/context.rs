//! One plugin context: the engine's device, the plugin's pipelines and images, the frame ring,
//! and the state between `submit` (frame t) and `extrapolate` (its target instants).

use std::mem::ManuallyDrop;
use std::sync::Arc;

use ash::vk;
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};

use crate::abi::*;
use crate::camera::Camera;
use crate::error::{bail, PatchexResult, Result};
use crate::inputs::{self, GeometryInputs, SourceInputs, TargetInputs};
use crate::passes::segmentation::{self, SegmentationSettings};
use crate::passes::warp::WarpSettings;
use crate::passes::{
    demodulate, diagnostics, lbp, pack_gbuffer, remodulate, warp, Pipelines, Texture,
    SANITIZE_COUNTER_BYTES,
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
const OBJECT_TABLE_OFFSET: u64 = 512;
pub const COUNTER_BYTES: u64 = OBJECT_TABLE_OFFSET + segmentation::TABLE_BYTES;

/// The plugin's working images, all at one extent (the largest frame seen so far).
struct WorkImages {
    extent: vk::Extent2D,
    source_shading: OwnedImage,
    source_geometry: OwnedImage,
    source_normal_id: OwnedImage,
    target_geometry: OwnedImage,
    target_normal_id: OwnedImage,
    warped: OwnedImage,
    /// Region of each target pixel (segmentation::REGION_*).
    regions: OwnedImage,
    lbp: OwnedImage,
}

impl WorkImages {
    /// Name and format of each image, in field order.
    const SPECS: [(&'static str, vk::Format); 8] = [
        ("patchex source shading", vk::Format::R32G32B32A32_SFLOAT),
        ("patchex source geometry", vk::Format::R32G32B32A32_SFLOAT),
        ("patchex source normal+id", vk::Format::R16G16B16A16_SFLOAT),
        ("patchex target geometry", vk::Format::R32G32B32A32_SFLOAT),
        ("patchex target normal+id", vk::Format::R16G16B16A16_SFLOAT),
        ("patchex warped shading", vk::Format::R32G32B32A32_SFLOAT),
        ("patchex regions", vk::Format::R32_UINT),
        ("patchex lbp", vk::Format::R32_SFLOAT),
    ];

    /// Vulkan requires storage-image support for every one of these formats, but a device that
    /// lacks it must be refused at creation rather than fail later.
    fn check_formats(gpu: &Gpu) -> Result<()> {
        let needed = vk::FormatFeatureFlags::STORAGE_IMAGE | vk::FormatFeatureFlags::SAMPLED_IMAGE;
        for (name, format) in Self::SPECS {
            let features = gpu.format_features(format);
            if !features.contains(needed) {
                bail!(
                    ErrorMissingDeviceFeature,
                    "the device lacks {:?} for {format:?}, the format of the {name} image",
                    needed & !features
                );
            }
        }
        Ok(())
    }

    fn new(gpu: &Gpu, allocator: &mut Allocator, extent: vk::Extent2D) -> Result<Self> {
        let mut made: Vec<OwnedImage> = Vec::with_capacity(Self::SPECS.len());
        for (name, format) in Self::SPECS {
            match OwnedImage::new(
                gpu,
                allocator,
                name,
                format,
                extent,
                vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::STORAGE,
            ) {
                Ok(image) => made.push(image),
                Err(error) => {
                    for mut image in made {
                        image.destroy(gpu, allocator);
                    }
                    return Err(error);
                }
            }
        }
        let [source_shading, source_geometry, source_normal_id, target_geometry, target_normal_id, warped, regions, lbp] =
            <[OwnedImage; 8]>::try_from(made)
                .ok()
                .expect("eight images");
        Ok(Self {
            extent,
            source_shading,
            source_geometry,
            source_normal_id,
            target_geometry,
            target_normal_id,
            warped,
            regions,
            lbp,
        })
    }

    fn into_vec(self) -> Vec<OwnedImage> {
        vec![
            self.source_shading,
            self.source_geometry,
            self.source_normal_id,
            self.target_geometry,
            self.target_normal_id,
            self.warped,
            self.regions,
            self.lbp,
        ]
    }

    fn all(&self) -> [&OwnedImage; 8] {
        [
            &self.source_shading,
            &self.source_geometry,
            &self.source_normal_id,
            &self.target_geometry,
            &self.target_normal_id,
            &self.warped,
            &self.regions,
            &self.lbp,
        ]
    }

    fn all_mut(&mut self) -> [&mut OwnedImage; 8] {
        [
            &mut self.source_shading,
            &mut self.source_geometry,
            &mut self.source_normal_id,
            &mut self.target_geometry,
            &mut self.target_normal_id,
            &mut self.warped,
            &mut self.regions,
            &mut self.lbp,
        ]
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
    extent: vk::Extent2D,
    camera: Camera,
}

/// Extension structs chained on a create info or an extrapolate call, validated.
#[derive(Default)]
pub struct Extensions {
    pub warp: Option<WarpSettings>,
    pub segmentation: Option<SegmentationSettings>,
    pub diagnostics: Option<PatchexImage>,
}

pub struct Context {
    gpu: Gpu,
    allocator: ManuallyDrop<Allocator>,
    pipelines: Arc<Pipelines>,
    ring: FrameRing,
    placeholders: Placeholders,
    work: Option<WorkImages>,
    max_extent: vk::Extent2D,
    default_warp: WarpSettings,
    default_segmentation: SegmentationSettings,
    source: Option<SourceFrame>,
}

impl Context {
    /// # Safety
    /// The handles in `info` must be live objects of one Vulkan instance.
    pub unsafe fn new(info: &PatchexCreateInfo, defaults: Extensions) -> Result<Self> {
        if info.preset != PATCHEX_PRESET_WARP_ONLY {
            bail!(
                ErrorInvalidArgument,
                "PatchexCreateInfo.preset {} is not available; this build has PATCHEX_PRESET_WARP_ONLY (0)",
                info.preset
            );
        }
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
        WorkImages::check_formats(&gpu)?;
        let mut allocator = Allocator::new(&AllocatorCreateDesc {
            instance: gpu.instance.clone(),
            device: gpu.device.clone(),
            physical_device: gpu.physical_device,
            debug_settings: Default::default(),
            buffer_device_address: false,
            allocation_sizes: Default::default(),
        })?;
        let pipelines = Pipelines::shared(&gpu)?;
        let set_layouts: Vec<_> = pipelines.all().iter().map(|p| p.set_layout).collect();
        let ring = FrameRing::new(
            &gpu,
            &mut allocator,
            info.frames_in_flight as usize,
            &set_layouts,
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
            max_extent: vk::Extent2D {
                width: info.max_width,
                height: info.max_height,
            },
            default_warp: defaults.warp.unwrap_or_default(),
            default_segmentation: defaults.segmentation.unwrap_or_default(),
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
        if inputs.frame_index <= previous.frame_index {
            bail!(
                ErrorOutOfOrder,
                "PatchexFrameDesc.frame_index {} does not increase (previous {})",
                inputs.frame_index,
                previous.frame_index
            );
        }
        Ok(if inputs.reset {
            PATCHEX_RESET_REQUESTED
        } else if inputs.frame_index != previous.frame_index + 1 {
            PATCHEX_RESET_FRAME_GAP
        } else {
            PATCHEX_RESET_NONE
        })
    }

    /// Grows the working images to hold `extent`; the old ones wait out the frames in flight.
    fn ensure_work_images(&mut self, extent: vk::Extent2D, frame_index: u64) -> Result<()> {
        let current = self.work.as_ref().map(|w| w.extent);
        if let Some(current) = current {
            if current.width >= extent.width && current.height >= extent.height {
                return Ok(());
            }
        }
        let grown = vk::Extent2D {
            width: extent.width.max(current.map_or(0, |c| c.width)),
            height: extent.height.max(current.map_or(0, |c| c.height)),
        };
        let work = WorkImages::new(&self.gpu, &mut self.allocator, grown)?;
        if let Some(old) = self.work.replace(work) {
            // The previous frame is the last one whose commands may use the old images.
            for image in old.into_vec() {
                self.ring.retire(frame_index.saturating_sub(1), image);
            }
        }
        Ok(())
    }

    fn placeholder_textures(&self) -> (Texture, Texture) {
        (
            (&self.placeholders.float).into(),
            (&self.placeholders.uint).into(),
        )
    }

    /// Records frame t's demodulation and G-buffer packing into `cmd`.
    pub fn submit(&mut self, cmd: vk::CommandBuffer, desc: &PatchexFrameDesc) -> Result<()> {
        self.check_queue_family(desc.queue_family_index, "PatchexFrameDesc")?;
        let inputs = inputs::source(&self.gpu, desc, self.max_extent)?;
        let reset_reason = self.reset_reason(&inputs)?;
        let (placeholder, placeholder_uint) = self.placeholder_textures();
        let mut access = EngineImageAccess::default();
        let demodulate_inputs = demodulate::DemodulateInputs {
            color: access.read(&inputs.color)?,
            base_color: access.read(&inputs.base_color)?,
            material: access.read_optional(inputs.material.as_ref())?,
            placeholder,
        };
        let pack_inputs = pack_inputs(&mut access, &inputs.geometry, placeholder_uint)?;

        self.ring
            .collect(&self.gpu, &mut self.allocator, inputs.frame_index);
        self.ensure_work_images(inputs.extent, inputs.frame_index)?;

        // Everything is validated and allocated: from here on the call cannot fail.
        let slot = self.ring.slot_of(inputs.frame_index);
        let device = &self.gpu.device;
        let work = self.work.as_mut().expect("allocated above");
        let mut owned: Vec<&mut OwnedImage> = work.all_mut().into_iter().collect();
        owned.push(&mut self.placeholders.float);
        owned.push(&mut self.placeholders.uint);
        barriers::initialize_owned(device, cmd, &mut owned);
        let work = self.work.as_ref().expect("allocated above");
        access.acquire(device, cmd);
        self.ring.clear_counters(device, cmd, slot, 0);
        barriers::compute_to_compute(device, cmd, true);

        let mut timed = TimedRegion::begin(&self.ring, device, cmd, slot, 0);
        timed.stage(PATCHEX_STAGE_DEMODULATE, || {
            demodulate::record(
                self.pipelines.get(Pipelines::DEMODULATE),
                device,
                cmd,
                self.ring.descriptor_set(slot, 0, Pipelines::DEMODULATE),
                inputs.extent,
                &demodulate_inputs,
                &work.source_shading,
                &self
                    .ring
                    .counter_range(slot, 0, SANITIZE_COUNTERS_OFFSET, SANITIZE_COUNTER_BYTES),
            )
        });
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
                    geometry: &work.source_geometry,
                    normal_id: &work.source_normal_id,
                },
            )
        });
        let stages = timed.stages;
        barriers::compute_to_host(device, cmd);
        access.release(device, cmd);

        self.ring.slots[slot].record = Some(FrameRecord {
            frame_index: inputs.frame_index,
            extent: inputs.extent,
            reset_reason,
            submit: RegionRecord {
                stages,
                alpha: 0.0,
                camera_cut: false,
            },
            extrapolations: Vec::new(),
        });
        self.source = Some(SourceFrame {
            frame_index: inputs.frame_index,
            extent: inputs.extent,
            camera: inputs.geometry.camera,
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
        let slot = self.ring.slot_of(source.frame_index);
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
        let pack_inputs = pack_inputs(&mut access, &inputs.geometry, placeholder_uint)?;
        let base_color = access.read(&inputs.base_color)?;
        let material = access.read_optional(inputs.material.as_ref())?;
        let motion = access.read(&inputs.motion_vectors)?;
        let output = access.write(&inputs.output)?;
        let diagnostics_image = match &extensions.diagnostics {
            Some(image) => Some(access.write(&ImportedImage::import_required(
                &self.gpu,
                image,
                &ImageRole::output("PatchexDiagnostics.image"),
                inputs.extent,
            )?)?),
            None => None,
        };

        let warp_settings = extensions.warp.unwrap_or(self.default_warp);
        let segmentation_settings = extensions.segmentation.unwrap_or(self.default_segmentation);
        let jitter_delta = (inputs.geometry.camera.jitter - source.camera.jitter).into();
        let warp_params = warp_settings.params(
            inputs.extent,
            &inputs.geometry.camera,
            jitter_delta,
            inputs.geometry.motion_vector_scale,
        );

        // Everything is validated: from here on the call cannot fail.
        let region = 1 + done;
        let device = &self.gpu.device;
        let work = self
            .work
            .as_ref()
            .expect("a submitted frame allocated the work images");
        let counters =
            self.ring
                .counter_range(slot, region, WARP_COUNTERS_OFFSET, warp::COUNTER_BYTES);
        let object_table =
            self.ring
                .counter_range(slot, region, OBJECT_TABLE_OFFSET, segmentation::TABLE_BYTES);
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
                    geometry: &work.target_geometry,
                    normal_id: &work.target_normal_id,
                },
            )
        });
        barriers::compute_to_compute(device, cmd, false);
        let warp_index = Pipelines::warp(warp_settings.kind);
        timed.stage(PATCHEX_STAGE_WARP, || {
            warp::record(
                self.pipelines.get(warp_index),
                device,
                cmd,
                self.ring.descriptor_set(slot, region, warp_index),
                &warp_params,
                &warp::WarpInputs {
                    source_shading: &work.source_shading,
                    source_geometry: &work.source_geometry,
                    source_normal_id: &work.source_normal_id,
                    target_geometry: &work.target_geometry,
                    target_normal_id: &work.target_normal_id,
                    motion,
                },
                &work.warped,
                &counters,
            )
        });
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
                    target_normal_id: &work.target_normal_id,
                    motion,
                    motion_scale: inputs.geometry.motion_vector_scale,
                },
                &object_table,
                &work.regions,
            )
        });
        timed.stage(PATCHEX_STAGE_LBP, || {
            lbp::record(
                self.pipelines.get(Pipelines::LBP),
                device,
                cmd,
                self.ring.descriptor_set(slot, region, Pipelines::LBP),
                inputs.extent,
                &work.warped,
                &work.lbp,
            )
        });
        barriers::compute_to_compute(device, cmd, false);
        timed.stage(PATCHEX_STAGE_REMODULATE, || {
            remodulate::record(
                self.pipelines.get(Pipelines::REMODULATE),
                device,
                cmd,
                self.ring
                    .descriptor_set(slot, region, Pipelines::REMODULATE),
                inputs.extent,
                &remodulate::RemodulateInputs {
                    shading: (&work.warped).into(),
                    base_color,
                    material,
                    placeholder,
                },
                output,
                &self.ring.counter_range(
                    slot,
                    region,
                    SANITIZE_COUNTERS_OFFSET,
                    SANITIZE_COUNTER_BYTES,
                ),
            )
        });
        if let Some(diagnostics_image) = diagnostics_image {
            timed.stage(PATCHEX_STAGE_DIAGNOSTICS, || {
                diagnostics::record(
                    self.pipelines.get(Pipelines::WRITE_DIAGNOSTICS),
                    device,
                    cmd,
                    self.ring
                        .descriptor_set(slot, region, Pipelines::WRITE_DIAGNOSTICS),
                    inputs.extent,
                    &diagnostics::DiagnosticsInputs {
                        warped: &work.warped,
                        regions: &work.regions,
                        lbp: &work.lbp,
                    },
                    diagnostics_image,
                )
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
        let slot = self.ring.slot_of(frame_index);
        let Some(record) = self.ring.slots[slot]
            .record
            .as_ref()
            .filter(|r| r.frame_index == frame_index)
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
            if region_record.camera_cut {
                stats.render_instead_reasons |= PATCHEX_RENDER_INSTEAD_CAMERA_CUT;
            }
            if stats.hole_fraction > PATCHEX_MAX_TRUSTED_HOLE_FRACTION {
                stats.render_instead_reasons |= PATCHEX_RENDER_INSTEAD_DISOCCLUSION;
            }
            stats.fi_fraction = segmented.fi_pixels as f32 / pixels;
            stats.near_be_fraction = segmented.near_be_pixels as f32 / pixels;
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
            extrapolation_count: record.extrapolations.len() as u32,
            extrapolations,
            device_memory_bytes: self.device_memory_bytes(),
        };
        Ok(if ready {
            PatchexResult::Success
        } else {
            PatchexResult::NotReady
        })
    }

    fn device_memory_bytes(&self) -> u64 {
        let work: u64 = self
            .work
            .as_ref()
            .map_or(0, |w| w.all().iter().map(|image| image.size_bytes()).sum());
        work + self.ring.retired_bytes()
            + self.ring.counters.size_bytes()
            + self.placeholders.float.size_bytes()
            + self.placeholders.uint.size_bytes()
    }
}

/// Registers the reads of one instant's geometry and returns them as the pack pass's inputs.
fn pack_inputs(
    access: &mut EngineImageAccess,
    geometry: &GeometryInputs,
    placeholder_uint: Texture,
) -> Result<pack_gbuffer::PackInputs> {
    Ok(pack_gbuffer::PackInputs {
        depth: access.read(&geometry.depth)?,
        normal: access.read(&geometry.normal)?,
        normal_encoding: geometry.normal_encoding,
        stencil: access.read_optional(geometry.stencil.as_ref())?,
        placeholder_uint,
    })
}

impl Drop for Context {
    fn drop(&mut self) {
        let gpu = &self.gpu;
        if let Some(work) = self.work.take() {
            for mut image in work.into_vec() {
                image.destroy(gpu, &mut self.allocator);
            }
        }
        self.placeholders.float.destroy(gpu, &mut self.allocator);
        self.placeholders.uint.destroy(gpu, &mut self.allocator);
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
