//! Types that cross the C ABI. cbindgen turns this file into `include/patchex.h`.
//!
//! Every top-level struct starts with `struct_type`, `struct_size` and `next`: the type tag says
//! what the struct is, the size lets later versions append fields, and `next` chains optional
//! extension structs (such as [`PatchexWarpSettings`]). Enumerations arriving from C are plain
//! integers with named constants, so no value the engine writes can be undefined behaviour here.

use std::ffi::{c_char, c_void};

use ash::vk;

// Vulkan types keep their C names in the header (which includes vulkan.h).
pub type VkInstance = vk::Instance;
pub type VkPhysicalDevice = vk::PhysicalDevice;
pub type VkDevice = vk::Device;
pub type VkCommandBuffer = vk::CommandBuffer;
pub type VkImage = vk::Image;
pub type VkImageView = vk::ImageView;
pub type VkFormat = vk::Format;
pub type VkImageLayout = vk::ImageLayout;
pub type VkImageUsageFlags = vk::ImageUsageFlags;
/// Nullable, as the C typedef is.
#[allow(non_camel_case_types)]
pub type PFN_vkGetInstanceProcAddr = Option<vk::PFN_vkGetInstanceProcAddr>;
#[allow(non_camel_case_types)]
pub type PFN_vkGetDeviceProcAddr = Option<vk::PFN_vkGetDeviceProcAddr>;

/// Version of this ABI, returned by `patchex_abi_version`; bumped on any incompatible change.
pub const PATCHEX_ABI_VERSION: u32 = 15;

/// 0 or 1; any other value is rejected as an invalid argument.
pub type PatchexBool = u32;

/// Tag in the first field of every versioned struct.
pub type PatchexStructType = u32;
pub const PATCHEX_STRUCT_TYPE_CREATE_INFO: PatchexStructType = 1;
pub const PATCHEX_STRUCT_TYPE_FRAME_DESC: PatchexStructType = 2;
pub const PATCHEX_STRUCT_TYPE_EXTRAPOLATE_DESC: PatchexStructType = 3;
pub const PATCHEX_STRUCT_TYPE_WARP_SETTINGS: PatchexStructType = 4;
pub const PATCHEX_STRUCT_TYPE_FRAME_STATS: PatchexStructType = 5;
pub const PATCHEX_STRUCT_TYPE_SEGMENTATION_SETTINGS: PatchexStructType = 6;
pub const PATCHEX_STRUCT_TYPE_DIAGNOSTICS: PatchexStructType = 7;
pub const PATCHEX_STRUCT_TYPE_SHADOW_INPUT: PatchexStructType = 8;
pub const PATCHEX_STRUCT_TYPE_SHADOW_FLOW_SETTINGS: PatchexStructType = 9;
pub const PATCHEX_STRUCT_TYPE_SHADOW_DIAGNOSTICS: PatchexStructType = 10;
pub const PATCHEX_STRUCT_TYPE_NETWORK_WEIGHTS: PatchexStructType = 11;
pub const PATCHEX_STRUCT_TYPE_NETWORK_SETTINGS: PatchexStructType = 12;
pub const PATCHEX_STRUCT_TYPE_NETWORK_PRECISION: PatchexStructType = 13;
pub const PATCHEX_STRUCT_TYPE_NETWORK_MEMORY: PatchexStructType = 14;
pub const PATCHEX_STRUCT_TYPE_TARGET_SHADOW_INPUT: PatchexStructType = 15;
pub const PATCHEX_STRUCT_TYPE_SUN_LIGHT: PatchexStructType = 16;
pub const PATCHEX_STRUCT_TYPE_TRANSLUCENCY_INPUT: PatchexStructType = 17;
pub const PATCHEX_STRUCT_TYPE_SKY_LIGHT: PatchexStructType = 18;

/// The first fields of every versioned struct, read before the rest.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PatchexStructHeader {
    pub struct_type: PatchexStructType,
    /// `sizeof` the struct as the caller's header declares it.
    pub struct_size: u32,
    /// Optional chain of extension structs, each starting with a `PatchexStructHeader`.
    pub next: *const c_void,
}

impl PatchexStructHeader {
    /// The header of a `T` with an empty chain, for Rust callers of the ABI (tests, tools).
    pub fn of<T>(struct_type: PatchexStructType) -> Self {
        Self {
            struct_type,
            struct_size: size_of::<T>() as u32,
            next: std::ptr::null(),
        }
    }
}

/// Trade of speed against accuracy: which sub-tasks a context can run, cheapest first (README,
/// Speed against accuracy, has their measured cost and quality). The preset fixes what a context
/// compiles and may allocate; per frame the engine runs less by leaving the shadow input off or
/// switching networks off (PatchexNetworkSettings), and a frame without dynamic objects runs no
/// network whatever the preset.
pub type PatchexPreset = u32;
/// Demodulate, warp (PatchexWarpSettings), remodulate. Holes keep the warp's nearest colour.
pub const PATCHEX_PRESET_WARP_ONLY: PatchexPreset = 0;
/// The warp, then PatchEX's two inpainting networks repair the foreground-interaction and
/// near-background patches around dynamic objects (far background keeps the warp). Compiles
/// the networks at create (seconds on a CPU driver) and holds their tensors for a patch as
/// large as the maximum extent.
pub const PATCHEX_PRESET_NETWORKS: PatchexPreset = 1;
/// The warp, and the shadow sub-task on frames that come with a PatchexShadowInput: the shadows
/// of dynamic objects tracked and moved on their own. Presets without it refuse the input.
pub const PATCHEX_PRESET_WARP_AND_SHADOWS: PatchexPreset = 2;
/// Everything, PatchEX as published: the warp, the shadow sub-task (with a shadow input) and the
/// inpainting networks.
pub const PATCHEX_PRESET_FULL: PatchexPreset = 3;

/// How the depth image encodes depth.
pub type PatchexDepthConvention = u32;
/// Linear view-space depth: distance along the camera's forward axis, in world units.
pub const PATCHEX_DEPTH_LINEAR_VIEW_Z: PatchexDepthConvention = 0;
/// Hardware depth, 0 at the near plane and 1 at the far plane.
pub const PATCHEX_DEPTH_HARDWARE: PatchexDepthConvention = 1;
/// Reversed hardware depth, 1 at the near plane and 0 at the far plane (or at infinity).
pub const PATCHEX_DEPTH_HARDWARE_REVERSED: PatchexDepthConvention = 2;

/// How the normal image encodes unit world-space normals.
pub type PatchexNormalEncoding = u32;
/// xyz in [-1, 1] (float formats, or SNORM).
pub const PATCHEX_NORMAL_SIGNED: PatchexNormalEncoding = 0;
/// xyz * 0.5 + 0.5 (UNORM formats).
pub const PATCHEX_NORMAL_UNORM: PatchexNormalEncoding = 1;

/// Which backward warp carries frame t to the target instant.
pub type PatchexWarpKind = u32;
/// Joint bilateral gather guided by the target's G-buffer (ExtraSS). The default.
pub const PATCHEX_WARP_GBUFFER_GUIDED: PatchexWarpKind = 0;
/// Plain motion-vector reprojection (bilinear); ghosts at disocclusions.
pub const PATCHEX_WARP_MOTION_VECTOR: PatchexWarpKind = 1;
/// Occlusion motion vectors (Zeng et al. 2021): disoccluded pixels borrow the neighbourhood's
/// motion that lands on matching geometry instead of ghosting the occluder.
pub const PATCHEX_WARP_OCCLUSION_MOTION_VECTOR: PatchexWarpKind = 2;

