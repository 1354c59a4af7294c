//! Plain-Rust versions of every GPU pass: the oracle the tests compare the shaders against.
//! Each function mirrors its shader line for line, takes the same generated `Params`, and
//! rounds where the GPU stores to a 16-bit float image.

pub mod demodulate;
pub mod gbuffer;
pub mod highlights;
pub mod inpaint;
pub mod lbp;
pub mod network;
pub mod optical_flow;
pub mod pack_gbuffer;
pub mod pack_output;
pub mod remodulate;
pub mod segmentation;
pub mod separate_shadows;
pub mod target_shadows;
pub mod translucency;
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
    /// Frame t's `PatchexSunLight`: the sun, and its visibility image.
    pub sun: Option<(crate::passes::highlights::Sun, &'a Image)>,
    /// Frame t's `PatchexSkyLight.radiance`, one image a mip.
    pub sky: Option<&'a [Image]>,
    /// Frame t's `PatchexTranslucencyInput`.
    pub translucency: Option<translucency::Input<'a>>,
}

/// Frame t's shadow input, and frame t-1's when it had one (and no reset came between).
pub struct ShadowInputs<'a> {
    pub color_without_dynamic_shadows: &'a Image,
    pub mask: &'a Image,
    /// Frame t-1's mask, object ids (stencil) and camera.
    pub previous: Option<(&'a Image, &'a Image, &'a crate::camera::Camera)>,
    pub flow: crate::passes::shadow_flow::FlowSettings,
    /// Frame pixels per texel of the flow's finest level: `shadow_flow::mask_step` of the
    /// largest frame the context has seen.
    pub mask_step: u32,
    /// The target's mask (`PatchexTargetShadowInput`), in place of the flow's shadows.
    pub target_mask: Option<&'a Image>,
}

/// The shadow sub-task's results.
pub struct Shadows {
    pub separated: separate_shadows::Separated,
    /// Level 0 flow to frame t-1, (dx, dy, 0, 0); zero without frame t-1's mask.
    pub flow: Image,
    /// The share of light the shadows take away at the target, which remodulation applies: the
    /// layer moved by the flow (with the occlusion-motion-vector warp) where that found a
    /// receiver, the layer carried by the frame's own warp elsewhere, rounded to f16 as stored
    /// (`include/warp.wgsl`, `shadow_share`); with a target mask, the share it places
    /// (`target_shadows`); with the flow off and no mask, the layer the frame's warp carried.
    /// Zero without frame t-1's mask: the shadows stay in the frame, on their receivers.
    pub share: Image,
}

/// Every intermediate result of one extrapolation.
pub struct Extrapolation {
    /// The engine's output image.
    pub output: Image,
    pub warped: warp::Warped,
    pub segmented: segmentation::Segmented,
    pub lbp: Image,
    /// With networks: their patches, outputs and the blended frame remodulation read.
    pub inpainted: Option<inpaint::Inpainted>,
    pub shadows: Option<Shadows>,
    /// Pixels of frame t and of the target whose inputs (or result) were sanitised.
    pub source_sanitized: u32,
    pub target_sanitized: u32,
    /// Pixels of frame t and of the target with NaN or infinite geometry.
    pub source_invalid_geometry: u32,
    pub target_invalid_geometry: u32,
    /// The stages computed, in order: the plugin's stages (`passes::STAGES`) for the same work.
    pub stages: Vec<crate::abi::PatchexStage>,
}

