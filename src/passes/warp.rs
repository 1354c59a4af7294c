//! The backward warps: each carries frame t's shading to the target instant, marks holes and
//! counts them. They share bindings and parameters (`shaders/include/warp.wgsl`) and differ in
//! how a pixel finds its source: `warp_gbuffer.wgsl` (the default), `warp_motion_vector.wgsl`
//! and `warp_occlusion_motion.wgsl`.

use ash::vk;

use crate::abi::*;
use crate::camera::Camera;
use crate::error::{bail, Result};
use crate::passes::pack_gbuffer::EngineGbuffer;
use crate::passes::{CounterRange, Texture};
use crate::shaders;
use crate::shaders::warp_gbuffer::binding;
/// The three warps' shared parameter block.
pub use crate::shaders::warp_gbuffer::Params;
use crate::vk::image::OwnedImage;
use crate::vk::pipeline::DescriptorWrites;
use crate::vk::recorder::{Pass, Recorder};

pub const MAX_KERNEL_RADIUS: u32 = 3;
pub const MAX_OCCLUSION_SEARCH_RADIUS: u32 = 16;

// The three warps take one parameter block, declared once in the shared include.
const _: () = assert!(
    size_of::<shaders::warp_gbuffer::Params>() == size_of::<shaders::warp_motion_vector::Params>()
        && size_of::<shaders::warp_gbuffer::Params>()
            == size_of::<shaders::warp_occlusion_motion::Params>()
);

/// Which warp runs and its tunable weights, validated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WarpSettings {
    pub kind: PatchexWarpKind,
    pub kernel_radius: u32,
    pub occlusion_search_radius: u32,
    pub sigma_spatial: f32,
    pub sigma_depth: f32,
    pub sigma_normal: f32,
    pub sigma_position: f32,
    pub hole_fill: PatchexHoleFill,
    pub resample: PatchexResample,
}

impl Default for WarpSettings {
    /// The PATCHEX_DEFAULT_* values of the header.
    fn default() -> Self {
        Self {
            kind: PATCHEX_WARP_GBUFFER_GUIDED,
            kernel_radius: PATCHEX_DEFAULT_KERNEL_RADIUS,
            occlusion_search_radius: PATCHEX_DEFAULT_OCCLUSION_SEARCH_RADIUS,
            sigma_spatial: PATCHEX_DEFAULT_SIGMA_SPATIAL,
            sigma_depth: PATCHEX_DEFAULT_SIGMA_DEPTH,
            sigma_normal: PATCHEX_DEFAULT_SIGMA_NORMAL,
            sigma_position: PATCHEX_DEFAULT_SIGMA_POSITION,
            hole_fill: PATCHEX_HOLE_FILL_BACKGROUND,
            resample: PATCHEX_RESAMPLE_CATMULL_ROM,
        }
    }
}