/// Severity passed to the log callback.
pub type PatchexLogLevel = u32;
pub const PATCHEX_LOG_ERROR: PatchexLogLevel = 0;
pub const PATCHEX_LOG_WARNING: PatchexLogLevel = 1;
pub const PATCHEX_LOG_INFO: PatchexLogLevel = 2;

/// Called from the thread that made the call being reported; `message` is valid only during
/// the callback. NULL for no logging.
pub type PatchexLogCallback = Option<
    unsafe extern "C" fn(user_data: *mut c_void, level: PatchexLogLevel, message: *const c_char),
>;

/// An engine-owned image, imported for one call. The plugin never takes ownership.
///
/// `image == VK_NULL_HANDLE` means "not provided", allowed only for optional inputs.
/// `width`/`height` are the image's full size; the plugin uses the top-left frame extent of it.
/// `layout` is the layout the image is in when the recorded commands execute; the plugin's
/// commands return it to that layout. UNDEFINED and PREINITIALIZED are rejected.
/// `usage` is the usage the image was created with: inputs need SAMPLED, the output STORAGE.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct PatchexImage {
    pub image: VkImage,
    /// A 2D view of mip 0, layer 0; for depth/stencil formats, of the one aspect to read.
    pub view: VkImageView,
    pub format: VkFormat,
    pub width: u32,
    pub height: u32,
    pub layout: VkImageLayout,
    pub usage: VkImageUsageFlags,
}

/// Camera of one instant. Matrices are column-major (glam/GLM order), right- or left-handed,
/// mapping to Vulkan clip space: NDC y grows down the image and depth follows `depth_convention`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct PatchexCamera {
    /// World to view.
    pub view: [f32; 16],
    /// View to clip, including this instant's jitter, exactly as the G-buffer was rendered.
    pub projection: [f32; 16],
    /// Sub-pixel offset of the sample positions, in pixels (x right, y down).
    pub jitter: [f32; 2],
    /// Distance to the near plane, in world units, > 0. It must be where the projection puts
    /// depth 0 (1 when reversed; either with linear depth), within 1%; otherwise the call fails
    /// with PATCHEX_RESULT_ERROR_INVALID_ARGUMENT. Named `near_plane` because `<windows.h>` defines
    /// `near` and `far` as empty macros.
    pub near_plane: f32,
    /// Distance to the far plane, > near_plane; may be +infinity (infinite far plane).
    pub far_plane: f32,
    pub depth_convention: PatchexDepthConvention,
}

/// The geometry buffers of one instant.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct PatchexGeometry {
    /// Single channel: R32_SFLOAT, R16_SFLOAT or D32_SFLOAT/D16_UNORM/D24_UNORM_S8_UINT/
    /// D32_SFLOAT_S8_UINT through a depth-aspect view. Encoding given by the camera.
    pub depth: PatchexImage,
    /// World-space normals in RGB, encoded per `normal_encoding`.
    pub normal: PatchexImage,
    pub normal_encoding: PatchexNormalEncoding,
    /// Optional: dynamic-object id, 0 for static geometry. R8_UINT, or the stencil aspect of
    /// S8_UINT, D16_UNORM_S8_UINT, D24_UNORM_S8_UINT or D32_SFLOAT_S8_UINT.
    pub stencil: PatchexImage,
    /// Motion to the previous instant (for a target: to the submitted frame t). After scaling,
    /// the position of the same surface point in the earlier frame minus this pixel, in pixels,
    /// excluding jitter. Required by `patchex_extrapolate`, optional for submitted frames.
    pub motion_vectors: PatchexImage,
    /// Multiplies the stored motion vectors: (1, 1) for backward motion in pixels,
    /// (width, height) for UV, negated for forward (current minus previous) vectors.
    pub motion_vector_scale: [f32; 2],
    pub camera: PatchexCamera,
}

/// Arguments of `patchex_create`.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PatchexCreateInfo {
    /// PATCHEX_STRUCT_TYPE_CREATE_INFO, sizeof(PatchexCreateInfo), optional chain
    /// (PatchexWarpSettings, PatchexSegmentationSettings and PatchexShadowFlowSettings set the
    /// context's defaults).
    pub header: PatchexStructHeader,
    pub instance: VkInstance,
    pub physical_device: VkPhysicalDevice,
    pub device: VkDevice,
    /// Required: every Vulkan function is loaded through it (or `get_device_proc_addr`).
    pub get_instance_proc_addr: PFN_vkGetInstanceProcAddr,
    /// Optional: device-level functions come from it when given (skips loader trampolines).
    pub get_device_proc_addr: PFN_vkGetDeviceProcAddr,
    /// Queue family of every command buffer the engine will pass; must support compute.
    pub queue_family_index: u32,
    /// Largest frame the context will be given. Internal images grow to the largest frame seen.
    pub max_width: u32,
    pub max_height: u32,
    /// How many frames the engine records ahead of the GPU (1 to 8): resources used by frame F
    /// are reused at frame F + frames_in_flight.
    pub frames_in_flight: u32,
    pub preset: PatchexPreset,
    pub log_callback: PatchexLogCallback,
    pub log_user_data: *mut c_void,
}

impl PatchexCreateInfo {
    /// Create info for Rust callers of the ABI (tests, tools): the warp-only preset, two frames
    /// in flight, device functions through the loader, no log callback.
    pub fn new(
        instance: VkInstance,
        physical_device: VkPhysicalDevice,
        device: VkDevice,
        get_instance_proc_addr: vk::PFN_vkGetInstanceProcAddr,
        queue_family_index: u32,
        max_width: u32,
        max_height: u32,
    ) -> Self {
        Self {
            header: PatchexStructHeader::of::<Self>(PATCHEX_STRUCT_TYPE_CREATE_INFO),
            instance,
            physical_device,
            device,
            get_instance_proc_addr: Some(get_instance_proc_addr),
            get_device_proc_addr: None,
            queue_family_index,
            max_width,
            max_height,
            frames_in_flight: 2,
            preset: PATCHEX_PRESET_WARP_ONLY,
            log_callback: None,
            log_user_data: std::ptr::null_mut(),
        }
    }
}

/// Frame t: what `patchex_submit_gbuffers` reads.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PatchexFrameDesc {
    /// PATCHEX_STRUCT_TYPE_FRAME_DESC, sizeof(PatchexFrameDesc), optional chain
    /// (PatchexShadowInput turns the shadow sub-task on for this frame; PatchexShadowFlowSettings
    /// overrides the context's flow settings for it; PatchexSunLight moves the sun's highlights
    /// with the view; PatchexTranslucencyInput moves what is drawn over the surfaces by its own
    /// motion).
    pub header: PatchexStructHeader,
    /// The engine's frame number. Without `reset` it must exceed the previous submit's
    /// (PATCHEX_RESULT_ERROR_OUT_OF_ORDER otherwise); a gap (not previous + 1) drops history as
    /// `reset` does. Any value is allowed with `reset`, including a lower or equal one and after
    /// UINT64_MAX: a reset may restart the numbering. patchex_get_frame_stats finds frames by
    /// this index (the newest frame of that index, when a reset repeated one).
    pub frame_index: u64,
    /// 1 for a camera cut, teleport or level load: history from earlier frames is dropped, and
    /// `frame_index` may start over.
    pub reset: PatchexBool,
    /// Queue family of the command buffer's pool.
    pub queue_family_index: u32,
    pub width: u32,
    pub height: u32,
    /// Final linear HDR colour, before tone mapping and UI; non-negative, up to 65504. Best
    /// taken before the translucency pass as well, the lit opaque surfaces alone: then draw the
    /// translucency for the target instant over the extrapolated frame, as over a rendered one
    /// (the integration guide says what that costs). Colour that holds its translucency wants a
    /// PatchexTranslucencyInput.
    pub color: PatchexImage,
    /// Base colour (albedo) in RGB. patchex divides the colour by it (plus the specular
    /// reflectance) to warp lighting rather than texture, and multiplies by the target's. Where
    /// that sum is below 0.05 in every channel (black and emissive materials) the result is
    /// never brighter than the colour the surface had, and HDR colour up to 65504 comes back
    /// unchanged over any base colour.
    pub base_color: PatchexImage,
    /// Optional: R metallic, G specular, B roughness (Unreal's GBufferB). Absent means
    /// metallic 0, specular 0.5, roughness 0.5. Roughness is read by the inpainting networks
    /// only; a two-channel image reads roughness 0.
    pub material: PatchexImage,
    pub geometry: PatchexGeometry,
}

