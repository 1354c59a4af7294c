//! `patchex_submit_gbuffers`: frame t's G-buffer packing, its demodulation (or, with a shadow
//! input, the shadow layer's separation) and the shadow mask's flow.

use ash::vk;

use crate::abi::*;
use crate::context::{Context, SourceFrame};
use crate::error::{bail, Result};
use crate::frame::counters;
use crate::frame::images::Growth;
use crate::frame::images::{ShadowImages, SkyImages, WorkImages};
use crate::frame::plan::{self, SubmitPlan};
use crate::frame::settings::{Extensions, NEEDS_SHADOW_PRESET};
use crate::inputs::{self, GeometryInputs, SourceInputs};
use crate::passes::highlights::{self, Sun};
use crate::passes::{
    demodulate, pack_gbuffer, separate_shadows, translucency, RegionPasses, SANITIZE_COUNTER_BYTES,
};
use crate::vk::barriers::EngineImageAccess;
use crate::vk::frame_ring::{FrameRecord, RegionRecord};
use crate::vk::image::OwnedImage;
use crate::vk::recorder::Recorder;

impl Context {
    /// Records frame t's demodulation (or shadow separation), G-buffer packing and, with a
    /// shadow input, the shadow mask's flow into `cmd`.
    pub fn submit(
        &mut self,
        cmd: vk::CommandBuffer,
        desc: &PatchexFrameDesc,
        extensions: Extensions,
    ) -> Result<()> {
        self.check_queue_family(desc.queue_family_index, "PatchexFrameDesc")?;
        if !self.preset.shadows && (extensions.shadow.is_some() || extensions.flow.is_some()) {
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
        let sun_inputs = extensions
            .sun
            .map(|input| inputs::sun(&self.gpu, &input, inputs.extent))
            .transpose()?;
        let sky_inputs = extensions
            .sky
            .map(|input| inputs::sky(&self.gpu, &input))
            .transpose()?;
        let translucency_inputs = extensions
            .translucency
            .map(|input| inputs::translucency(&self.gpu, &input, inputs.extent))
            .transpose()?;
        let flow_settings = extensions.flow.unwrap_or(self.defaults.flow);
        let reset_reason = self.reset_reason(&inputs)?;
        let (placeholder, placeholder_uint) = self.images.placeholders();
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
        let gbuffer = engine_gbuffer(&mut access, &inputs.geometry)?;
        let sun_visibility = sun_inputs
            .as_ref()
            .map(|sun| access.read(&sun.visibility))
            .transpose()?;
        let sky_map = match &sky_inputs {
            Some((map, sky)) => Some((access.read(map)?, *sky)),
            None => None,
        };
        let translucency_images = match &translucency_inputs {
            Some(input) => Some((
                access.read(&input.mask)?,
                match &input.motion_vectors {
                    Some(motion) => Some((access.read(motion)?, input.motion_vector_scale)),
                    None => None,
                },
                match &inputs.geometry.motion_vectors {
                    Some(motion) => {
                        Some((access.read(motion)?, inputs.geometry.motion_vector_scale))
                    }
                    None => None,
                },
                access.read_optional(input.opaque_color.as_ref())?,
            )),
            None => None,
        };

        let serial = self.source.as_ref().map_or(1, |s| s.serial + 1);
        self.ring.collect(&self.gpu, &mut self.allocator, serial);
        let mut growth = Growth {
            gpu: &self.gpu,
            allocator: &mut self.allocator,
            ring: &mut self.ring,
            serial,
        };
        self.images.ensure_work(&mut growth, inputs.extent)?;
        // A sun or a sky: their reflections are taken out of frame t and placed at the target.
        let reflects = sun_inputs.is_some() || sky_map.is_some();
        if reflects {
            self.images.ensure_highlights(&mut growth)?;
        }
        if let Some((_, sky)) = sky_map {
            self.images.ensure_sky(&mut growth, sky.kept_extent())?;
        }
        if translucency_inputs.is_some() {
            self.images.ensure_translucency(&mut growth)?;
        }
        // Frame t-1's expansion is usable when its flow made it, unbroken, on the same images;
        // this frame's flow, switched off, needs none.
        let flow_made_expansion = |history| {
            history == PATCHEX_SHADOW_HISTORY_STARTED || history == PATCHEX_SHADOW_HISTORY_TRACKED
        };
        let mut track = reset_reason == PATCHEX_RESET_NONE
            && flow_settings.runs()
            && self.source.as_ref().is_some_and(|s| {
                flow_made_expansion(s.shadow_history) && s.extent == inputs.extent
            });
        if shadow_inputs.is_some() {
            track &= !self.images.ensure_shadows(&mut growth)?;
            if flow_settings.runs() {
                track &= !self.images.ensure_flow(&mut growth)?;
            }
            self.shadow_current = 1 - self.shadow_current;
        }

        // With frame t-1 to track from: static receivers' motion into it, where the flow starts.
        let reprojection = self.source.as_ref().filter(|_| track).map(|previous| {
            inputs
                .geometry
                .camera
                .reprojection_into(&previous.camera, inputs.extent)
        });

        let shadow_history = match &shadow_inputs {
            None => PATCHEX_SHADOW_HISTORY_NONE,
            Some(_) if !flow_settings.runs() => PATCHEX_SHADOW_HISTORY_SEPARATED,
            Some(_) if track => PATCHEX_SHADOW_HISTORY_TRACKED,
            Some(_) => PATCHEX_SHADOW_HISTORY_STARTED,
        };

        // Everything is validated and allocated: from here on the call cannot fail.
        let slot = self.ring.slot_of(serial);
        let mut owned: Vec<&mut OwnedImage> = self.images.submit_images().collect();
        if let Some(inpainting) = self.inpainting.as_mut() {
            owned.extend(inpainting.images());
        }
        let mut rec = Recorder::new(&self.gpu.device, cmd).skipping(self.test_fault);
        rec.initialize(&mut owned);
        let passes = RegionPasses {
            pipelines: &self.pipelines,
            ring: &self.ring,
            slot,
            region: 0,
        };
        let contents = plan::submit_counters(&passes, &flow_settings);
        rec.acquire(&access, &passes.all_counters(), Some(&contents));
        let mut rec = rec.timed(&self.ring, slot, 0);
        let separates = shadows_separated(shadow_history);
        let work = self.images.work.as_ref().expect("allocated above");
        let sun = sun_inputs.as_ref().map(|input| Sun {
            direction: input.direction,
            illuminance: input.illuminance,
        });
        let highlights = reflects.then(|| {
            let highlights = highlights::SourceHighlights {
                sun: sun.zip(sun_visibility),
                sky: sky_map.map(|(map, sky)| {
                    let kept = &self.images.sky.as_ref().expect("allocated above");
                    (map, sky, &kept[SkyImages::RADIANCE])
                }),
                shadows: separation_inputs.as_ref().map(|separation| {
                    let layer = &self.images.shadows.as_ref().expect("allocated above")
                        [ShadowImages::LAYER];
                    highlights::ShadowsInShading {
                        mask: separation.mask,
                        separated: separates.then_some((
                            separation.color,
                            separation.color_without_dynamic_shadows,
                            layer,
                        )),
                    }
                }),
                base_color,
                material,
                placeholder,
                rays: inputs
                    .geometry
                    .camera
                    .pixel_rays(inputs.extent, inputs.geometry.camera.position()),
                source_depth: &work[WorkImages::SOURCE_DEPTH],
                source_normal_id: &work[WorkImages::SOURCE_NORMAL_ID],
                sanitized: passes.counters(counters::SANITIZE, SANITIZE_COUNTER_BYTES),
            };
            let images = self.images.highlights.as_ref().expect("allocated above");
            (highlights, images)
        });
        let translucency = translucency_images.map(|(mask, motion, surface_motion, opaque)| {
            translucency::SourceTranslucency {
                color,
                base_color,
                material,
                mask,
                motion,
                surface_motion,
                opaque,
                placeholder,
                source_depth: &work[WorkImages::SOURCE_DEPTH],
                source_normal_id: &work[WorkImages::SOURCE_NORMAL_ID],
                sanitized: passes.counters(counters::SANITIZE, SANITIZE_COUNTER_BYTES),
            }
        });
        let plan = SubmitPlan {
            extent: inputs.extent,
            passes,
            work,
            gbuffer: &gbuffer,
            demodulation: demodulate::DemodulateInputs {
                color,
                base_color,
                material,
                placeholder,
            },
            separation: separation_inputs.as_ref().zip(self.images.shadows.as_ref()),
            flow_atlases: self.images.flow.as_ref(),
            shadow_current: self.shadow_current,
            flow: flow_settings,
            reprojection,
            separates,
            highlights: highlights.as_ref().map(|(h, images)| (h, *images)),
            translucency: translucency.as_ref().map(|t| {
                let kept = self.images.translucency.as_ref().expect("allocated above");
                (t, kept)
            }),
            placeholder,
            placeholder_uint,
        };
        plan::record_submit(&mut rec, &plan);
        let stages = rec.finish(
            &access,
            &plan.passes.all_counters(),
            self.ring.readback.buffer,
        );

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
            shadow_history,
            // A sky without a sun places the sky's reflection alone.
            sun: reflects.then(|| sun.unwrap_or(highlights::NO_SUN)),
            sky: sky_map.map(|(_, sky)| sky),
            translucency: translucency_inputs
                .as_ref()
                .map(|input| input.motion_vectors.is_some()),
        });
        Ok(())
    }

    /// Why frame t starts a new history, if it does; refuses an index that does not increase.
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
}

/// Registers the reads of one instant's engine G-buffer and returns it as the passes bind it.
pub(crate) fn engine_gbuffer(
    access: &mut EngineImageAccess,
    geometry: &GeometryInputs,
) -> Result<pack_gbuffer::EngineGbuffer> {
    Ok(pack_gbuffer::EngineGbuffer {
        depth: access.read(&geometry.depth)?,
        normal: access.read(&geometry.normal)?,
        normal_encoding: geometry.normal_encoding,
        stencil: access.read_optional(geometry.stencil.as_ref())?,
        camera: geometry.camera,
    })
}

/// Frame t's shadows were separated from its shading, for its flow to move or a target mask to
/// place: frame t-1's flow left an expansion to track from, or the flow is off.
pub(crate) fn shadows_separated(history: PatchexShadowHistory) -> bool {
    history == PATCHEX_SHADOW_HISTORY_TRACKED || history == PATCHEX_SHADOW_HISTORY_SEPARATED
}
