//! Each call's stages, in the order of `passes::STAGES`. `Context::submit` and
//! `Context::extrapolate` check the call and allocate what it needs into a plan
//! ([`SubmitPlan`], [`ExtrapolationPlan`]); [`record_submit`] and [`record`] list the stages;
//! each stage is one function that records its passes from the plan, and leaves out what the
//! plan says it does not run.

use ash::vk;

use crate::abi::*;
use crate::camera::PixelRays;
use crate::frame::counters;
use crate::frame::images::{
    AnalysisImages, DiagnosticImages, FlowAtlases, HighlightImages, OutputStaging, ShadowImages,
    TranslucencyImages, WorkImages,
};
use crate::frame::settings::NetworkSwitches;
use crate::passes::inpaint::{self, Inpainting};
use crate::passes::pack_gbuffer::EngineGbuffer;
use crate::passes::segmentation::{self, SegmentationSettings};
use crate::passes::shadow_flow::{self, FlowSettings};
use crate::passes::warp::{self, Remodulation, Store, WarpSettings};
use crate::passes::{
    demodulate, diagnostics, fill_holes, highlights, lbp, pack_gbuffer, pack_output, remodulate,
    separate_shadows, target_shadows, translucency, CounterRange, PipelineId, Pipelines,
    RegionPasses, Texture, SANITIZE_COUNTER_BYTES,
};
use crate::shaders::PushConstants;
use crate::vk::image::{ImportedImage, OwnedImage};
use crate::vk::recorder::Recorder;

/// Everything frame t's submit records with: its inputs, images and settings, resolved.
pub struct SubmitPlan<'a> {
    pub extent: vk::Extent2D,
    pub passes: RegionPasses<'a>,
    pub work: &'a WorkImages,
    pub gbuffer: &'a EngineGbuffer,
    pub demodulation: demodulate::DemodulateInputs,
    /// With a shadow input: what the separation reads, and the shadow images.
    pub separation: Option<(&'a separate_shadows::SeparationInputs, &'a ShadowImages)>,
    /// The flow's atlases, once a frame's flow has run.
    pub flow_atlases: Option<&'a FlowAtlases>,
    /// Which of the alternating flow images is frame t's.
    pub shadow_current: usize,
    pub flow: FlowSettings,
    /// With frame t-1 to track from: static receivers' motion into it, where the flow starts.
    pub reprojection: Option<PixelRays>,
    /// Frame t's shadows are separated from its shading (`submit::shadows_separated`).
    pub separates: bool,
    /// With a sun: what frame t's highlights are taken out with, and where its visibility is kept.
    pub highlights: Option<(&'a highlights::SourceHighlights<'a>, &'a HighlightImages)>,
    /// With a translucency input: what it is taken apart with, and where its layer is kept.
    pub translucency: Option<(
        &'a translucency::SourceTranslucency<'a>,
        &'a TranslucencyImages,
    )>,
    pub placeholder: Texture,
    pub placeholder_uint: Texture,
}

/// Records frame t's stages in order.
pub fn record_submit(rec: &mut Recorder, plan: &SubmitPlan) {
    pack_source(rec, plan);
    demodulate(rec, plan);
    shadow_flow(rec, plan);
}

fn pack_source(rec: &mut Recorder, plan: &SubmitPlan) {
    rec.stage(PATCHEX_STAGE_PACK_SOURCE_GBUFFER, |rec| {
        pack_gbuffer::record(
            rec,
            plan.passes.get(PipelineId::PackGbuffer),
            plan.extent,
            plan.gbuffer,
            plan.placeholder_uint,
            &pack_gbuffer::PackOutputs {
                depth: &plan.work[WorkImages::SOURCE_DEPTH],
                normal_id: &plan.work[WorkImages::SOURCE_NORMAL_ID],
                counters: plan
                    .passes
                    .counters(counters::GEOMETRY, pack_gbuffer::COUNTER_BYTES),
            },
        )
    });
}