/// The target instant: what `patchex_extrapolate` reads and writes.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PatchexExtrapolateDesc {
    /// PATCHEX_STRUCT_TYPE_EXTRAPOLATE_DESC, sizeof(PatchexExtrapolateDesc), optional chain
    /// (PatchexWarpSettings and PatchexSegmentationSettings override the context's defaults
    /// for this call; PatchexDiagnostics and PatchexShadowDiagnostics ask for the per-pixel
    /// intermediate results; PatchexTargetShadowInput gives the shadows at the target).
    pub header: PatchexStructHeader,
    pub queue_family_index: u32,
    /// Position of the target between frame t (0) and frame t+1 (1), in (0, 1].
    pub alpha: f32,
    /// Must equal the submitted frame's extent.
    pub width: u32,
    pub height: u32,
    pub base_color: PatchexImage,
    /// As PatchexFrameDesc's, at the target instant.
    pub material: PatchexImage,
    pub geometry: PatchexGeometry,
    /// Receives the extrapolated linear HDR colour. R16G16B16A16_SFLOAT with STORAGE usage.
    pub output: PatchexImage,
}

/// The warp settings a context uses unless told otherwise: a 3x3 gather; a texel keeps most of
/// its weight within ~5% relative depth, ~0.1 of (1 - cos) of normal angle (about 25 degrees),
/// and 1.5 pixel footprints of world position.
pub const PATCHEX_DEFAULT_KERNEL_RADIUS: u32 = 1;
pub const PATCHEX_DEFAULT_SIGMA_SPATIAL: f32 = 0.75;
pub const PATCHEX_DEFAULT_SIGMA_DEPTH: f32 = 0.05;
pub const PATCHEX_DEFAULT_SIGMA_NORMAL: f32 = 0.1;
pub const PATCHEX_DEFAULT_SIGMA_POSITION: f32 = 1.5;
pub const PATCHEX_DEFAULT_OCCLUSION_SEARCH_RADIUS: u32 = 8;
/// The segmentation's default k_x and k_y. `patchex calibrate` measures a mover's wake (the
/// high-variation background connected to it) at about a pixel on the generated training scenes,
/// which these grow past at their speeds; motion does not predict it well enough to fit k.
pub const PATCHEX_DEFAULT_GROWTH_X: f32 = 1.9;
pub const PATCHEX_DEFAULT_GROWTH_Y: f32 = 3.1;

/// Chainable on PatchexCreateInfo (context default) or PatchexExtrapolateDesc (this call).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PatchexWarpSettings {
    /// PATCHEX_STRUCT_TYPE_WARP_SETTINGS, sizeof(PatchexWarpSettings), chain.
    pub header: PatchexStructHeader,
    pub kind: PatchexWarpKind,
    /// G-buffer-guided warp: gather radius in pixels, 0 to 3 (a (2r+1)^2 kernel).
    pub kernel_radius: u32,
    /// Gaussian sigma of the spatial weight, in pixels (> 0).
    pub sigma_spatial: f32,
    /// Tolerance on relative depth for dynamic objects (> 0).
    pub sigma_depth: f32,
    /// Tolerance on 1 - dot(normals) (> 0).
    pub sigma_normal: f32,
    /// Tolerance on world-position distance for static geometry, in pixel footprints on the
    /// target's surface (> 0).
    pub sigma_position: f32,
    /// Occlusion-motion-vector warp: radius in pixels searched for a better motion vector,
    /// 0 to 16 (every second pixel is tried).
    pub occlusion_search_radius: u32,
    /// G-buffer-guided warp: how a hole (a pixel whose own motion finds no agreeing surface in
    /// frame t) is filled. PATCHEX_HOLE_FILL_BACKGROUND, 0, is the default.
    pub hole_fill: PatchexHoleFill,
    /// G-buffer-guided warp: how frame t is resampled on static surfaces.
    /// PATCHEX_RESAMPLE_CATMULL_ROM, 0, is the default.
    pub resample: PatchexResample,
}

/// `PatchexWarpSettings.resample`.
pub type PatchexResample = u32;
/// Catmull-Rom over the 16 texels around the source point, held within the range of the four
/// nearest, where all 16 show the pixel's static surface; bilinear elsewhere and on moving
/// objects. Keeps the finest detail, which bilinear halves at a half-texel shift: lower FLIP,
/// for more texel reads in the warp.
pub const PATCHEX_RESAMPLE_CATMULL_ROM: PatchexResample = 0;
/// The four nearest texels, weighted by position: the cheaper fetch.
pub const PATCHEX_RESAMPLE_BILINEAR: PatchexResample = 1;

/// `PatchexWarpSettings.hole_fill`.
pub type PatchexHoleFill = u32;
/// From the side the disocclusion uncovers: a mean of frame t's texels within 12 pixels of the
/// pixel's own source point, each weighted by how closely its normal, depth and object id match
/// the target pixel's own surface and by its distance. The occluder that hid the pixel is
/// nearer than the surface it uncovers, so it is not smeared into the hole; scenery entering at
/// the frame's edge (an off-screen source point) takes the texels inside the edge that face the
/// same way. Where no texel within 12 pixels shows the pixel's surface (sky entering beside an
/// occluder that filled frame t's edge), texels within 96 pixels are weighed instead.
pub const PATCHEX_HOLE_FILL_BACKGROUND: PatchexHoleFill = 0;
/// The source texel nearest to where the pixel's own motion lands: usually the occluder itself,
/// which leaves a halo of it around moving silhouettes. For comparison.
pub const PATCHEX_HOLE_FILL_NEAREST: PatchexHoleFill = 1;

/// Chainable on PatchexCreateInfo (context default) or PatchexExtrapolateDesc (this call).
/// Foveated segmentation (PatchEX Algorithm 1): the near-background region of a dynamic object
/// is its bounding rectangle grown by `growth_x * mean|v_x|` left and right and by
/// `growth_y * mean|v_y|` above and below, where v is the motion of the object's pixels.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PatchexSegmentationSettings {
    /// PATCHEX_STRUCT_TYPE_SEGMENTATION_SETTINGS, sizeof(PatchexSegmentationSettings), chain.
    pub header: PatchexStructHeader,
    /// k_x, finite and 0 to 64. The default is fitted by `patchex calibrate`.
    pub growth_x: f32,
    /// k_y, finite and 0 to 64.
    pub growth_y: f32,
}

