//! `patchex_extrapolate`: one target instant from frame t. The target's G-buffer packing, the
//! warp of frame t's shading (and of its shadow layer), segmentation, the networks on their
//! patches, remodulation into the engine's output, and the diagnostics.

use ash::vk;

use crate::abi::*;
use crate::context::Context;
use crate::error::{bail, PatchexResult, Result};
use crate::frame::counters;
use crate::frame::images::{OutputStaging, ShadowImages, WorkImages};
use crate::frame::recorder::TimedRegion;
use crate::frame::settings::Extensions;
use crate::frame::submit::pack_inputs;
use crate::inputs::{self, TargetInputs};
use crate::passes::inpaint;
use crate::passes::{
    diagnostics, lbp, pack_gbuffer, pack_output, remodulate, segmentation, warp, Pipelines,
    Texture, SANITIZE_COUNTER_BYTES,
};
use crate::vk::barriers::{self, EngineImageAccess};
use crate::vk::frame_ring::RegionRecord;
use crate::vk::image::{ImageRole, ImportedImage, OwnedImage};

impl Context {
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
        let (placeholder, placeholder_uint) = self.images.placeholders();
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
        let run_networks = extensions.networks.unwrap_or(self.defaults.networks);
        let warp_settings = extensions.warp.unwrap_or(self.defaults.warp);
        let segmentation_settings = extensions
            .segmentation
            .unwrap_or(self.defaults.segmentation);
        let jitter_delta = (inputs.geometry.camera.jitter - source.camera.jitter).into();
        let warp_params = warp_settings.params(
            inputs.extent,
            &inputs.geometry.camera,
            jitter_delta,
            inputs.geometry.motion_vector_scale,
        );

        if inputs.output.written_by_copy {
            self.images.ensure_output_staging(
                &self.gpu,
                &mut self.allocator,
                &mut self.ring,
                source.serial,
            )?;
        }

        // Everything is validated and allocated: from here on the call cannot fail.
        let region = 1 + done;
        let device = &self.gpu.device;
        let work = self
            .images
            .work
            .as_ref()
            .expect("a submitted frame allocated the work images");
        let object_table = self.ring.counter_range(
            slot,
            region,
            counters::OBJECT_TABLE,
            segmentation::TABLE_BYTES,
        );
        let staging = match self.images.output_staging.as_mut() {
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
                        counters::GEOMETRY,
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
                counters::WARP,
            )
        });
        let shadows = self.images.shadows.as_ref().filter(|_| source.has_shadows);
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
                    counters::SURFACE_LAYER,
                );
                record_warp(
                    Pipelines::WARP_OCCLUSION_MOTION,
                    Pipelines::SHADOW_WARP_SET,
                    &params,
                    layer,
                    (&shadows[ShadowImages::FLOW]).into(),
                    &shadows[ShadowImages::WARPED_LAYER],
                    counters::SHADOW_WARP,
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
            let patches = self.ring.counter_range(
                slot,
                region,
                counters::PATCHES,
                inpaint::PATCH_SLOTS_BYTES,
            );
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
                &self
                    .ring
                    .counter_range(slot, region, counters::SANITIZE, SANITIZE_COUNTER_BYTES),
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
}