/// Frame t's colour over its modulation; with a shadow input, also the shadow layer apart; with
/// a sun, less its highlights; with a translucency input, less what is drawn over its surfaces.
fn demodulate(rec: &mut Recorder, plan: &SubmitPlan) {
    let sanitized = plan
        .passes
        .counters(counters::SANITIZE, SANITIZE_COUNTER_BYTES);
    let shading = &plan.work[WorkImages::SOURCE_SHADING];
    rec.stage(PATCHEX_STAGE_DEMODULATE, |rec| {
        match plan.separation {
            Some((separation, shadows)) => {
                separate_shadows::record(
                    rec,
                    plan.passes.get(PipelineId::SeparateShadows),
                    plan.extent,
                    separation,
                    &separate_shadows::SeparationOutputs {
                        source_objects: plan.gbuffer.objects(plan.placeholder_uint),
                        shading,
                        shadow_layer: &shadows[ShadowImages::LAYER],
                    },
                    &sanitized,
                    plan.separates,
                );
            }
            None => demodulate::record(
                rec,
                plan.passes.get(PipelineId::Demodulate),
                plan.extent,
                &plan.demodulation,
                shading,
                &sanitized,
            ),
        }
        if let Some((highlights, images)) = plan.highlights {
            highlights::record_removal(
                rec,
                plan.passes.get(PipelineId::RemoveHighlights),
                plan.extent,
                highlights,
                shading,
                &images[HighlightImages::VISIBILITY],
            );
        }
        if let Some((translucency, kept)) = plan.translucency {
            translucency::record_separation(
                rec,
                plan.passes.get(PipelineId::SeparateTranslucency),
                plan.extent,
                translucency,
                shading,
                kept,
            );
        }
    });
}

/// How the shadow mask moved from frame t-1 to frame t.
fn shadow_flow(rec: &mut Recorder, plan: &SubmitPlan) {
    let atlases = plan.flow_atlases.filter(|_| plan.flow.runs());
    let (Some((separation, _)), Some(atlases)) = (plan.separation, atlases) else {
        return;
    };
    let passes = &plan.passes;
    rec.stage(PATCHEX_STAGE_SHADOW_FLOW, |rec| {
        shadow_flow::record(
            rec,
            &shadow_flow::FlowPasses {
                mask_finest: passes.get(PipelineId::ShadowMaskFinest),
                mask_pyramid: passes.get(PipelineId::ShadowMaskPyramid),
                poly: passes.get(PipelineId::ShadowPoly),
                iterate: [0, 1].map(|n| passes.nth(PipelineId::ShadowFlowIterate, n)),
                start: passes.nth(PipelineId::ShadowFlowIterate, 2),
            },
            plan.extent,
            &plan.flow,
            &atlases.flow_images(
                plan.shadow_current,
                shadow_flow::FrameMask {
                    mask: separation.mask,
                    source_objects: plan.gbuffer.objects(plan.placeholder_uint),
                    source_depth: &plan.work[WorkImages::SOURCE_DEPTH],
                },
                passes.counters(counters::EXPANSION, shadow_flow::EXPANSION_BYTES),
                plan.placeholder,
            ),
            plan.reprojection.as_ref(),
        )
    });
}

