//! `patchex_extrapolate`: one target instant from frame t. The target's G-buffer packing, the
//! warp of frame t's shading (and of its shadow layer), segmentation, the networks on their
//! patches, remodulation into the engine's output, and the diagnostics.

use ash::vk;

use crate::abi::*;
use crate::context::Context;
use crate::error::{bail, PatchexResult, Result};
use crate::frame::counters;
use crate::frame::images::{AnalysisImages, Growth, OutputStaging, ShadowImages, WorkImages};
use crate::frame::settings::Extensions;
use crate::frame::submit::engine_gbuffer;
use crate::inputs::{self, TargetInputs};
use crate::passes::inpaint;
use crate::passes::{
    diagnostics, fill_holes, lbp, pack_output, remodulate, segmentation, warp, PipelineId,
    Pipelines, RegionPasses, Texture, SANITIZE_COUNTER_BYTES,
};
use crate::vk::barriers::EngineImageAccess;
use crate::vk::frame_ring::RegionRecord;
use crate::vk::image::{ImageRole, ImportedImage};
use crate::vk::recorder::Recorder;

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
        let target_gbuffer = engine_gbuffer(&mut access, &inputs.geometry)?;
        let base_color = access.read(&inputs.base_color)?;
        let material = access.read_optional(inputs.material.as_ref())?;
        let output = access.write(&inputs.output)?;
        let mut import_diagnostics = |image: Option<&PatchexImage>, name| {
            image
                .map(|image| {
                    let role = ImageRole::diagnostics(name);
                    access.write(&ImportedImage::import_required(
                        &self.gpu,
                        image,
                        &role,
                        inputs.extent,
                    )?)
                })
                .transpose()
        };
        let diagnostics_image =
            import_diagnostics(extensions.diagnostics.as_ref(), "PatchexDiagnostics.image")?;
        let shadow_diagnostics_image = import_diagnostics(
            extensions.shadow_diagnostics.as_ref(),
            "PatchexShadowDiagnostics.image",
        )?;
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

        let mut growth = Growth {
            gpu: &self.gpu,
            allocator: &mut self.allocator,
            ring: &mut self.ring,
            serial: source.serial,
        };
        if inputs.output.written_by_copy {
            self.images.ensure_output_staging(&mut growth)?;
        }
        // The regions and the LBP map, for the networks and the diagnostics only.
        let analyse = self.inpainting.is_some() || diagnostics_image.is_some();
        if analyse {
            self.images.ensure_analysis(&mut growth)?;
        }

        // Everything is validated and allocated: from here on the call cannot fail.
        let region = 1 + done;
        let mut rec = Recorder::new(&self.gpu.device, cmd).skipping(self.test_fault);
        let staging = match self.images.output_staging.as_mut() {
            Some(staging) if inputs.output.written_by_copy => {
                let [frame, packed] = &mut staging.images;
                rec.initialize(&mut [frame, packed]);
                Some(&*staging)
            }
            _ => None,
        };
        let analysis = match self.images.analysis.as_mut() {
            Some(analysis) if analyse => {
                let [regions, lbp] = &mut analysis.images;
                rec.initialize(&mut [regions, lbp]);
                Some(&*analysis)
            }
            _ => None,
        };
        // The warp writes its shading here; the later passes refine it in place.
        let frame: Texture = staging.map_or(output, |s| (&s[OutputStaging::FRAME]).into());
        rec.acquire(&access);
        rec.fill_zero(&self.ring.region_counters(slot, region));
        let cameras = self
            .ring
            .counter_range(slot, region, counters::CAMERAS, warp::CAMERAS_BYTES);
        rec.update(
            &cameras,
            &warp::cameras(&source.camera, &target_gbuffer, inputs.extent),
        );
        let deferred_holes =
            [counters::DEFERRED_HOLES, counters::SURFACE_DEFERRED_HOLES].map(|offset| {
                let range =
                    self.ring
                        .counter_range(slot, region, offset, warp::DEFERRED_HOLES_BYTES);
                rec.update(&range, &warp::NO_DEFERRED_HOLES);
                range
            });
        let mut rec = rec.timed(&self.ring, slot, region);
        let passes = RegionPasses {
            pipelines: &self.pipelines,
            ring: &self.ring,
            slot,
            region,
        };
        let counters = |offset, bytes| self.ring.counter_range(slot, region, offset, bytes);
        let object_table = counters(counters::OBJECT_TABLE, segmentation::TABLE_BYTES);
        let work = self
            .images
            .work
            .as_ref()
            .expect("a submitted frame allocated the work images");
        let shadows = self.images.shadows.as_ref().filter(|_| source.has_shadows);

        // Every warp of this extrapolation reads frame t's packed G-buffer and the target's. The
        // G-buffer warp lists its holes in `hole_list`'s image with its count in
        // `deferred_holes[n]`, and the fill's n-th set fills them.
        let warp_pipeline = Pipelines::warp(warp_settings.kind);
        let lists_holes = warp_pipeline == PipelineId::WarpGbuffer;
        // The nearest-texel fill is the warp's own; only the default defers its holes.
        let fills_holes = lists_holes && warp_settings.hole_fill == PATCHEX_HOLE_FILL_BACKGROUND;
        let warp_inputs = |source_shading, motion| warp::WarpInputs {
            source_shading,
            source_depth: &work[WorkImages::SOURCE_DEPTH],
            source_normal_id: &work[WorkImages::SOURCE_NORMAL_ID],
            target: &target_gbuffer,
            motion,
            cameras: &cameras,
            placeholder,
            placeholder_uint,
        };
        let hole_list = |n: usize| warp::HoleList {
            list: &work[WorkImages::HOLE_LIST],
            deferred: &deferred_holes[n],
            fill: passes.nth(PipelineId::FillHoles, n),
        };
        // With nothing to run between the warp and the output (no shadow layers, networks or
        // diagnostics), the warp remodulates as it writes, and the frame is read and written once.
        let remodulate_in_warp = shadows.is_none() && !analyse;
        let remodulation = warp::Remodulation {
            base_color,
            material,
        };
        let frame_store = if remodulate_in_warp {
            warp::Store::Remodulated(&remodulation)
        } else {
            warp::Store::Shading
        };
        let frame_inputs = warp_inputs(&work[WorkImages::SOURCE_SHADING], motion);
        let frame_counters = counters(counters::WARP, warp::COUNTER_BYTES);
        let frame_holes = lists_holes.then(|| hole_list(0));
        rec.stage(PATCHEX_STAGE_WARP, |rec| {
            warp::record(
                rec,
                passes.nth(warp_pipeline, 0),
                &warp_params,
                &frame_inputs,
                frame_store,
                frame,
                &frame_counters,
                frame_holes.as_ref(),
            )
        });
        if let Some(holes) = frame_holes.as_ref().filter(|_| fills_holes) {
            rec.stage(PATCHEX_STAGE_FILL_HOLES, |rec| {
                fill_holes::record(
                    rec,
                    &warp_params,
                    &frame_inputs,
                    frame_store,
                    frame,
                    &frame_counters,
                    holes,
                )
            });
        }
        if let Some(shadows) = shadows {
            // The shadow layer moved by the mask's flow scaled to the target instant; then
            // through the frame's own warp (where that warp put frame t's shadow), which turns
            // the moved layer into the shadows' share at the target in place.
            let params =
                warp_settings.shadow_params(inputs.extent, &inputs.geometry.camera, inputs.alpha);
            let layer = &shadows[ShadowImages::LAYER];
            let share = &shadows[ShadowImages::SHADOW_SHARE];
            rec.stage(PATCHEX_STAGE_SHADOW_WARP, |rec| {
                if !source.shadows_tracked {
                    // No frame t-1 to measure a drift from: the shadows stay on their receivers,
                    // where the frame's warp carried them, and change nothing. (Moved by a zero
                    // flow instead, they would stay put on the screen and slide across the
                    // ground under a moving camera.)
                    rec.clear(share);
                    return;
                }
                let flow_warp = PipelineId::WarpOcclusionMotion;
                warp::record(
                    rec,
                    passes.nth(flow_warp, if warp_pipeline == flow_warp { 2 } else { 0 }),
                    &params,
                    &warp_inputs(layer, (&shadows[ShadowImages::FLOW]).into()),
                    warp::Store::Shading,
                    share.into(),
                    &counters(counters::SHADOW_WARP, warp::COUNTER_BYTES),
                    None,
                );
                // The frame's fill has read its holes: the list's image takes the layer's.
                let layer_inputs = warp_inputs(layer, motion);
                let layer_counters = counters(counters::SURFACE_LAYER, warp::COUNTER_BYTES);
                let layer_holes = lists_holes.then(|| hole_list(1));
                warp::record(
                    rec,
                    passes.nth(warp_pipeline, 1),
                    &warp_params,
                    &layer_inputs,
                    warp::Store::ShadowShare,
                    share.into(),
                    &layer_counters,
                    layer_holes.as_ref(),
                );
                if let Some(holes) = layer_holes.as_ref().filter(|_| fills_holes) {
                    fill_holes::record(
                        rec,
                        &warp_params,
                        &layer_inputs,
                        warp::Store::ShadowShare,
                        share.into(),
                        &layer_counters,
                        holes,
                    );
                }
            });
        }
        rec.stage(PATCHEX_STAGE_SEGMENT, |rec| {
            segmentation::record(
                rec,
                &segmentation::SegmentationPasses {
                    object_bounds: passes.get(PipelineId::ObjectBounds),
                    grow_regions: passes.get(PipelineId::GrowRegions),
                    region_masks: passes.get(PipelineId::RegionMasks),
                },
                inputs.extent,
                &segmentation_settings,
                &segmentation::SegmentationInputs {
                    target_stencil: target_gbuffer.stencil,
                    motion,
                    motion_scale: inputs.geometry.motion_vector_scale,
                    placeholder_uint,
                },
                &object_table,
                analysis.map(|a| &a[AnalysisImages::REGIONS]),
            )
        });
        if let Some(analysis) = analysis {
            rec.stage(PATCHEX_STAGE_LBP, |rec| {
                lbp::record(
                    rec,
                    passes.get(PipelineId::Lbp),
                    inputs.extent,
                    frame,
                    &analysis[AnalysisImages::LBP],
                )
            });
        }
        if let Some((inpainting, analysis)) = self.inpainting.as_ref().zip(analysis) {
            let patches = counters(counters::PATCHES, inpaint::PATCH_SLOTS_BYTES);
            rec.stage(PATCHEX_STAGE_INFERENCE, |rec| {
                inpaint::record_plan(
                    rec,
                    passes.get(PipelineId::PlanPatches),
                    inputs.extent,
                    &inpaint::PatchPlan {
                        levels: inpainting.levels(run_networks.running()),
                        whole_frame: run_networks.whole_frame,
                        divisor: run_networks.divisor,
                        max_patch_side: inpainting.max_patch_side,
                    },
                    &object_table,
                    &patches,
                );
                let runs = inpainting.runs(&passes, &patches);
                inpaint::record(
                    rec,
                    &inpaint::FrameInputs {
                        warped: frame,
                        material,
                        lbp: (&analysis[AnalysisImages::LBP]).into(),
                        placeholder,
                        frame_extent: inputs.extent,
                    },
                    &runs,
                );
            });
            rec.stage(PATCHEX_STAGE_BLEND, |rec| {
                inpaint::record_blend(
                    rec,
                    passes.get(PipelineId::BlendPatches),
                    &inpaint::BlendInputs {
                        regions: &analysis[AnalysisImages::REGIONS],
                        networks: inpainting.tensors(),
                        whole_frame: run_networks.whole_frame,
                        correct_valid_pixels: run_networks.correct_valid_pixels,
                    },
                    &patches,
                    frame,
                )
            });
        }
        // Before remodulation, which turns the frame's warped shading into the output.
        let shadow_diagnostics = shadow_diagnostics_image.zip(shadows);
        if diagnostics_image.is_some() || shadow_diagnostics.is_some() {
            rec.stage(PATCHEX_STAGE_DIAGNOSTICS, |rec| {
                if let Some(image) = diagnostics_image {
                    let analysis = analysis.expect("made for the diagnostics");
                    let sources = diagnostics::frame_sources(
                        frame,
                        &analysis[AnalysisImages::REGIONS],
                        &analysis[AnalysisImages::LBP],
                    );
                    let pass = passes.get(PipelineId::WriteDiagnostics);
                    diagnostics::record(rec, pass, inputs.extent, sources, image);
                }
                if let Some((image, shadows)) = shadow_diagnostics {
                    let sources = diagnostics::shadow_sources(
                        &shadows[ShadowImages::FLOW],
                        &shadows[ShadowImages::LAYER],
                        &shadows[ShadowImages::SHADOW_SHARE],
                    );
                    let pass = passes.get(PipelineId::WriteShadowDiagnostics);
                    diagnostics::record(rec, pass, inputs.extent, sources, image);
                }
            });
        }
        if !remodulate_in_warp {
            rec.stage(PATCHEX_STAGE_REMODULATE, |rec| {
                remodulate::record(
                    rec,
                    passes.get(PipelineId::Remodulate),
                    inputs.extent,
                    &remodulate::RemodulateInputs {
                        base_color,
                        material,
                        shadow_share: shadows.map(|s| (&s[ShadowImages::SHADOW_SHARE]).into()),
                        placeholder,
                    },
                    frame,
                    &counters(counters::SANITIZE, SANITIZE_COUNTER_BYTES),
                )
            });
        }
        if let Some(staging) = staging {
            let encoding = pack_output::encoding(inputs.output.format)
                .expect("every copied output format has an encoding");
            rec.stage(PATCHEX_STAGE_PACK_OUTPUT, |rec| {
                pack_output::record(
                    rec,
                    passes.get(PipelineId::PackOutput),
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
        let stages = rec.finish(
            &access,
            &self.ring.region_counters(slot, region),
            self.ring.readback.buffer,
        );

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