/// Chainable on PatchexFrameDesc, with PATCHEX_PRESET_WARP_AND_SHADOWS or PATCHEX_PRESET_FULL:
/// the shadows cast by dynamic objects in frame t. Warping moves what is painted on surfaces,
/// but a moving character's shadow moves over ground whose motion vectors are zero; with this
/// input patchex separates that shadow from frame t, estimates its motion from the masks of
/// frames t-1 and t (Farneback dense optical flow, at half resolution, or coarser where the
/// context's frames have been larger than 1280 pixels a side), moves it to the target
/// instant with the occlusion-motion-vector warp, and swaps it for the shadow the frame's own
/// warp carried along. Without it the shadow sub-task does
/// not run and costs nothing; its motion is known from the second consecutive frame with it.
///
/// Separation, per pixel of frame t, with m the demodulation factor of the frame's colour: the
/// shadow layer is (color - color_without_dynamic_shadows) / m, on static pixels (dynamic
/// objects keep the shadows on them, which move with them). Nothing is divided by the mask, so
/// a fully shadowed pixel (mask 0) is as stable as a lit one. On static target pixels the
/// shading becomes max(warped shading - carried layer + moved layer, 0), where the moved layer
/// found a receiver.
///
/// What an engine provides: the mask is the sun's visibility through dynamic casters only
/// (1 lit, 0 fully shadowed; static casters excluded), and the colour is frame t lit as if
/// dynamic casters cast no shadow. A deferred renderer gets both from its directional light's
/// pass: evaluate the light once with the dynamic-caster shadow term and once without it
/// (Unreal: a second projection of the movable-object shadow into its own screen shadow mask,
/// and SceneColor plus (1 - mask) times the light's contribution; see plugin-unreal/README.md).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PatchexShadowInput {
    /// PATCHEX_STRUCT_TYPE_SHADOW_INPUT, sizeof(PatchexShadowInput), chain.
    pub header: PatchexStructHeader,
    /// Visibility of the sun through dynamic casters, in [0, 1], in the first channel. Float or
    /// UNORM formats. Values outside [0, 1] or NaN are sanitised and counted.
    pub mask: PatchexImage,
    /// Frame t's linear HDR colour without the shadows of dynamic casters; formats as `color`.
    pub color_without_dynamic_shadows: PatchexImage,
}

/// Chainable on PatchexExtrapolateDesc, when frame t came with a PatchexShadowInput: the
/// dynamic casters' shadows at the target instant, in place of the shadows the flow moves there.
/// The flow moves frame t's shadows but keeps their shape; this mask has the target's shape (a
/// walking character's legs cast where they are now). Optional, and a trade: it costs the
/// engine a pass, and patchex two small passes (the sun's share of frame t's light, then the
/// shadows placed), against shadows that match the target.
///
/// How patchex uses it, on static target pixels: the shading warped without the dynamic
/// shadows loses (1 - mask) times the share of its light that the sun gives. That share is frame
/// t's own where the warp carried it from a shadowed texel (the layer over the darkness there),
/// and the mean over frame t's shadows elsewhere. Dynamic objects keep the shadows on them, as
/// without this input. It takes effect from the second consecutive frame with a shadow input,
/// as the flow does (before that, shadows stay where the warp carries them), or from the first
/// with the flow off (PatchexShadowFlowSettings.levels 0), which an engine that gives this
/// input on every extrapolation should choose: its submits then run no flow.
///
/// What an engine provides: the same mask as PatchexShadowInput's, at the target instant: the
/// sun's visibility through dynamic casters only, at the target's pixels. A depth-only pass of
/// the dynamic casters into the sun's shadow map at their target pose, projected against the
/// target depth the engine already has for the G-buffer.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PatchexTargetShadowInput {
    /// PATCHEX_STRUCT_TYPE_TARGET_SHADOW_INPUT, sizeof(PatchexTargetShadowInput), chain.
    pub header: PatchexStructHeader,
    /// Visibility of the sun through dynamic casters at the target, in [0, 1], in the first
    /// channel. Float or UNORM formats. Values outside [0, 1] or NaN are sanitised and counted.
    pub mask: PatchexImage,
}

/// Chainable on PatchexFrameDesc: the sun (one directional light) that lit frame t, so that its
/// highlights move with the view instead of staying where frame t saw them. Without it, patchex
/// warps the light a surface reflects towards the camera as if it did not depend on the view: a
/// glossy floor's highlight stays on the floor where frame t saw it, and a moving camera sees it
/// stuck to the surface instead of sliding.
///
/// How patchex uses it: in frame t it takes the sun's specular reflection out of the shading it
/// warps, and at the target it adds the reflection back as the target's view sees it, times the
/// visibility carried from frame t by the motion vectors (and, with a shadow input, times the
/// dynamic shadows' share at the target). The reflection is the one the glTF metallic-roughness
/// model and Unreal's default lit shading evaluate: a GGX distribution of alpha = roughness^2
/// (roughness below 0.02 evaluated as 0.02), height-correlated Smith visibility and Schlick's
/// Fresnel from a specular colour of lerp(0.08 * specular, base colour, metallic), read from
/// `base_color` and `material` (R metallic, G specular, B roughness; without a material image,
/// metallic 0, specular 0.5, roughness 0.5). The target's `material` should be given too. Light
/// from the sky (without a PatchexSkyLight) and other lights stays in the warped shading. A
/// renderer with another specular model leaves the difference where frame t had it.
///
/// On moving objects (a non-zero stencil id), whose surfaces may turn towards or away from the
/// sun between frames, it also relights the sun's diffuse reflection: Lambert's, base colour
/// times (1 - metallic) over pi, times the sun's illuminance and the cosine to the sun. It adds
/// the difference between that term at the target's normal and at frame t's normal where the
/// warp took the pixel from, times the same visibility. Static surfaces do not turn: their
/// diffuse light is warped as it is.
///
/// It costs patchex one pass over frame t's pixels in the submit, and one over the target's.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PatchexSunLight {
    /// PATCHEX_STRUCT_TYPE_SUN_LIGHT, sizeof(PatchexSunLight), chain.
    pub header: PatchexStructHeader,
    /// World-space direction from a surface towards the sun, in the normals' space; any finite
    /// length above 0 (patchex normalises it).
    pub direction: [f32; 3],
    /// The light's colour times its intensity, in linear RGB, as the engine shades with it and in
    /// the units of `color` (with any pre-exposure): a white Lambertian surface facing the sun
    /// shows illuminance / pi. Finite, >= 0.
    pub illuminance: [f32; 3],
    /// Visibility of the sun at frame t's pixels, in [0, 1], in the first channel: the shadow
    /// term the engine lit `color` with, through every caster; with a PatchexShadowInput, through
    /// the static casters alone (the term `color_without_dynamic_shadows` was lit with). Float or
    /// UNORM formats. Values outside [0, 1] or NaN are sanitised and counted.
    pub visibility: PatchexImage,
}

/// Largest side of a PatchexSkyLight's map.
pub const PATCHEX_MAX_SKY_SIDE: u32 = 1024;
/// Most mips of a PatchexSkyLight's map patchex reads.
pub const PATCHEX_MAX_SKY_MIPS: u32 = 8;