impl WarpSettings {
    pub fn from_abi(settings: &PatchexWarpSettings) -> Result<Self> {
        if settings.kind > PATCHEX_WARP_OCCLUSION_MOTION_VECTOR {
            bail!(
                ErrorInvalidArgument,
                "PatchexWarpSettings.kind {} is not a PATCHEX_WARP_* value",
                settings.kind
            );
        }
        if settings.occlusion_search_radius > MAX_OCCLUSION_SEARCH_RADIUS {
            bail!(
                ErrorInvalidArgument,
                "PatchexWarpSettings.occlusion_search_radius {} exceeds {MAX_OCCLUSION_SEARCH_RADIUS}",
                settings.occlusion_search_radius
            );
        }
        if settings.resample > PATCHEX_RESAMPLE_BILINEAR {
            bail!(
                ErrorInvalidArgument,
                "PatchexWarpSettings.resample {} is not a PATCHEX_RESAMPLE_* value",
                settings.resample
            );
        }
        if settings.hole_fill > PATCHEX_HOLE_FILL_NEAREST {
            bail!(
                ErrorInvalidArgument,
                "PatchexWarpSettings.hole_fill {} is not a PATCHEX_HOLE_FILL_* value",
                settings.hole_fill
            );
        }
        if settings.kernel_radius > MAX_KERNEL_RADIUS {
            bail!(
                ErrorInvalidArgument,
                "PatchexWarpSettings.kernel_radius {} exceeds {MAX_KERNEL_RADIUS}",
                settings.kernel_radius
            );
        }
        for (name, sigma) in [
            ("sigma_spatial", settings.sigma_spatial),
            ("sigma_depth", settings.sigma_depth),
            ("sigma_normal", settings.sigma_normal),
            ("sigma_position", settings.sigma_position),
        ] {
            if !(sigma.is_finite() && sigma > 0.0) {
                bail!(
                    ErrorInvalidArgument,
                    "PatchexWarpSettings.{name} {sigma} must be finite and positive"
                );
            }
        }
        Ok(Self {
            kind: settings.kind,
            kernel_radius: settings.kernel_radius,
            occlusion_search_radius: settings.occlusion_search_radius,
            sigma_spatial: settings.sigma_spatial,
            sigma_depth: settings.sigma_depth,
            sigma_normal: settings.sigma_normal,
            sigma_position: settings.sigma_position,
            hole_fill: settings.hole_fill,
            resample: settings.resample,
        })
    }

    /// These settings as the ABI struct, with an empty chain (for Rust callers: tests, tools).
    pub fn to_abi(&self) -> PatchexWarpSettings {
        PatchexWarpSettings {
            header: PatchexStructHeader::of::<PatchexWarpSettings>(
                PATCHEX_STRUCT_TYPE_WARP_SETTINGS,
            ),
            kind: self.kind,
            kernel_radius: self.kernel_radius,
            sigma_spatial: self.sigma_spatial,
            sigma_depth: self.sigma_depth,
            sigma_normal: self.sigma_normal,
            sigma_position: self.sigma_position,
            occlusion_search_radius: self.occlusion_search_radius,
            hole_fill: self.hole_fill,
            resample: self.resample,
        }
    }

    /// The shaders' parameters for a target seen by `camera`.
    pub fn params(
        &self,
        extent: vk::Extent2D,
        camera: &Camera,
        jitter_delta: [f32; 2],
        motion_scale: [f32; 2],
    ) -> Params {
        Params {
            extent: [extent.width, extent.height],
            jitter_delta,
            motion_scale,
            kernel_radius: self.kernel_radius as i32,
            inv_two_sigma_spatial_sq: 1.0 / (2.0 * self.sigma_spatial * self.sigma_spatial),
            inv_sigma_depth: 1.0 / self.sigma_depth,
            inv_sigma_normal: 1.0 / self.sigma_normal,
            inv_sigma_position: 1.0 / self.sigma_position,
            occlusion_search_radius: self.occlusion_search_radius as i32,
            in_plane_weight: 1.0,
            pixel_angle: camera.pixel_angle(extent.height),
            hole_fill: self.hole_fill,
            resample: self.resample,
            ..Default::default()
        }
    }
}

impl WarpSettings {
    /// The occlusion-motion-vector warp's parameters for the shadow layer, driven by the shadow
    /// mask's flow (displacement to frame t-1) scaled to the target instant. A shadow slides
    /// across its receiver, landing on other points of the same surface, so the agreement test
    /// measures world position only across the target's surface: a source agrees when it has
    /// the target's object id and normal and lies on its plane (a kerb's top is not the road),
    /// and only then is the shadow added. Its fetch weighs texels by that agreement: the layer
    /// is zero on dynamic objects, which must not thin the shadow beside them.
    pub fn shadow_params(&self, extent: vk::Extent2D, camera: &Camera, alpha: f32) -> Params {
        Params {
            in_plane_weight: 0.0,
            agreeing_bilinear: 1,
            ..self.params(extent, camera, [0.0, 0.0], [alpha, alpha])
        }
    }
}

