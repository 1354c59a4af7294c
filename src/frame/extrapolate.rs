//! `patchex_extrapolate`: one target instant from frame t. The target's G-buffer packing, the
//! warp of frame t's shading (and of its shadow layer), segmentation, the networks on their
//! patches, remodulation into the engine's output, and the diagnostics.

use ash::vk;

use crate::abi::*;
use crate::context::Context;
use crate::error::{bail, PatchexResult, Result};
use crate::frame::images::{Growth, ImageSet, OutputStaging, SkyImages};
use crate::frame::plan::{self, ExtrapolationPlan};
use crate::frame::settings::Extensions;
use crate::frame::submit::{engine_gbuffer, shadows_separated};
use crate::inputs::{self, TargetInputs};
use crate::passes::pack_gbuffer::EngineGbuffer;
use crate::passes::{warp, RegionPasses, Texture};
use crate::vk::barriers::EngineImageAccess;
use crate::vk::frame_ring::RegionRecord;
use crate::vk::image::{ImageRole, ImportedImage, MASK_FORMATS};
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
        let (inputs, slot, done, serial) = self.check_target(desc, &extensions)?;
        let engine = self.import_engine_images(&inputs, &extensions)?;
        // The regions' and the LBP map's images, for the diagnostics only.
        let diagnose = engine.diagnostics.is_some();
        self.allocate(serial, inputs.output.written_by_copy, diagnose)?;

        // Everything is validated and allocated: from here on the call cannot fail.
        let source = self.source.as_ref().expect("checked");
        let placeholders = self.images.placeholders();
        let run_networks = extensions.networks.unwrap_or(self.defaults.networks);
        let warp_settings = extensions.warp.unwrap_or(self.defaults.warp);
        let camera = &inputs.geometry.camera;
        let jitter_delta = (camera.jitter - source.camera.jitter).into();
        let region = 1 + done;
        let mut rec = Recorder::new(&self.gpu.device, cmd).skipping(self.test_fault);
        let staging = in_use(
            &mut rec,
            self.images.output_staging.as_mut(),
            inputs.output.written_by_copy,
        );
        let analysis = in_use(&mut rec, self.images.analysis.as_mut(), diagnose);
        let diagnostic_images = in_use(&mut rec, self.images.diagnostics.as_mut(), diagnose);
        // The warp writes its shading here; the later passes refine it in place.
        let frame: Texture = staging.map_or(engine.output, |s| (&s[OutputStaging::FRAME]).into());
        let passes = RegionPasses {
            pipelines: &self.pipelines,
            ring: &self.ring,
            slot,
            region,
        };
        let cameras = warp::cameras(&source.camera, &engine.target_gbuffer, inputs.extent);
        let (counters, cameras, deferred_holes) = plan::starting_counters(&passes, &cameras);
        rec.acquire(&engine.access, &passes.all_counters(), Some(&counters));
        let mut rec = rec.timed(&self.ring, slot, region);
        let work = self
            .images
            .work
            .as_ref()
            .expect("a submitted frame allocated the work images");
        let shadows = self
            .images
            .shadows
            .as_ref()
            .filter(|_| source.has_shadows());
        let plan = ExtrapolationPlan {
            extent: inputs.extent,
            passes,
            work,
            shadows,
            shadows_separated: shadows_separated(source.shadow_history),
            shadow_flow: self
                .images
                .flow
                .as_ref()
                .filter(|_| source.shadow_history == PATCHEX_SHADOW_HISTORY_TRACKED)
                .map(|atlases| atlases.frame_flow(inputs.extent)),
            target_shadow_mask: engine.target_shadow_mask,
            analysis,
            diagnostic_images,
            inpainting: self.inpainting.as_ref(),
            networks: run_networks,
            frame,
            staging,
            output: &inputs.output,
            target: &engine.target_gbuffer,
            motion: engine.motion,
            motion_scale: inputs.geometry.motion_vector_scale,
            remodulation: warp::Remodulation {
                base_color: engine.base_color,
                material: engine.material,
            },
            placeholders,
            warp: warp_settings,
            warp_params: warp_settings.params(
                inputs.extent,
                camera,
                jitter_delta,
                inputs.geometry.motion_vector_scale,
            ),
            shadow_params: warp_settings.shadow_params(inputs.extent, camera, inputs.alpha),
            segmentation: extensions
                .segmentation
                .unwrap_or(self.defaults.segmentation),
            cameras,
            deferred_holes,
            diagnostics: engine.diagnostics,
            shadow_diagnostics: engine.shadow_diagnostics,
            sun: source.sun.zip(self.images.highlights.as_ref()),
            kept_sky: source
                .sky
                .zip(self.images.sky.as_ref())
                .map(|(sky, kept)| (&kept[SkyImages::RADIANCE], sky)),
            translucency: self.images.translucency.as_ref().zip(source.translucency),
            alpha: inputs.alpha,
        };
        plan::record(&mut rec, &plan);
        let stages = rec.finish(
            &engine.access,
            &plan.passes.all_counters(),
            self.ring.readback.buffer,
        );
        let record = RegionRecord {
            stages,
            alpha: inputs.alpha,
            camera_cut: camera.is_cut_from(&source.camera),
            whole_frame: self.inpainting.is_some() && run_networks.whole_frame,
        };
        Ok(self.keep_extrapolation(slot, record))
    }

    /// Keeps what an extrapolation recorded for the stats of its slot; `RenderInstead` for a
    /// camera cut.
    fn keep_extrapolation(&mut self, slot: usize, record: RegionRecord) -> PatchexResult {
        let camera_cut = record.camera_cut;
        self.ring.slots[slot]
            .record
            .as_mut()
            .expect("the submit recorded this slot")
            .extrapolations
            .push(record);
        if camera_cut {
            PatchexResult::RenderInstead
        } else {
            PatchexResult::Success
        }
    }

    /// The images this extrapolation needs beyond the submit's: the staging of an output the
    /// passes cannot store (`staging`), and the diagnostics' regions and LBP map
    /// (`diagnostics`).
    fn allocate(&mut self, serial: u64, staging: bool, diagnostics: bool) -> Result<()> {
        let mut growth = Growth {
            gpu: &self.gpu,
            allocator: &mut self.allocator,
            ring: &mut self.ring,
            serial,
        };
        if staging {
            self.images.ensure_output_staging(&mut growth)?;
        }
        if diagnostics {
            self.images.ensure_analysis(&mut growth)?;
            self.images.ensure_diagnostics(&mut growth)?;
        }
        Ok(())
    }

    /// The target's inputs, checked against the submitted frame, with the frame ring's slot of
    /// that frame, the extrapolations it already has, and its submit's serial.
    fn check_target(
        &self,
        desc: &PatchexExtrapolateDesc,
        extensions: &Extensions,
    ) -> Result<(TargetInputs, usize, usize, u64)> {
        self.check_queue_family(desc.queue_family_index, "PatchexExtrapolateDesc")?;
        if self.inpainting.is_none() && extensions.networks.is_some() {
            bail!(
                ErrorInvalidArgument,
                "PatchexNetworkSettings needs a context made with PATCHEX_PRESET_NETWORKS or \
                 PATCHEX_PRESET_FULL"
            );
        }
        let Some(source) = &self.source else {
            bail!(
                ErrorNoSourceFrame,
                "patchex_extrapolate called before any patchex_submit_gbuffers"
            );
        };
        if extensions.target_shadow_mask.is_some() && !source.has_shadows() {
            bail!(
                ErrorInvalidArgument,
                "PatchexTargetShadowInput needs frame t to have come with a PatchexShadowInput \
                 (frame {} did not)",
                source.frame_index
            );
        }
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
        Ok((inputs, slot, done, source.serial))
    }

    /// The engine's images this extrapolation reads and writes, checked and borrowed.
    fn import_engine_images(
        &self,
        inputs: &TargetInputs,
        extensions: &Extensions,
    ) -> Result<EngineImages> {
        let mut access = EngineImageAccess::default();
        let motion = access.read(&inputs.motion_vectors)?;
        let target_gbuffer = engine_gbuffer(&mut access, &inputs.geometry)?;
        let base_color = access.read(&inputs.base_color)?;
        let material = access.read_optional(inputs.material.as_ref())?;
        let output = access.write(&inputs.output)?;
        let target_shadow_mask = extensions
            .target_shadow_mask
            .as_ref()
            .map(|mask| {
                let role = ImageRole::input("PatchexTargetShadowInput.mask", MASK_FORMATS);
                access.read(&ImportedImage::import_required(
                    &self.gpu,
                    mask,
                    &role,
                    inputs.extent,
                )?)
            })
            .transpose()?;
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
        let diagnostics =
            import_diagnostics(extensions.diagnostics.as_ref(), "PatchexDiagnostics.image")?;
        let shadow_diagnostics = import_diagnostics(
            extensions.shadow_diagnostics.as_ref(),
            "PatchexShadowDiagnostics.image",
        )?;
        Ok(EngineImages {
            access,
            motion,
            target_gbuffer,
            base_color,
            material,
            output,
            target_shadow_mask,
            diagnostics,
            shadow_diagnostics,
        })
    }
}

/// The engine's images of one extrapolation, as the passes bind them.
struct EngineImages {
    /// How each is borrowed: acquired before the first pass, released after the last.
    access: EngineImageAccess,
    motion: Texture,
    target_gbuffer: EngineGbuffer,
    base_color: Texture,
    material: Option<Texture>,
    output: Texture,
    target_shadow_mask: Option<Texture>,
    diagnostics: Option<Texture>,
    shadow_diagnostics: Option<Texture>,
}

/// `set` when this call uses it, its images moved to GENERAL if no command buffer has used them.
fn in_use<'s, const N: usize, Kind>(
    rec: &mut Recorder,
    set: Option<&'s mut ImageSet<N, Kind>>,
    used: bool,
) -> Option<&'s ImageSet<N, Kind>> {
    let set = set.filter(|_| used)?;
    rec.initialize(&mut set.images.each_mut());
    Some(set)
}