/// Chainable on PatchexFrameDesc: the sky that lit frame t, so that its reflection in glossy
/// surfaces moves with the view, as PatchexSunLight moves the sun's highlights. Without it, the
/// sky a floor or a car body mirrors stays where frame t saw it, carried with the surface.
///
/// How patchex uses it: in frame t it takes the sky's specular reflection out of the shading it
/// warps, and at the target it adds the reflection the target's view sees, from the target's own
/// normals and material. The reflection is the sky's radiance in the mirror direction (read from
/// the map bilinearly, and between its two mips around the pixel's roughness when it has
/// several) times the split-sum environment BRDF in Karis' analytic fit, the one Unreal's
/// mobile renderer uses, from the specular colour and roughness PatchexSunLight describes
/// (roughness below 0.02 evaluated as 0.02). No shadow or occlusion takes from it. An engine
/// whose sky reflection differs (occluded, a lookup-table BRDF, prefiltered other than the mips
/// say) leaves the difference where frame t had it; reflection captures and screen-space
/// reflections stay in the warped shading. Given with or without a PatchexSunLight.
///
/// It costs patchex nothing more than PatchexSunLight's two passes (which run for it alone when
/// there is no sun), and a copy of the map, which the first pass makes.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PatchexSkyLight {
    /// PATCHEX_STRUCT_TYPE_SKY_LIGHT, sizeof(PatchexSkyLight), chain.
    pub header: PatchexStructHeader,
    /// The sky's radiance by direction, in linear RGB and the units of `color`: a square
    /// octahedral map of the normals' world space, 2 to PATCHEX_MAX_SKY_SIDE texels a side,
    /// whole (not the frame's extent). Texel (i, j) of a map of side n shows the direction
    /// normalize(x, y, 1 - |x| - |y|) for (x, y) = 2 * (i + 0.5, j + 0.5) / n - 1, where
    /// |x| + |y| <= 1; elsewhere the direction normalize(sx * (1 - |y|), sy * (1 - |x|),
    /// 1 - |x| - |y|), sx and sy the signs of x and y (+ for 0). The formats `color` takes;
    /// texels that are NaN, negative, infinite or beyond 65504 are sanitised and counted in
    /// `source_sanitized_pixels`. `view` shows the map's first `mip_levels` mips.
    pub radiance: PatchexImage,
    /// 0 or 1: one map, the sky as a mirror reflects it, read whatever the roughness. 2 to
    /// PATCHEX_MAX_SKY_MIPS: mip m (an octahedral map of side >> m texels a side, at least 2)
    /// holds the sky as a surface of roughness m / (mip_levels - 1) reflects it, prefiltered as
    /// the engine prefilters its sky light; patchex reads between the two mips around each
    /// pixel's roughness.
    pub mip_levels: u32,
}

/// Chainable on PatchexFrameDesc: where frame t's colour holds something drawn over the opaque
/// surface of the G-buffer after lighting: alpha-blended glass and foliage, particles (smoke,
/// sparks, fire), emissive effects composited over the scene. Without it, patchex takes every
/// pixel's colour for the light of the surface in the G-buffer: it divides a smoke puff by the
/// albedo of the wall behind it and moves it with the wall.
///
/// How patchex uses it: in frame t, where the mask covers a pixel, it takes the opaque surface
/// behind for the shading it warps: `opaque_color` where the engine gives it, else an estimate
/// from the shading of nearby uncovered texels of the same surface. It keeps the rest as a
/// premultiplied layer over it: colour = layer + (1 - mask) * surface. At the target, it moves
/// that layer by its own motion, extrapolated at constant velocity to the target instant (each
/// texel splatted where its motion takes it), or, without motion vectors of its own, as the
/// target's motion vectors say the surface behind it moves; then blends it over the
/// extrapolated frame. Without `opaque_color`, a layer the same all around a pixel (inside a
/// pane of glass, a full-screen tint), one covering a pixel less than a fifth (thin smoke), one
/// whose own motion is that of the surface behind it to within half a pixel (given frame t's
/// geometry motion vectors), and a fully covered region far from any uncovered texel stay in the
/// colour and move with the surface behind them, where the estimate would only add its errors.
/// With `opaque_color`, only a layer whose motion is the surface's to within a tenth of a pixel
/// stays (glass set in a wall, a decal): the warp follows that surface's geometry more sharply
/// than the splat would.
///
/// What an engine provides, after the conventions of FSR's transparency-and-composition mask:
/// the mask's first channel is the opacity with which everything drawn after the G-buffer's
/// lighting covers the pixel: 1 - the product of (1 - alpha) over the translucent draws there
/// (additive draws: their luminance over the pixel's, held to 1). A forward pass writes it with
/// the blend state it draws colour with, into one more render target. The motion vectors are
/// those draws' own, written the same way (alpha-weighted), in the convention of the geometry's.
///
/// It costs patchex one pass over frame t's covered pixels in the submit and one over the
/// target's in each extrapolation, and 12 bytes a pixel of memory from the first frame with it.
/// `opaque_color` costs the engine a copy of its scene colour before the translucency pass
/// (none where that pass draws into a target of its own), and saves patchex the estimate.
///
/// It is for colour handed over after the translucency pass. An engine that hands over its
/// colour from before that pass and draws its translucency over the extrapolated frame gives no
/// mask: nothing in that colour is translucent, and every translucent pixel is then as it is at
/// the target, which this input only estimates.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PatchexTranslucencyInput {
    /// PATCHEX_STRUCT_TYPE_TRANSLUCENCY_INPUT, sizeof(PatchexTranslucencyInput), chain.
    pub header: PatchexStructHeader,
    /// Coverage of frame t's pixels by translucency, in [0, 1], in the first channel: 0 shows the
    /// G-buffer's surface alone. Float or UNORM formats. Values outside [0, 1] or NaN are
    /// sanitised and counted.
    pub mask: PatchexImage,
    /// Optional: the translucency's own motion to the previous instant, read where the mask is
    /// above 0; formats, meaning and scale as PatchexGeometry.motion_vectors. Non-finite vectors
    /// are taken as zero and counted.
    pub motion_vectors: PatchexImage,
    pub motion_vector_scale: [f32; 2],
    /// Optional: frame t's lit colour before the translucency pass, in the colour's space (the
    /// engine's scene colour copied before it draws its translucency). Given it, patchex takes
    /// the layer apart exactly, layer = colour - (1 - mask) * opaque colour, where without it it
    /// estimates the surface behind. Formats as PatchexFrameDesc.color; texels that are NaN,
    /// negative, infinite or beyond 65504 are sanitised and counted.
    pub opaque_color: PatchexImage,
}

/// Farneback optical-flow settings a context uses unless told otherwise: four pyramid levels
/// (motion up to about 8 * window_radius texels of the finest level), one iteration per level
/// (on the generated validation split, two iterations a level or a fifth level scored lower over
/// the shadows), a 15x15 window, and a 5x5 polynomial fit with sigma 1.1 (Farneback's own
/// choice for that size).
pub const PATCHEX_DEFAULT_FLOW_LEVELS: u32 = 4;
pub const PATCHEX_DEFAULT_FLOW_ITERATIONS: u32 = 1;
pub const PATCHEX_DEFAULT_FLOW_WINDOW_RADIUS: u32 = 7;
pub const PATCHEX_DEFAULT_FLOW_POLY_RADIUS: u32 = 2;
pub const PATCHEX_DEFAULT_FLOW_POLY_SIGMA: f32 = 1.1;

/// Chainable on PatchexCreateInfo (context default) or PatchexFrameDesc (this frame), with a
/// shadows preset (PATCHEX_PRESET_WARP_AND_SHADOWS or FULL): the dense optical flow that
/// tracks the dynamic-caster shadow mask between frames t-1 and t.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PatchexShadowFlowSettings {
    /// PATCHEX_STRUCT_TYPE_SHADOW_FLOW_SETTINGS, sizeof(PatchexShadowFlowSettings), chain.
    pub header: PatchexStructHeader,
    /// Pyramid levels, 1 to 6; each halves the resolution and doubles the motion it can follow.
    /// 0 switches the flow off, for an engine that chains a PatchexTargetShadowInput on every
    /// extrapolation: its submit then costs no flow, and needs no frame t-1.
    pub levels: u32,
    /// Flow refinements per level, 1 to 10.
    pub iterations: u32,
    /// Half-size of the window the flow is fitted over, 1 to 15 (a (2r+1)^2 window).
    pub window_radius: u32,
    /// Half-size of the polynomial expansion's neighbourhood, 1 to 3.
    pub poly_radius: u32,
    /// Gaussian sigma of the polynomial expansion's weights, in pixels, 0.1 to 4.
    pub poly_sigma: f32,
}