/// Everything one extrapolation records with: its inputs, images and settings, resolved.
pub struct ExtrapolationPlan<'a> {
    pub extent: vk::Extent2D,
    pub passes: RegionPasses<'a>,
    pub work: &'a WorkImages,
    /// The shadow sub-task's images, when frame t came with a shadow input.
    pub shadows: Option<&'a ShadowImages>,
    /// Frame t's shadows were separated from its shading (`submit::shadows_separated`).
    pub shadows_separated: bool,
    /// Frame t-1 came with one too: how the flow measured the shadows drift.
    pub shadow_flow: Option<shadow_flow::FrameFlow<'a>>,
    /// `PatchexTargetShadowInput.mask`: the shadows at the target, in place of the flow's.
    pub target_shadow_mask: Option<Texture>,
    /// The regions, for the diagnostics.
    pub analysis: Option<&'a AnalysisImages>,
    /// The LBP map, for the diagnostics.
    pub diagnostic_images: Option<&'a DiagnosticImages>,
    /// The networks, when the preset has them.
    pub inpainting: Option<&'a Inpainting>,
    pub networks: NetworkSwitches,
    /// Where the warp writes its shading and the later passes refine it: the engine's output,
    /// or the staging image an output format the passes cannot store needs.
    pub frame: Texture,
    pub staging: Option<&'a OutputStaging>,
    pub output: &'a ImportedImage,
    pub target: &'a EngineGbuffer,
    pub motion: Texture,
    pub motion_scale: [f32; 2],
    pub remodulation: Remodulation,
    /// Bound where a pass reads nothing: a float and an integer image.
    pub placeholders: (Texture, Texture),
    pub warp: WarpSettings,
    pub warp_params: warp::Params,
    /// How the shadow layer moves to the target instant.
    pub shadow_params: warp::Params,
    pub segmentation: SegmentationSettings,
    /// Both instants' cameras, written into the counters before the first stage.
    pub cameras: CounterRange,
    /// The holes the G-buffer warp leaves to the fill.
    pub deferred_holes: CounterRange,
    pub diagnostics: Option<Texture>,
    pub shadow_diagnostics: Option<Texture>,
    /// Frame t came with a sun (`PatchexSunLight`) or a sky: the sun (`NO_SUN` without one),
    /// and its kept visibility.
    pub sun: Option<(highlights::Sun, &'a HighlightImages)>,
    /// Frame t came with a sky (`PatchexSkyLight`): its kept mips, and their layout.
    pub kept_sky: Option<(&'a OwnedImage, highlights::SkyMap)>,
    /// Frame t came with a translucency input: its kept layer, and whether it has its own
    /// motion.
    pub translucency: Option<(&'a TranslucencyImages, bool)>,
    /// The target's place between frame t and frame t+1.
    pub alpha: f32,
}

/// Records the extrapolation's stages in order.
pub fn record(rec: &mut Recorder, plan: &ExtrapolationPlan) {
    move_shadows(rec, plan);
    segment(rec, plan);
    warp_frame(rec, plan);
    fill_holes(rec, plan);
    target_shadows(rec, plan);
    lbp(rec, plan);
    diagnostics(rec, plan);
    inference_and_blend(rec, plan);
    remodulate(rec, plan);
    place_highlights(rec, plan);
    place_translucency(rec, plan);
    pack_output(rec, plan);
}

/// A call's counters as `Recorder::acquire` writes them ahead of its passes: zeros, but for
/// `blocks`, each at its offset.
fn counter_contents(passes: &RegionPasses, blocks: &[(u64, &[u8])]) -> Vec<u8> {
    let mut contents = vec![0u8; passes.all_counters().range as usize];
    for &(offset, bytes) in blocks {
        contents[offset as usize..offset as usize + bytes.len()].copy_from_slice(bytes);
    }
    contents
}

/// The submit's counters, with what the shadow flow's expansion reads there.
pub fn submit_counters(passes: &RegionPasses, flow: &FlowSettings) -> Vec<u8> {
    let expansion = flow.expansion();
    counter_contents(passes, &[(counters::EXPANSION, expansion.as_bytes())])
}

/// The extrapolation's counters, with what its passes read there: both instants' `cameras` and
/// no deferred holes yet. Also returns those two ranges.
pub fn starting_counters(
    passes: &RegionPasses,
    cameras: &warp::Cameras,
) -> (Vec<u8>, CounterRange, CounterRange) {
    let contents = counter_contents(
        passes,
        &[
            (counters::CAMERAS, cameras.as_bytes()),
            (counters::DEFERRED_HOLES, warp::NO_DEFERRED_HOLES.as_bytes()),
        ],
    );
    (
        contents,
        passes.counters(counters::CAMERAS, warp::CAMERAS_BYTES),
        passes.counters(counters::DEFERRED_HOLES, warp::DEFERRED_HOLES_BYTES),
    )
}

impl<'a> ExtrapolationPlan<'a> {
    fn warp_pipeline(&self) -> PipelineId {
        Pipelines::warp(self.warp.kind)
    }

    /// The G-buffer warp lists its holes for the fill; the other warps fill their own.
    fn lists_holes(&self) -> bool {
        self.warp_pipeline() == PipelineId::WarpGbuffer
    }

    /// The target's shadows come from its mask: the engine gave one, and frame t's shadows were
    /// separated from its shading (from the second consecutive frame with a shadow input, or
    /// from the first with the flow off).
    fn places_target_shadows(&self) -> bool {
        self.shadows.is_some() && self.shadows_separated && self.target_shadow_mask.is_some()
    }

    /// The shadow layer moves by its flow: frame t-1's shadows were tracked, and no target mask
    /// replaces them.
    fn moves_shadows(&self) -> bool {
        self.shadows.is_some()
            && self.shadows_separated
            && self.shadow_flow.is_some()
            && !self.places_target_shadows()
    }

    /// The shadow layer, which the frame's warp carries into the shadows' share wherever frame
    /// t's shadows were separated from its shading: there the share is the carried layer, for a
    /// target mask to replace, or, with the flow off and no mask, as it is; with the flow, the
    /// carried layer fills in where the moved one found no receiver.
    fn carried_layer(&self) -> Option<warp::CarriedLayer<'a>> {
        let shadows = self.shadows.filter(|_| self.shadows_separated)?;
        Some(warp::CarriedLayer {
            source: &shadows[ShadowImages::LAYER],
            share: (&shadows[ShadowImages::SHADOW_SHARE]).into(),
            moved: self.moves_shadows(),
        })
    }

    /// The nearest-texel fill is the warp's own; only the default defers its holes.
    fn fills_holes(&self) -> bool {
        self.lists_holes() && self.warp.hole_fill == PATCHEX_HOLE_FILL_BACKGROUND
    }

    /// With nothing to run between the warp and the output but the highlights (no shadow layers,
    /// networks or diagnostics), the warp remodulates as it writes.
    fn remodulates_in_warp(&self) -> bool {
        self.shadows.is_none() && self.inpainting.is_none() && self.analysis.is_none()
    }

    /// The networks run, and their blend remodulates as it writes.
    fn blends(&self) -> bool {
        self.inpainting.is_some()
    }

    /// The segmentation's object totals and grown rectangles.
    fn object_table(&self) -> CounterRange {
        self.passes
            .counters(counters::OBJECT_TABLE, segmentation::TABLE_BYTES)
    }

    fn remodulation_inputs(&self) -> remodulate::RemodulateInputs {
        remodulate::RemodulateInputs {
            base_color: self.remodulation.base_color,
            material: self.remodulation.material,
            shadow_share: self
                .shadows
                .map(|s| (&s[ShadowImages::SHADOW_SHARE]).into()),
            placeholder: self.placeholders.0,
        }
    }

    /// Where the output's passes count what they sanitised.
    fn sanitized(&self) -> CounterRange {
        self.passes
            .counters(counters::SANITIZE, SANITIZE_COUNTER_BYTES)
    }

    fn frame_store(&self) -> Store<'_> {
        if self.remodulates_in_warp() {
            Store::Remodulated(&self.remodulation)
        } else {
            Store::Shading
        }
    }

    /// What every warp reads: `source_shading` of frame t moved by `motion` to the target, with
    /// `layer` beside it.
    fn warp_inputs(
        &'a self,
        source_shading: &'a OwnedImage,
        motion: Texture,
        layer: Option<warp::CarriedLayer<'a>>,
    ) -> warp::WarpInputs<'a> {
        warp::WarpInputs {
            source_shading,
            source_depth: &self.work[WorkImages::SOURCE_DEPTH],
            source_normal_id: &self.work[WorkImages::SOURCE_NORMAL_ID],
            target: self.target,
            motion,
            cameras: &self.cameras,
            placeholder: self.placeholders.0,
            placeholder_uint: self.placeholders.1,
            layer,
        }
    }

    fn frame_inputs(&'a self) -> warp::WarpInputs<'a> {
        self.warp_inputs(
            &self.work[WorkImages::SOURCE_SHADING],
            self.motion,
            self.carried_layer(),
        )
    }

    /// The networks' patch records (`inpaint::PATCH_SLOT_*`).
    fn patches(&self) -> CounterRange {
        self.passes
            .counters(counters::PATCHES, inpaint::PATCH_SLOTS_BYTES)
    }

    /// The G-buffer warp's hole list, which the fill fills.
    fn hole_list(&'a self) -> warp::HoleList<'a> {
        warp::HoleList {
            list: &self.work[WorkImages::HOLE_LIST],
            deferred: &self.deferred_holes,
            fill: self.passes.get(PipelineId::FillHoles),
        }
    }
}

/// The shadow layer moved by the mask's flow scaled to the target instant, into the shadows'
/// share, where the frame's warp then completes it. With `PATCHEX_SHADOW_HISTORY_STARTED`
/// (no frame t-1 to measure a drift from) the share is cleared: the shadows stay on their
/// receivers, where the frame's warp carries them, and change nothing. (Moved by a zero flow
/// instead, they would stay put on the screen and slide across the ground under a moving camera.)
fn move_shadows(rec: &mut Recorder, plan: &ExtrapolationPlan) {
    let Some(shadows) = plan.shadows else {
        return;
    };
    let share = &shadows[ShadowImages::SHADOW_SHARE];
    if plan.shadows_separated && !plan.moves_shadows() {
        return;
    }
    rec.stage(PATCHEX_STAGE_SHADOW_WARP, |rec| {
        if !plan.shadows_separated {
            rec.clear(share);
            return;
        }
        let flow = plan
            .shadow_flow
            .expect("moving the shadows needs their flow");
        // The occlusion-motion warp's sets: the frame's own warp uses the first when it is
        // that warp.
        let flow_warp = PipelineId::WarpOcclusionMotion;
        let flow_set = (plan.warp_pipeline() == flow_warp) as usize;
        // It reads its motion from the flow's finest level.
        let params = warp::Params {
            motion_level_offset: flow.finest.offset,
            motion_level_size: flow.finest.size,
            ..plan.shadow_params
        };
        warp::record(
            rec,
            plan.passes.nth(flow_warp, flow_set),
            &params,
            &plan.warp_inputs(&shadows[ShadowImages::LAYER], flow.atlas.into(), None),
            Store::Shading,
            share.into(),
            &plan
                .passes
                .counters(counters::SHADOW_WARP, warp::COUNTER_BYTES),
            None,
        );
    });
}

/// Frame t's shading, and with a shadow input its shadow layer, carried to the target.
fn warp_frame(rec: &mut Recorder, plan: &ExtrapolationPlan) {
    let holes = plan.lists_holes().then(|| plan.hole_list());
    rec.stage(PATCHEX_STAGE_WARP, |rec| {
        warp::record(
            rec,
            plan.passes.get(plan.warp_pipeline()),
            &plan.warp_params,
            &plan.frame_inputs(),
            plan.frame_store(),
            plan.frame,
            &plan.passes.counters(counters::WARP, warp::COUNTER_BYTES),
            holes.as_ref(),
        )
    });
}

fn fill_holes(rec: &mut Recorder, plan: &ExtrapolationPlan) {
    if !plan.fills_holes() {
        return;
    }
    rec.stage(PATCHEX_STAGE_FILL_HOLES, |rec| {
        fill_holes::record(
            rec,
            &plan.warp_params,
            &plan.frame_inputs(),
            plan.frame_store(),
            plan.frame,
            &plan.passes.counters(counters::WARP, warp::COUNTER_BYTES),
            &plan.hole_list(),
        )
    });
}

/// With a target shadow input: the share of light the target's shadows take away, from its
/// mask and the sun's share of frame t's light, in place of the carried layer.
fn target_shadows(rec: &mut Recorder, plan: &ExtrapolationPlan) {
    let Some(mask) = plan
        .target_shadow_mask
        .filter(|_| plan.places_target_shadows())
    else {
        return;
    };
    let shadows = plan
        .shadows
        .expect("placing shadows needs the shadow images");
    rec.stage(PATCHEX_STAGE_TARGET_SHADOWS, |rec| {
        target_shadows::record(
            rec,
            [
                plan.passes.get(PipelineId::EstimateSunShare),
                plan.passes.get(PipelineId::PlaceTargetShadows),
            ],
            plan.extent,
            &target_shadows::TargetShadowInputs {
                shadow_layer: &shadows[ShadowImages::LAYER],
                mask,
                stencil: plan.target.stencil,
                placeholder_uint: plan.placeholders.1,
                sun_share: plan
                    .passes
                    .counters(counters::SUN_SHARE, target_shadows::SUN_SHARE_BYTES),
                sanitized: plan.sanitized(),
            },
            &shadows[ShadowImages::SHADOW_SHARE],
        )
    });
}

/// The objects' rectangles; with the networks, their patches, planned from the same totals, which
/// list the rectangles too; with the diagnostics, every pixel's region.
fn segment(rec: &mut Recorder, plan: &ExtrapolationPlan) {
    let table = plan.object_table();
    let inputs = segmentation::SegmentationInputs {
        target_objects: plan.target.objects(plan.placeholders.1),
        motion: plan.motion,
        motion_scale: plan.motion_scale,
    };
    rec.stage(PATCHEX_STAGE_SEGMENT, |rec| {
        let passes = &plan.passes;
        segmentation::record_bounds(
            rec,
            passes.get(PipelineId::ObjectBounds),
            plan.extent,
            &inputs,
            &table,
        );
        match plan.inpainting {
            // The networks' planning lists the grown rectangles as well.
            Some(inpainting) => {
                let networks = &plan.networks;
                inpaint::record_plan(
                    rec,
                    passes.get(PipelineId::PlanPatches),
                    plan.extent,
                    &inpaint::PatchPlan {
                        levels: inpainting.levels(networks.running()),
                        whole_frame: networks.whole_frame,
                        divisor: networks.divisor,
                        max_patch_side: inpainting.max_patch_side,
                        growth: plan.segmentation.growth,
                        step_levels: inpainting.pipelines.step_table(),
                    },
                    &table,
                    &plan.patches(),
                )
            }
            None => segmentation::record_growth(
                rec,
                passes.get(PipelineId::GrowRegions),
                plan.extent,
                &plan.segmentation,
                &table,
            ),
        }
        if let Some(analysis) = plan.analysis {
            segmentation::record_masks(
                rec,
                plan.passes.get(PipelineId::RegionMasks),
                plan.extent,
                &inputs,
                &table,
                &analysis[AnalysisImages::REGIONS],
            );
        }
    });
}

/// The warped frame's LBP map, for the diagnostics to show.
fn lbp(rec: &mut Recorder, plan: &ExtrapolationPlan) {
    let Some(images) = plan.diagnostic_images else {
        return;
    };
    rec.stage(PATCHEX_STAGE_LBP, |rec| {
        lbp::record(
            rec,
            plan.passes.get(PipelineId::Lbp),
            plan.extent,
            plan.frame,
            &images[DiagnosticImages::LBP],
        )
    });
}

/// The networks on the patches the segmentation planned, then their blend.
fn inference_and_blend(rec: &mut Recorder, plan: &ExtrapolationPlan) {
    let Some(inpainting) = plan.inpainting else {
        return;
    };
    let patches = plan.patches();
    let networks = &plan.networks;
    rec.stage(PATCHEX_STAGE_INFERENCE, |rec| {
        inpaint::record(
            rec,
            &inpaint::FrameInputs {
                warped: plan.frame,
                material: plan.remodulation.material,
                placeholder: plan.placeholders.0,
                frame_extent: plan.extent,
            },
            &inpainting.run(&plan.passes, &patches),
        );
    });
    rec.stage(PATCHEX_STAGE_BLEND, |rec| {
        inpaint::record_blend(
            rec,
            plan.passes.get(PipelineId::BlendPatches),
            plan.extent,
            &inpaint::BlendInputs {
                patches,
                target_objects: plan.target.objects(plan.placeholders.1),
                table: plan.object_table(),
                networks: inpainting.tensors(),
                whole_frame: networks.whole_frame,
                correct_valid_pixels: networks.correct_valid_pixels,
            },
            &plan.remodulation_inputs(),
            plan.frame,
            &plan.sanitized(),
        )
    });
}

/// Before the networks and remodulation, from the warped frame's hole flags.
fn diagnostics(rec: &mut Recorder, plan: &ExtrapolationPlan) {
    let shadow_diagnostics = plan.shadow_diagnostics.zip(plan.shadows);
    if plan.diagnostics.is_none() && shadow_diagnostics.is_none() {
        return;
    }
    rec.stage(PATCHEX_STAGE_DIAGNOSTICS, |rec| {
        if let Some(image) = plan.diagnostics {
            let analysis = plan.analysis.expect("made for the diagnostics");
            let lbp = plan.diagnostic_images.expect("made for the diagnostics");
            let sources = diagnostics::frame_sources(
                plan.frame,
                &analysis[AnalysisImages::REGIONS],
                &lbp[DiagnosticImages::LBP],
            );
            let pass = plan.passes.get(PipelineId::WriteDiagnostics);
            let params = diagnostics::frame_params(plan.extent);
            diagnostics::record(rec, pass, &params, plan.extent, sources, image);
        }
        if let Some((image, shadows)) = shadow_diagnostics {
            let (atlas, params) = diagnostics::shadow_params(plan.extent, plan.shadow_flow);
            let sources = diagnostics::shadow_sources(
                atlas.unwrap_or(plan.placeholders.0),
                &shadows[ShadowImages::LAYER],
                &shadows[ShadowImages::SHADOW_SHARE],
            );
            let pass = plan.passes.get(PipelineId::WriteShadowDiagnostics);
            diagnostics::record(rec, pass, &params, plan.extent, sources, image);
        }
    });
}

fn remodulate(rec: &mut Recorder, plan: &ExtrapolationPlan) {
    if plan.remodulates_in_warp() || plan.blends() {
        return;
    }
    rec.stage(PATCHEX_STAGE_REMODULATE, |rec| {
        remodulate::record(
            rec,
            plan.passes.get(PipelineId::Remodulate),
            plan.extent,
            &plan.remodulation_inputs(),
            plan.frame,
            &plan.sanitized(),
        )
    });
}

/// The sun's highlights and the sky's reflection as the target sees them, added to the
/// remodulated frame.
fn place_highlights(rec: &mut Recorder, plan: &ExtrapolationPlan) {
    let Some((sun, images)) = plan.sun else {
        return;
    };
    let inputs = highlights::TargetHighlights {
        sun,
        kept_visibility: &images[HighlightImages::VISIBILITY],
        kept_sky: plan.kept_sky,
        source_depth: &plan.work[WorkImages::SOURCE_DEPTH],
        source_normal_id: &plan.work[WorkImages::SOURCE_NORMAL_ID],
        target: plan.target,
        base_color: plan.remodulation.base_color,
        material: plan.remodulation.material,
        motion: plan.motion,
        warp: &plan.warp_params,
        cameras: &plan.cameras,
        shadow_share: plan
            .shadows
            .map(|s| (&s[ShadowImages::SHADOW_SHARE]).into()),
        target_mask: plan
            .target_shadow_mask
            .filter(|_| plan.places_target_shadows()),
        placeholders: plan.placeholders,
        sanitized: plan.sanitized(),
    };
    rec.stage(PATCHEX_STAGE_HIGHLIGHTS, |rec| {
        highlights::record_placement(
            rec,
            plan.passes.get(PipelineId::PlaceHighlights),
            plan.extent,
            &inputs,
            plan.frame,
        )
    });
}

/// Frame t's translucency, moved to the target, over the finished frame.
fn place_translucency(rec: &mut Recorder, plan: &ExtrapolationPlan) {
    let Some((kept, has_motion)) = plan.translucency else {
        return;
    };
    let inputs = translucency::TargetTranslucency {
        kept,
        has_motion,
        target: plan.target,
        target_motion: plan.motion,
        source_depth: &plan.work[WorkImages::SOURCE_DEPTH],
        source_normal_id: &plan.work[WorkImages::SOURCE_NORMAL_ID],
        cameras: &plan.cameras,
        warp: &plan.warp_params,
        placeholder_uint: plan.placeholders.1,
        alpha: plan.alpha,
        sanitized: plan.sanitized(),
    };
    rec.stage(PATCHEX_STAGE_TRANSLUCENCY, |rec| {
        translucency::record_placement(
            rec,
            plan.passes.get(PipelineId::PlaceTranslucency),
            plan.extent,
            &inputs,
            plan.frame,
        )
    });
}

/// Into an output format the passes cannot store, from the staging image.
fn pack_output(rec: &mut Recorder, plan: &ExtrapolationPlan) {
    let Some(staging) = plan.staging else {
        return;
    };
    let encoding = pack_output::encoding(plan.output.format)
        .expect("every copied output format has an encoding");
    rec.stage(PATCHEX_STAGE_PACK_OUTPUT, |rec| {
        pack_output::record(
            rec,
            plan.passes.get(PipelineId::PackOutput),
            plan.extent,
            &pack_output::Packing {
                encoding,
                frame: &staging[OutputStaging::FRAME],
                packed: &staging[OutputStaging::PACKED],
                output: plan.output,
            },
        )
    });
}