pub struct WarpInputs<'a> {
    pub source_shading: &'a OwnedImage,
    pub source_depth: &'a OwnedImage,
    pub source_normal_id: &'a OwnedImage,
    /// The target's G-buffer, read where each pixel needs it.
    pub target: &'a EngineGbuffer,
    pub motion: Texture,
    /// Both instants' `Cameras`, which the extrapolation writes into its counters first.
    pub cameras: &'a CounterRange,
    pub placeholder: Texture,
    pub placeholder_uint: Texture,
    /// With a shadow input: the shadow layer, warped beside the shading.
    pub layer: Option<CarriedLayer<'a>>,
}

/// Frame t's shadow layer, which a warp carries beside the shading with the same weights (both
/// move with the surfaces), into the shadows' share at the target (`Params::carries_layer`).
#[derive(Clone, Copy)]
pub struct CarriedLayer<'a> {
    pub source: &'a OwnedImage,
    pub share: Texture,
    /// `share` holds the layer as its flow moved it already: the carried layer only fills in
    /// where the flow found no receiver (`Params::shadow_share`).
    pub moved: bool,
}

/// The target's material, when the warp also remodulates (`Params::remodulate`).
pub struct Remodulation {
    pub base_color: Texture,
    pub material: Option<Texture>,
}

/// What a warp stores for a pixel.
#[derive(Clone, Copy)]
pub enum Store<'a> {
    /// The warped shading, with its hole flag and divisor in alpha (`frame_alpha` in
    /// gbuffer.wgsl), for the passes between the warp and remodulation. Also the shadow layer
    /// as its flow moves it.
    Shading,
    /// The shading remodulated: the output, when nothing runs between the warp and it.
    Remodulated(&'a Remodulation),
}

/// The three warps' uniform block: both instants' pixel rays.
pub use crate::shaders::warp_gbuffer::Cameras;
pub const CAMERAS_BYTES: u64 = size_of::<Cameras>() as u64;

/// Frame t's and the target's cameras as the warps rebuild positions with them, and how the
/// target's engine G-buffer reads. Positions are relative to the target's camera, so that they
/// keep their precision however far from the world's origin the cameras are.
pub fn cameras(source: &Camera, target: &EngineGbuffer, extent: vk::Extent2D) -> Cameras {
    let origin = target.camera.position();
    let (s, t) = (
        source.pixel_rays(extent, origin),
        target.camera.pixel_rays(extent, origin),
    );
    Cameras {
        source_position: s.position.into(),
        source_at_origin: s.at_origin.into(),
        source_per_x: s.per_x.into(),
        source_per_y: s.per_y.into(),
        target_position: t.position.into(),
        target_at_origin: t.at_origin.into(),
        target_per_x: t.per_x.into(),
        target_per_y: t.per_y.into(),
        target_depth_curve: target.camera.depth_curve(extent),
        target_far: target.camera.far,
        target_depth_convention: target.camera.depth_convention,
        target_normal_encoding: target.normal_encoding,
        target_has_stencil: target.stencil.is_some() as u32,
        ..Default::default()
    }
}

/// Byte offsets of the counters in `CounterRange`, as `WarpCounters` in the shader declares them.
pub const HOLE_PIXELS_OFFSET: u64 = 0;
pub const OFFSCREEN_PIXELS_OFFSET: u64 = 4;
/// f32 bits of the largest |motion| of a target pixel.
pub const LARGEST_MOTION_OFFSET: u64 = 8;
pub const INVALID_GEOMETRY_OFFSET: u64 = 12;
pub const SANITIZED_OFFSET: u64 = 16;
pub const COUNTER_BYTES: u64 = 20;

/// Where a G-buffer warp lists the holes it leaves to `fill_holes`: the list image (R32_UINT,
/// the frame's size) and its `DeferredHoles` record, which the host sets to (0, 0, 1, 1) first;
/// and the fill's pass that reads them.
pub struct HoleList<'a> {
    pub list: &'a OwnedImage,
    pub deferred: &'a CounterRange,
    pub fill: Pass<'a>,
}