/// Chainable on PatchexCreateInfo with a networks preset (PATCHEX_PRESET_NETWORKS or FULL): the
/// networks' weights from files instead of the ones built into the library (safetensors written
/// by training/train.py; the file names its topology). A null path keeps that network's
/// built-in weights.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PatchexNetworkWeights {
    /// PATCHEX_STRUCT_TYPE_NETWORK_WEIGHTS, sizeof(PatchexNetworkWeights), chain.
    pub header: PatchexStructHeader,
    /// UTF-8 path of the foreground-interaction network, or null.
    pub fi_path: *const c_char,
    /// UTF-8 path of the near-background network, or null.
    pub near_be_path: *const c_char,
}

/// How the networks store their tensors between layers. Either format is one every Vulkan device
/// supports for storage images; the arithmetic is f32 in both.
pub type PatchexTensorPrecision = u32;
/// RGBA16F: half the memory and bandwidth of FP32. The default; it changes the repaired colour by
/// well under what the networks repair (README, the inpainting networks).
pub const PATCHEX_TENSOR_PRECISION_FP16: PatchexTensorPrecision = 0;
/// RGBA32F for every layer's output (the gathered input stays RGBA16F): the networks as trained.
pub const PATCHEX_TENSOR_PRECISION_FP32: PatchexTensorPrecision = 1;

/// Chainable on PatchexCreateInfo with a networks preset (PATCHEX_PRESET_NETWORKS or FULL): the
/// storage precision of the networks' tensors, fixed when the context compiles them.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PatchexNetworkPrecision {
    /// PATCHEX_STRUCT_TYPE_NETWORK_PRECISION, sizeof(PatchexNetworkPrecision), chain.
    pub header: PatchexStructHeader,
    pub tensors: PatchexTensorPrecision,
}

/// Chainable on PatchexCreateInfo with a networks preset (PATCHEX_PRESET_NETWORKS or FULL): how
/// large a patch the networks' tensors hold, fixed when the context makes them. A patch that
/// spans more than `max_patch_side` network texels on either axis runs at twice the resolution
/// divisor, doubled until it fits (`PatchexExtrapolationStats.network_divisors` reports the
/// divisor each network ran at). The tensors' memory and the inference's time stay bounded
/// whatever the frame size, and a large patch gets a smoother correction (README, memory).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PatchexNetworkMemory {
    /// PATCHEX_STRUCT_TYPE_NETWORK_MEMORY, sizeof(PatchexNetworkMemory), chain.
    pub header: PatchexStructHeader,
    /// Network texels per axis: a multiple of PATCHEX_NETWORK_PATCH_SIDE_MULTIPLE from
    /// PATCHEX_NETWORK_PATCH_SIDE_MULTIPLE to PATCHEX_MAX_NETWORK_PATCH_SIDE.
    pub max_patch_side: u32,
}
/// About 12 MiB of FP16 tensors for both shipped networks, whatever the frame size. Chosen on the
/// generated validation scenes at 1920x1080: against 512 (37 MiB more), the same PSNR, SSIM and
/// FLIP over every region, for a third of the inference time (README, memory).
pub const PATCHEX_DEFAULT_NETWORK_MAX_PATCH_SIDE: u32 = 256;
/// Every network's patch is a multiple of 2^(levels - 1) texels, at most 32.
pub const PATCHEX_NETWORK_PATCH_SIDE_MULTIPLE: u32 = 32;
pub const PATCHEX_MAX_NETWORK_PATCH_SIDE: u32 = 4096;

/// Chainable on PatchexCreateInfo (context default) or PatchexExtrapolateDesc (this call) with
/// a networks preset (PATCHEX_PRESET_NETWORKS or FULL): which region's network runs. A network
/// that is off leaves its region as the warp made it. Both run by default, each on its region's
/// patch.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PatchexNetworkSettings {
    /// PATCHEX_STRUCT_TYPE_NETWORK_SETTINGS, sizeof(PatchexNetworkSettings), chain.
    pub header: PatchexStructHeader,
    pub run_fi: PatchexBool,
    pub run_near_be: PatchexBool,
    /// Runs the FI network over the whole frame and takes its result for every pixel; the
    /// near-BE network does not run. The paper's ablation of foveated segmentation: it costs
    /// the whole frame's inference and is less accurate (README, evaluation); a frame wider or
    /// taller than `PatchexNetworkMemory.max_patch_side` runs at a coarser divisor. Needs run_fi.
    pub whole_frame: PatchexBool,
    /// Frame pixels per network texel on each axis: 1 (the frame's resolution, the default), 2
    /// or 4. A network at divisor d reads each d x d block's mean, and its correction is
    /// upsampled bilinearly and added to the warped colour: about 1/d^2 of the inference time
    /// for a smoother correction (README, Speed against accuracy). A patch larger than
    /// `PatchexNetworkMemory.max_patch_side` runs at a multiple of it.
    pub resolution_divisor: u32,
    /// PATCHEX_FALSE (the default): a network's correction replaces only the warp's holes,
    /// where the warp found no agreeing source in frame t; every other pixel keeps the warp,
    /// which a correction there did not improve on scenes the networks never saw (README,
    /// generated scenes). PATCHEX_TRUE: the paper's blend, the correction over every pixel of
    /// its region.
    pub correct_valid_pixels: PatchexBool,
}

/// Chainable on PatchexExtrapolateDesc: an engine image that receives per-pixel intermediate
/// results, for debug views and evaluation. R16G16B16A16_SFLOAT with STORAGE usage, the size of
/// the output. R = hole (1, the warp's colour is a guess) or valid (0); G = region (0 far
/// background, 0.5 near background, 1 foreground interaction); B = LBP code / 255; A = 1.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PatchexDiagnostics {
    /// PATCHEX_STRUCT_TYPE_DIAGNOSTICS, sizeof(PatchexDiagnostics), chain.
    pub header: PatchexStructHeader,
    pub image: PatchexImage,
}

/// Chainable on PatchexExtrapolateDesc: an engine image that receives the shadow sub-task's
/// intermediate results, written only when frame t came with a PatchexShadowInput.
/// R16G16B16A16_SFLOAT with STORAGE usage, the size of the output. RG = the shadow mask's flow at
/// this pixel of frame t (its displacement to frame t-1, in pixels); B = luminance of frame t's
/// shadow layer (the share of light the dynamic shadows take away, in [-1, 0]); A = luminance of
/// that share at the target instant (the layer moved by its flow where it found a receiver, as
/// the frame's warp carried it elsewhere).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PatchexShadowDiagnostics {
    /// PATCHEX_STRUCT_TYPE_SHADOW_DIAGNOSTICS, sizeof(PatchexShadowDiagnostics), chain.
    pub header: PatchexStructHeader,
    pub image: PatchexImage,
}

/// Maximum number of extrapolations recorded from one submitted frame.
pub const PATCHEX_MAX_EXTRAPOLATIONS_PER_FRAME: usize = 4;