/// The whole extrapolation, stage by stage in the order of `passes::STAGES`, as the plugin
/// records it.
pub fn extrapolate(
    source: &FrameInputs,
    target: &FrameInputs,
    shadow_inputs: Option<&ShadowInputs>,
    alpha: f32,
    warp: &crate::passes::warp::WarpSettings,
    segmentation: &crate::passes::segmentation::SegmentationSettings,
    networks: inpaint::Networks,
) -> Extrapolation {
    use crate::abi::*;
    use crate::passes::pack_gbuffer::params as pack_params;
    let mut stages = vec![PATCHEX_STAGE_PACK_SOURCE_GBUFFER];
    let extent = ash::vk::Extent2D {
        width: source.base_color.width as u32,
        height: source.base_color.height as u32,
    };
    // The target's G-buffer decodes as frame t's does (the warps read it through the packing's
    // functions), but its normals are used as they are, not coded; its motion vectors are
    // checked too, frame t's are not read.
    // Positions relative to the target's camera, as the warps rebuild them.
    let origin = target.camera.position();
    let pack = |frame: &FrameInputs, motion: Option<&Image>, instant| {
        let params = pack_params(
            frame.camera,
            extent,
            frame.normal_encoding,
            frame.stencil.is_some(),
        );
        let rays = frame.camera.pixel_rays(extent, origin);
        pack_gbuffer::pack_gbuffer(
            frame.depth,
            frame.normal,
            frame.stencil,
            motion,
            &params,
            &rays,
            instant,
        )
    };
    let (source_packed, target_packed) = (
        pack(source, None, pack_gbuffer::Instant::Source),
        pack(target, target.motion, pack_gbuffer::Instant::Target),
    );
    let color = source.color.expect("frame t has colour");
    // Frame t's shadows are separated for frame t-1's flow to move, or with the flow off for a
    // target mask to place.
    let separates = |shadow: &ShadowInputs| !shadow.flow.runs() || shadow.previous.is_some();
    let mut separated = shadow_inputs.map(|shadow| {
        separate_shadows::separate(
            color,
            shadow.color_without_dynamic_shadows,
            shadow.mask,
            source.base_color,
            source.material,
            &source_packed.normal_id,
            separates(shadow),
        )
    });
    let (mut shading, mut source_sanitized) = match &separated {
        Some(separated) => (separated.shading.clone(), separated.sanitized),
        None => demodulate::demodulate(color, source.base_color, source.material),
    };
    // With a sun or a sky: their reflections out of the shading, the visibility and the sky
    // kept for the target.
    let reflects = source.sun.is_some() || source.sky.is_some();
    let kept_visibility = reflects.then(|| {
        let removed = highlights::remove(
            &shading,
            &highlights::SourceHighlights {
                sun: source.sun,
                sky: source.sky,
                shadows: shadow_inputs
                    .zip(separated.as_ref())
                    .map(|(shadow, separation)| highlights::ShadowsInShading {
                        mask: shadow.mask,
                        separated: separates(shadow).then_some((
                            color,
                            shadow.color_without_dynamic_shadows,
                            &separation.shadow_layer,
                        )),
                    }),
                base_color: source.base_color,
                material: source.material,
                rays: source.camera.pixel_rays(extent, source.camera.position()),
                geometry: &source_packed.geometry,
                normal_id: &source_packed.normal_id,
            },
        );
        shading = removed.shading;
        source_sanitized += removed.sanitized;
        if let (Some(separation), Some(layer)) = (separated.as_mut(), removed.shadow_layer) {
            separation.shadow_layer = layer;
        }
        let sun = source
            .sun
            .map_or(crate::passes::highlights::NO_SUN, |(sun, _)| sun);
        let kept_sky = removed.kept_sky.zip(source.sky.map(<[Image]>::len));
        (sun, removed.visibility, kept_sky)
    });
    // With a translucency input: what is drawn over the surfaces out of the shading.
    let translucency = source.translucency.map(|input| {
        let separated = translucency::separate(
            &shading,
            &translucency::SourceTranslucency {
                color,
                base_color: source.base_color,
                material: source.material,
                mask: input.mask,
                motion: input.motion,
                surface_motion: source.motion.map(|m| (m, source.motion_vector_scale)),
                opaque: input.opaque,
                geometry: &source_packed.geometry,
                normal_id: &source_packed.normal_id,
            },
        );
        source_sanitized += separated.sanitized;
        shading = separated.shading.clone();
        (separated, input.motion.is_some())
    });
    stages.push(PATCHEX_STAGE_DEMODULATE);
    // The shadows' flow to frame t-1, in frame t's submit: none without frame t-1's mask or
    // with the flow off.
    let flow = shadow_inputs
        .zip(separated.as_ref())
        .map(|(shadow, separated)| {
            let (mask, object_ids, camera) = shadow.previous.filter(|_| shadow.flow.runs())?;
            stages.push(PATCHEX_STAGE_SHADOW_FLOW);
            let previous_mask = separate_shadows::flow_mask(mask, object_ids);
            let start = optical_flow::FlowStart {
                geometry: &source_packed.geometry,
                reprojection: source.camera.reprojection_into(camera, extent),
            };
            Some(optical_flow::frame_flow(
                &separated.mask,
                &previous_mask,
                &shadow.flow,
                shadow.mask_step,
                &start,
            ))
        });
    let jitter_delta = (target.camera.jitter - source.camera.jitter).into();
    let params = warp.params(
        extent,
        target.camera,
        jitter_delta,
        target.motion_vector_scale,
    );
    let motion = target.motion.expect("the target has motion vectors");
    // The shadow layer moved by its flow to the target instant, where no target mask replaces
    // it; the frame's warp completes it where the flow found no receiver.
    let moved_shadows = shadow_inputs
        .zip(separated.as_ref())
        .zip(flow.as_ref())
        .filter(|((shadow, _), _)| separates(shadow) && shadow.target_mask.is_none())
        .and_then(|((_, separated), flow)| {
            let flow = flow.as_ref()?;
            stages.push(PATCHEX_STAGE_SHADOW_WARP);
            Some(warp::warp(
                PATCHEX_WARP_OCCLUSION_MOTION_VECTOR,
                &warp::WarpSources::of(&separated.shadow_layer, &source_packed),
                &warp::WarpTarget::of(&target_packed, flow),
                &warp.shadow_params(extent, target.camera, alpha),
            ))
        });
    let segmented = segmentation::segment(
        &target_packed.normal_id,
        motion,
        target.motion_vector_scale,
        segmentation.growth,
    );
    stages.push(PATCHEX_STAGE_SEGMENT);
    let warped = warp::warp(
        warp.kind,
        &warp::WarpSources::of(&shading, &source_packed),
        &warp::WarpTarget::of(&target_packed, motion),
        &params,
    );
    stages.push(PATCHEX_STAGE_WARP);
    // The G-buffer warp's background fill is a stage of its own in the plugin; here the warp
    // fills as it goes.
    if warp.kind == PATCHEX_WARP_GBUFFER_GUIDED && warp.hole_fill == PATCHEX_HOLE_FILL_BACKGROUND {
        stages.push(PATCHEX_STAGE_FILL_HOLES);
    }
    let mut target_mask_sanitized = 0;
    let no_flow = || Image::new(extent.width as usize, extent.height as usize, 4);
    let shadows = shadow_inputs
        .zip(separated)
        .zip(flow)
        .map(|((shadow, separated), flow)| {
            if !separates(shadow) {
                return Shadows {
                    separated,
                    flow: no_flow(),
                    share: no_flow(),
                };
            }
            // The plugin's frame warp carries the layer beside the shading, with its weights.
            let carried = warp::warp(
                warp.kind,
                &warp::WarpSources::of(&separated.shadow_layer, &source_packed),
                &warp::WarpTarget::of(&target_packed, motion),
                &params,
            );
            let share = match (shadow.target_mask, &moved_shadows) {
                (Some(mask), _) => {
                    stages.push(PATCHEX_STAGE_TARGET_SHADOWS);
                    let sums = target_shadows::sun_share_sums(&separated.shadow_layer);
                    let (share, sanitized) =
                        target_shadows::place(&carried, mask, target.stencil, sums);
                    target_mask_sanitized = sanitized;
                    share
                }
                (None, Some(moved)) => shadow_share(&moved.warped, &carried.warped),
                // The flow off and no mask: the shadows stay where the warp carries them.
                (None, None) => carried.warped,
            };
            Shadows {
                separated,
                flow: flow.unwrap_or_else(no_flow),
                share,
            }
        });
    // Computed always, for the tests of the diagnostics: the plugin's stage runs for them only.
    let lbp = lbp::lbp(&warped.warped);
    let inpainted = networks.any().then(|| {
        stages.extend([PATCHEX_STAGE_INFERENCE, PATCHEX_STAGE_BLEND]);
        inpaint::inpaint(
            networks,
            &warped.warped,
            target.material,
            &segmented.regions,
            &segmented.rects,
        )
    });
    let (output, remodulate_sanitized) = remodulate::remodulate(
        inpainted.as_ref().map_or(&warped.warped, |i| &i.blended),
        &warped.divisor,
        shadows.as_ref().map(|s| &s.share),
        target.base_color,
        target.material,
    );
    if inpainted.is_none() {
        // With the networks, the blend remodulates as it writes.
        stages.push(PATCHEX_STAGE_REMODULATE);
    }
    let mut target_sanitized = remodulate_sanitized + target_mask_sanitized;
    let output = match &kept_visibility {
        Some((sun, kept, kept_sky)) => {
            stages.push(PATCHEX_STAGE_HIGHLIGHTS);
            let (output, sanitized) = highlights::place(
                &output,
                &highlights::TargetHighlights {
                    sun: *sun,
                    kept_visibility: kept,
                    kept_sky: kept_sky.as_ref().map(|(image, levels)| (image, *levels)),
                    source_geometry: &source_packed.geometry,
                    source_normal_id: &source_packed.normal_id,
                    geometry: &target_packed.geometry,
                    normal_id: &target_packed.normal_id,
                    valid: &target_packed.valid,
                    base_color: target.base_color,
                    material: target.material,
                    motion,
                    warp: &params,
                    shadow_share: shadows.as_ref().map(|s| &s.share),
                    target_mask: shadow_inputs
                        .filter(|shadow| separates(shadow))
                        .and_then(|shadow| shadow.target_mask),
                    rays: target.camera.pixel_rays(extent, origin),
                },
            );
            target_sanitized += sanitized;
            output
        }
        None => output,
    };
    let output = match &translucency {
        Some((separated, has_motion)) => {
            stages.push(PATCHEX_STAGE_TRANSLUCENCY);
            let mut output = output;
            target_sanitized += translucency::place(
                &mut output,
                &translucency::TargetTranslucency {
                    layer: &separated.layer,
                    motion: has_motion.then_some(&separated.motion),
                    source_geometry: &source_packed.geometry,
                    source_normal_id: &source_packed.normal_id,
                    target: warp::WarpTarget::of(&target_packed, motion),
                    warp: &params,
                    alpha,
                },
            );
            output
        }
        None => output,
    };
    Extrapolation {
        output,
        warped,
        segmented,
        lbp,
        inpainted,
        shadows,
        source_sanitized,
        target_sanitized,
        source_invalid_geometry: source_packed.invalid_pixels,
        target_invalid_geometry: target_packed.invalid_pixels,
        stages,
    }
}

/// The shadows' share at the target: the `moved` layer where the flow found a receiver (alpha
/// 1), the `carried` one elsewhere, rounded to f16 as stored; alpha the moved layer's.
fn shadow_share(moved: &Image, carried: &Image) -> Image {
    Image::from_fn(moved.width, moved.height, 4, |x, y| {
        let (moved, carried) = (moved.at(x, y), carried.at(x, y));
        let share = |c: usize| round_to_f16(carried[c] + (moved[c] - carried[c]) * moved[3]);
        vec![share(0), share(1), share(2), moved[3]]
    })
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