/// Bytes of `DeferredHoles` in `shaders/include/warp.wgsl`.
pub const DEFERRED_HOLES_BYTES: u64 = 16;
/// Its contents before a warp: no hole yet, and an indirect dispatch of (0, 1, 1) workgroups.
pub const NO_DEFERRED_HOLES: [u32; 4] = [0, 0, 1, 1];

/// Records a warp. `holes` is the G-buffer warp's hole list, which it fills in place of the
/// holes' colour (`fill_holes` follows it); the other warps take none.
#[allow(clippy::too_many_arguments)]
pub fn record(
    rec: &mut Recorder,
    pass: Pass,
    params: &Params,
    inputs: &WarpInputs,
    store: Store,
    warped: Texture,
    counters: &CounterRange,
    holes: Option<&HoleList>,
) {
    let bound = rec.bind(pass, |writes| {
        let writes = bind_common(writes, inputs, store, warped, counters);
        match holes {
            Some(holes) => writes
                .image(binding::HOLE_LIST, holes.list)
                .buffer(binding::DEFERRED, holes.deferred),
            None => writes,
        }
    });
    let extent = vk::Extent2D {
        width: params.extent[0],
        height: params.extent[1],
    };
    rec.dispatch(&bound, &storing(params, inputs, store), extent);
}

/// The parameters with what the warp stores switched on.
pub fn storing(params: &Params, inputs: &WarpInputs, store: Store) -> Params {
    let remodulation = match store {
        Store::Remodulated(remodulation) => Some(remodulation),
        Store::Shading => None,
    };
    Params {
        remodulate: remodulation.is_some() as u32,
        has_material: remodulation.is_some_and(|r| r.material.is_some()) as u32,
        carries_layer: inputs.layer.is_some() as u32,
        shadow_share: inputs.layer.is_some_and(|l| l.moved) as u32,
        ..*params
    }
}

/// The bindings of `shaders/include/warp.wgsl`, which every warp and the hole fill declare.
pub fn bind_common<'p>(
    writes: DescriptorWrites<'p>,
    inputs: &WarpInputs<'p>,
    store: Store,
    warped: Texture,
    counters: &CounterRange,
) -> DescriptorWrites<'p> {
    let target = inputs.target;
    let (base_color, material) = match store {
        Store::Remodulated(r) => (r.base_color, r.material.unwrap_or(inputs.placeholder)),
        Store::Shading => (inputs.placeholder, inputs.placeholder),
    };
    // Without a layer its storage binding takes the warped image again, unwritten, so it moves
    // no bytes.
    let unwritten = Texture { bytes: 0, ..warped };
    let (source_layer, share, moved_layer) = match inputs.layer {
        Some(layer) => (
            layer.source.into(),
            layer.share,
            if layer.moved {
                layer.share
            } else {
                inputs.placeholder
            },
        ),
        None => (inputs.placeholder, unwritten, inputs.placeholder),
    };
    writes
        .image(binding::SOURCE_SHADING, inputs.source_shading)
        .image(binding::SOURCE_DEPTH, inputs.source_depth)
        .image(binding::SOURCE_NORMAL_ID, inputs.source_normal_id)
        .image(binding::TARGET_DEPTH, target.depth)
        .image(binding::TARGET_NORMAL, target.normal)
        .image(
            binding::TARGET_STENCIL,
            target.stencil.unwrap_or(inputs.placeholder_uint),
        )
        .image(binding::BASE_COLOR, base_color)
        .image(binding::MATERIAL, material)
        .image(binding::MOTION, inputs.motion)
        .image(binding::WARPED, warped)
        .image(binding::SOURCE_LAYER, source_layer)
        .image(binding::WARPED_LAYER, share)
        .image(binding::MOVED_LAYER, moved_layer)
        .buffer(binding::COUNTERS, counters)
        .buffer(binding::CAMERAS, inputs.cameras)
}