/// Stage indices into the `gpu_ms` arrays.
pub type PatchexStage = u32;
/// Demodulation of frame t; with a PatchexShadowInput, the shadow separation in its place.
pub const PATCHEX_STAGE_DEMODULATE: PatchexStage = 0;
pub const PATCHEX_STAGE_PACK_SOURCE_GBUFFER: PatchexStage = 1;
/// No longer recorded (ABI 8): the warps read the target's G-buffer themselves.
pub const PATCHEX_STAGE_PACK_TARGET_GBUFFER: PatchexStage = 2;
/// The frame's warp. With a shadow input it carries the shadow layer beside the frame, with the
/// same weights. With nothing between it and the output (no shadow input, networks or
/// diagnostics) it also remodulates, and PATCHEX_STAGE_REMODULATE does not run. Its holes are
/// filled in PATCHEX_STAGE_FILL_HOLES.
pub const PATCHEX_STAGE_WARP: PatchexStage = 3;
/// The warped shading times the target's own material: the output. With nothing between it and
/// the warp the warp does it, with the networks the blend.
pub const PATCHEX_STAGE_REMODULATE: PatchexStage = 4;
/// Foveated segmentation: object bounds, grown rectangles, region masks; with the networks,
/// their patches.
pub const PATCHEX_STAGE_SEGMENT: PatchexStage = 5;
/// The warped frame's LBP map, only when a PatchexDiagnostics image is chained (the networks make
/// their LBP code as they gather their input).
pub const PATCHEX_STAGE_LBP: PatchexStage = 6;
/// Only when a PatchexDiagnostics image is chained.
pub const PATCHEX_STAGE_DIAGNOSTICS: PatchexStage = 7;
/// Submit, with a PatchexShadowInput and the flow on: mask pyramid, polynomial expansion and
/// Farneback flow.
pub const PATCHEX_STAGE_SHADOW_FLOW: PatchexStage = 8;
/// Extrapolation of a frame with a shadow input and the flow's measure of its drift, without a
/// PatchexTargetShadowInput, before the frame's warp: the shadow layer moved by its flow, which
/// the frame's warp completes where the flow found no receiver. With
/// PATCHEX_SHADOW_HISTORY_STARTED, only the clearing of the shadows' share.
pub const PATCHEX_STAGE_SHADOW_WARP: PatchexStage = 9;
/// A networks preset (PATCHEX_PRESET_NETWORKS or FULL), a frame with dynamic objects: the
/// networks' input gathering and both networks (their patches are planned in
/// PATCHEX_STAGE_SEGMENT).
pub const PATCHEX_STAGE_INFERENCE: PatchexStage = 10;
/// The networks' results blended back under the region masks, the frame remodulated as it is
/// written: with the networks, PATCHEX_STAGE_REMODULATE does not run. It runs when no network
/// found a patch too.
pub const PATCHEX_STAGE_BLEND: PatchexStage = 11;
/// An output in a packed format (every output format but R16G16B16A16_SFLOAT): the frame
/// packed into the format's texels and copied into the output image.
pub const PATCHEX_STAGE_PACK_OUTPUT: PatchexStage = 12;
/// The G-buffer-guided warp's hole fill (PATCHEX_HOLE_FILL_BACKGROUND): a pass over the holes
/// the frame's warp listed, remodulating them when the warp does, and filling the shadow layer
/// it carries.
pub const PATCHEX_STAGE_FILL_HOLES: PatchexStage = 13;
/// Extrapolation with a PatchexTargetShadowInput, after the warp that carries the shadow layer:
/// the sun's share of frame t's light over its shadows, then the shadows placed from the
/// target's mask.
pub const PATCHEX_STAGE_TARGET_SHADOWS: PatchexStage = 14;
/// Extrapolation of a frame that came with a PatchexSunLight or a PatchexSkyLight, after
/// remodulation: the sun's highlights and the sky's reflection, evaluated for the target's view.
/// (Frame t's are taken out of its shading in PATCHEX_STAGE_DEMODULATE.)
pub const PATCHEX_STAGE_HIGHLIGHTS: PatchexStage = 15;
/// Extrapolation of a frame that came with a PatchexTranslucencyInput, last before the output's
/// packing: frame t's translucency moved by its own motion and blended over the extrapolated
/// frame. (It is taken apart from the opaque surface behind it in PATCHEX_STAGE_DEMODULATE.)
pub const PATCHEX_STAGE_TRANSLUCENCY: PatchexStage = 16;
/// Size of the `gpu_ms` arrays; stages added later take indices below it.
pub const PATCHEX_STAGE_SLOTS: usize = 17;

/// Why the history before a submitted frame was dropped.
pub type PatchexResetReason = u32;
pub const PATCHEX_RESET_NONE: PatchexResetReason = 0;
pub const PATCHEX_RESET_FIRST_FRAME: PatchexResetReason = 1;
pub const PATCHEX_RESET_REQUESTED: PatchexResetReason = 2;
pub const PATCHEX_RESET_FRAME_GAP: PatchexResetReason = 3;

/// Rectangles reported per extrapolation; the GPU segments every object id regardless.
pub const PATCHEX_MAX_REPORTED_OBJECTS: usize = 16;

/// One dynamic object's near-background rectangle, in pixels of the target image.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PatchexRegionRect {
    /// The object's stencil id (1 to 255).
    pub object_id: u32,
    /// Target pixels showing the object.
    pub pixel_count: u32,
    /// The grown rectangle, clamped to the image: x to x + width, y to y + height.
    pub x: u32,
    pub y: u32,
    pub width: u32,
    pub height: u32,
    /// Mean |motion| of the object's pixels, in pixels.
    pub mean_motion_x: f32,
    pub mean_motion_y: f32,
}

/// What one extrapolation did.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct PatchexExtrapolationStats {
    pub alpha: f32,
    /// Fraction of target pixels whose warped colour is a guess: the source fell off-screen or
    /// no source texel's geometry agreed with the target's.
    pub hole_fraction: f32,
    /// Fraction of target pixels whose source fell off-screen.
    pub offscreen_fraction: f32,
    /// Target pixels whose base colour or material had to be sanitised (as for
    /// `source_sanitized_pixels`; with frame t's PatchexSunLight or PatchexSkyLight, also the
    /// roughness of the pixels its reflections are placed on), or whose result exceeded the
    /// largest half float and was clamped to it. A pixel is counted once by each pass that
    /// sanitised it.
    pub sanitized_pixels: u32,
    /// Fraction of target pixels in the foreground-interaction region (dynamic objects).
    pub fi_fraction: f32,
    /// Fraction of target pixels in the near-background region.
    pub near_be_fraction: f32,
    /// Dynamic objects (distinct non-zero stencil ids) in the target.
    pub object_count: u32,
    /// The first min(object_count, PATCHEX_MAX_REPORTED_OBJECTS) objects' rectangles, by id.
    pub rects: [PatchexRegionRect; PATCHEX_MAX_REPORTED_OBJECTS],
    /// GPU milliseconds per stage (index PATCHEX_STAGE_*), 0 for stages that did not run: from
    /// the moment all earlier work in the command buffer finished to the moment the stage's
    /// finished, so the stages' times add up to the call's.
    pub gpu_ms: [f32; PATCHEX_STAGE_SLOTS],
    /// 0 when the extrapolated frame can be trusted; otherwise the PATCHEX_RENDER_INSTEAD_*
    /// reasons to render this instant instead of showing the extrapolation.
    pub render_instead_reasons: PatchexRenderInsteadReasons,
    /// The longest motion vector of a target pixel towards frame t, in pixels (after
    /// `motion_vector_scale`; NaN and infinite vectors left out): how far this extrapolation
    /// reaches back.
    pub largest_motion: f32,
    /// The stages this extrapolation ran, as bits 1 << PATCHEX_STAGE_*.
    pub stages_run: u32,
    /// Fraction of target pixels whose colour an inpainting network replaced (FI and near-BE
    /// pixels of the networks that ran; 1 with PatchexNetworkSettings.whole_frame); 0 without
    /// networks or dynamic objects.
    pub repaired_fraction: f32,
    /// Target pixels whose depth is NaN or outside its convention's range (linear depth <= 0,
    /// hardware depth outside [0, 1]; +infinity is sky in linear depth), or whose normal or
    /// motion vector has a NaN or infinite component. Each is a hole, counted in
    /// `hole_fraction`: its warp finds no agreeing source or falls off-screen, and the hole
    /// fill gives it a finite colour.
    pub invalid_geometry_pixels: u32,
    /// Frame pixels per network texel each network ran at, FI then near-BE: the requested
    /// `resolution_divisor`, or a multiple of it where the patch was larger than
    /// `PatchexNetworkMemory.max_patch_side`; 0 for a network that did not run.
    pub network_divisors: [u32; 2],
}

/// Bits of `PatchexExtrapolationStats.render_instead_reasons`.
pub type PatchexRenderInsteadReasons = u32;
/// The target camera looks more than PATCHEX_CAMERA_CUT_DEGREES away from frame t's, or its
/// field of view differs by more than PATCHEX_CAMERA_CUT_ZOOM: a camera cut. Known when the
/// call is recorded, so `patchex_extrapolate` also returns PATCHEX_RESULT_RENDER_INSTEAD.
pub const PATCHEX_RENDER_INSTEAD_CAMERA_CUT: PatchexRenderInsteadReasons = 1;
/// More than PATCHEX_MAX_TRUSTED_HOLE_FRACTION of the frame is hole: disoccluded, or coming
/// from outside frame t's view. Known once the GPU has run the frame.
pub const PATCHEX_RENDER_INSTEAD_DISOCCLUSION: PatchexRenderInsteadReasons = 2;
pub const PATCHEX_CAMERA_CUT_DEGREES: f32 = 30.0;
/// Relative change of the vertical focal length (zoom) taken for a cut.
pub const PATCHEX_CAMERA_CUT_ZOOM: f32 = 0.25;
pub const PATCHEX_MAX_TRUSTED_HOLE_FRACTION: f32 = 0.25;

/// Filled by `patchex_get_frame_stats`; the caller sets the header.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PatchexFrameStats {
    /// PATCHEX_STRUCT_TYPE_FRAME_STATS, sizeof(PatchexFrameStats), chain (none defined yet).
    pub header: PatchexStructHeader,
    pub frame_index: u64,
    pub width: u32,
    pub height: u32,
    pub reset_reason: PatchexResetReason,
    /// 1 when the queue family writes timestamps; otherwise every `gpu_ms` is 0.
    pub timings_valid: PatchexBool,
    /// GPU milliseconds of the submit stages (index PATCHEX_STAGE_*).
    pub submit_gpu_ms: [f32; PATCHEX_STAGE_SLOTS],
    /// Pixels of frame t with an input patchex had to sanitise: a colour (or, with a shadow
    /// input, a colour without dynamic shadows) that is NaN, negative, infinite or beyond the
    /// largest half float (65504), or a base colour, metallic, specular or shadow-mask value
    /// that is NaN or outside [0, 1] (with a PatchexSunLight, also the sun's visibility, and the
    /// roughness of pixels the sun reaches; with a PatchexSkyLight, the roughness of every
    /// pixel, and each texel of its map as a pixel; with a PatchexTranslucencyInput, also its
    /// mask, and its motion vectors where not finite). NaN becomes 0, everything else the
    /// nearest usable value. Bright colour within the half-float range is never changed,
    /// whatever its base colour. A pixel is counted once by each pass that sanitised it.
    pub source_sanitized_pixels: u32,
    /// Pixels of frame t whose depth is NaN or outside its convention's range, or whose normal
    /// has a NaN or infinite component (as for `invalid_geometry_pixels`; its motion vectors are
    /// not read). The warp takes nothing from them that is not finite.
    pub source_invalid_geometry_pixels: u32,
    pub extrapolation_count: u32,
    pub extrapolations: [PatchexExtrapolationStats; PATCHEX_MAX_EXTRAPOLATIONS_PER_FRAME],
    /// Device memory the context holds now, in bytes.
    pub device_memory_bytes: u64,
    /// The stages the submit ran, as bits 1 << PATCHEX_STAGE_*.
    pub submit_stages_run: u32,
    /// What the shadow sub-task had to work with for this frame (PATCHEX_SHADOW_HISTORY_*).
    pub shadow_history: PatchexShadowHistory,
    /// What the submit's stages move and compute.
    pub submit_traffic: PatchexStageTraffic,
    /// The same for each extrapolation, in the order of `extrapolations`.
    pub extrapolation_traffic: [PatchexStageTraffic; PATCHEX_MAX_EXTRAPOLATIONS_PER_FRAME],
}

/// What one call's stages move and compute (index PATCHEX_STAGE_*), as their passes declare it:
/// every image and buffer range a dispatch binds counts once, whole (an image at its extent),
/// read where the shader may load through the binding and written where it may store. A pass
/// over part of a resource counts that part: an iteration of the shadow flow, one level of its
/// pyramid atlases; the hole fill, the texels around the holes the warp listed; the networks'
/// passes and the blend, the share of the frame and of the tensors their patches span. A
/// hardware-independent measure of a stage's memory traffic: a cache may save some of it, a
/// gather that reads a texel twice costs more. The parts the GPU decided (the holes, the
/// patches) are read back with the frame's statistics.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct PatchexStageTraffic {
    pub bytes_read: [u64; PATCHEX_STAGE_SLOTS],
    pub bytes_written: [u64; PATCHEX_STAGE_SLOTS],
    /// Arithmetic operations: each shader's static count per invocation (every expression once,
    /// per vector lane; every loop body and branch once) times the invocations dispatched. The
    /// networks' layers (inference) count their 3x3 convolutions over the patches the GPU
    /// planned, a multiply-add counting two.
    pub arithmetic_operations: [u64; PATCHEX_STAGE_SLOTS],
    /// Compute dispatches recorded, direct and indirect. On a GPU each costs a few microseconds
    /// however little it does, which dominates a stage of small passes.
    pub dispatches: [u32; PATCHEX_STAGE_SLOTS],
    /// Pipeline barriers recorded, each before a command that waits for earlier ones: the GPU
    /// drains its work there.
    pub barriers: [u32; PATCHEX_STAGE_SLOTS],
}

/// `PatchexFrameStats.shadow_history`.
pub type PatchexShadowHistory = u32;
/// The frame came without a PatchexShadowInput: the shadow sub-task did not run.
pub const PATCHEX_SHADOW_HISTORY_NONE: PatchexShadowHistory = 0;
/// The frame had a shadow input but frame t-1 did not (or a reset or gap came between, or the
/// frame size changed): its shadows' drift is unknown, so they stay on their receivers and move
/// only as the frame's warp moves the surfaces (the shadow layer is not warped).
pub const PATCHEX_SHADOW_HISTORY_STARTED: PatchexShadowHistory = 1;
/// Frame t-1 had a shadow input too: the shadows' motion was tracked.
pub const PATCHEX_SHADOW_HISTORY_TRACKED: PatchexShadowHistory = 2;
/// The flow was switched off (PatchexShadowFlowSettings.levels 0): the shadows were separated
/// for a PatchexTargetShadowInput to place; an extrapolation without one keeps them where the
/// frame's warp carries them.
pub const PATCHEX_SHADOW_HISTORY_SEPARATED: PatchexShadowHistory = 3;
