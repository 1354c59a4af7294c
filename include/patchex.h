/*
 * patchex: real-time frame extrapolation for Vulkan engines (PatchEX, Dixit and Sarangi 2024).
 *
 * CALL SEQUENCE, per engine frame F (frame_index increasing; a reset may restart it):
 *   patchex_submit_gbuffers(ctx, cmd, {frame F's colour and G-buffer})
 *   patchex_extrapolate(ctx, cmd, {target instant F + alpha: its G-buffer, output image})
 *     (up to PATCHEX_MAX_EXTRAPOLATIONS_PER_FRAME times, e.g. alpha 1/3 then 2/3)
 *   ... engine submits cmd, waits on its fence later ...
 *   patchex_get_frame_stats(ctx, F, &stats) once that fence has signalled: GPU time per
 *     stage, hole fraction, and each dynamic object's near-background rectangle.
 *
 * WHAT IS RECORDED. Each call records compute dispatches, pipeline barriers, timestamp queries
 * and (extrapolate) one vkCmdFillBuffer into the engine's command buffer, outside any render
 * pass. patchex never submits, never waits, and never creates or destroys engine objects.
 *
 * STATE THE ENGINE MUST REBIND AFTERWARDS: the compute pipeline, compute descriptor sets
 * (set 0) and compute push constants. Graphics state is untouched.
 *
 * IMAGE LAYOUTS. Each engine image comes with the layout it will be in when the commands run
 * (any core layout with defined contents; not UNDEFINED or PREINITIALIZED). patchex
 * transitions mip 0 / layer 0 to what it needs (inputs: kept if already GENERAL or a read-only
 * layout, else SHADER_READ_ONLY_OPTIMAL or DEPTH_STENCIL_READ_ONLY_OPTIMAL; output: GENERAL)
 * and returns it to the layout it was handed in. The barriers wait on ALL_COMMANDS/MEMORY_WRITE
 * before and release to ALL_COMMANDS/MEMORY_READ|MEMORY_WRITE after, so the engine needs no
 * barrier of its own around the calls. Inputs need VK_IMAGE_USAGE_SAMPLED_BIT; the output
 * needs VK_IMAGE_USAGE_STORAGE_BIT.
 *
 * LIFETIMES. Inputs are read when the command buffer executes and are not needed afterwards:
 * patchex copies what it keeps from frame t. Command buffers must be submitted in the order
 * they were recorded. When the engine records a frame's submit, the GPU must have finished
 * everything recorded for the frame submitted frames_in_flight submits earlier (its submit and
 * its extrapolations): so one command buffer may hold work for at most frames_in_flight
 * consecutive frames. Handles cannot be checked for liveness: an image
 * or view destroyed before the call, or before its command buffer has executed, is undefined
 * behaviour, as for any Vulkan use of it. Destroy every context before its device.
 *
 * THREADING. A context is not internally synchronised: calls on one context must not overlap
 * (one render thread, or external locking); it may move between threads between calls.
 * Different contexts may be used from different threads at once, on one device or on several;
 * contexts on one device share their compiled pipelines, and patchex_create and
 * patchex_destroy may run concurrently. The engine keeps Vulkan's own rules: a command buffer
 * and its pool are used by one thread at a time, and submissions to a shared queue are
 * serialised. patchex_result_string and patchex_abi_version may be called from any thread;
 * patchex_last_error(NULL) reports the calling thread's last failure that had no context.
 *
 * VERSIONS. Compare patchex_abi_version() with PATCHEX_ABI_VERSION right after loading the
 * library, before any other call, and refuse a library whose version differs: it is bumped on
 * every incompatible change. Every struct starts with struct_type, struct_size and next.
 * struct_size is sizeof the struct as the caller's header declares it: a smaller one than this
 * library's is refused (PATCHEX_RESULT_ERROR_STRUCT_VERSION); a larger one, from a newer header
 * of the same ABI version that appended fields, is accepted and the appended fields are not
 * read. New features arrive as chained structs, and a chained struct_type this library does not
 * know is refused (PATCHEX_RESULT_ERROR_INVALID_STRUCT_TYPE), so no request is dropped unread.
 *
 * REQUIREMENTS. A Vulkan 1.0 device (or later) and a queue family with VK_QUEUE_COMPUTE_BIT. No
 * extension and no optional device feature is needed: the shaders are SPIR-V 1.0 and use only
 * core capabilities. patchex_create checks that the device can sample and store its working
 * formats (R32G32B32A32_SFLOAT, R16G16B16A16_SFLOAT, R32_SFLOAT, R32_UINT) and returns
 * PATCHEX_RESULT_ERROR_MISSING_DEVICE_FEATURE otherwise. GPU timings need a queue family with
 * timestamp bits; without them timings_valid is 0 and everything else works.
 *
 * FORMATS, per role (VK_FORMAT_ left out). Inputs need SAMPLED usage and the device's
 * SAMPLED_IMAGE support; a format outside its role's list is PATCHEX_RESULT_ERROR_UNSUPPORTED_FORMAT.
 *   colour: R16G16B16A16_SFLOAT R32G32B32A32_SFLOAT B10G11R11_UFLOAT_PACK32 A2B10G10R10_UNORM_PACK32 A2R10G10B10_UNORM_PACK32 R8G8B8A8_UNORM R8G8B8A8_SRGB B8G8R8A8_UNORM B8G8R8A8_SRGB R8G8B8A8_SNORM R16G16B16A16_UNORM R16G16B16A16_SNORM
 *   depth: R32_SFLOAT R16_SFLOAT D32_SFLOAT D16_UNORM D24_UNORM_S8_UINT D32_SFLOAT_S8_UINT
 *   stencil: R8_UINT S8_UINT D16_UNORM_S8_UINT D24_UNORM_S8_UINT D32_SFLOAT_S8_UINT
 *   motion vectors: R16G16_SFLOAT R32G32_SFLOAT R16G16B16A16_SFLOAT R32G32B32A32_SFLOAT
 *   shadow mask: R8_UNORM R16_UNORM R16_SFLOAT R32_SFLOAT R16G16B16A16_SFLOAT R32G32B32A32_SFLOAT R8G8B8A8_UNORM
 *   output: R16G16B16A16_SFLOAT B10G11R11_UFLOAT_PACK32 A2B10G10R10_UNORM_PACK32 R8G8B8A8_UNORM R8G8B8A8_SRGB B8G8R8A8_UNORM B8G8R8A8_SRGB
 *   diagnostics: R16G16B16A16_SFLOAT
 * "colour" is frame t's color, color_without_dynamic_shadows, both instants' base_color and
 * material, and normals. An SRGB colour is decoded to linear as it is read, UNORM and SNORM
 * ones read in [0, 1] and [-1, 1]. The output R16G16B16A16_SFLOAT and the diagnostics images are
 * written by a shader and need STORAGE usage; every other output format is packed by a pass and
 * copied in, and needs TRANSFER_DST usage instead: UNORM clamps to [0, 1] (so an LDR output wants
 * tone-mapped colour in), SRGB encodes, B10G11R11 drops alpha and clamps negatives to 0.
 *
 * ERRORS. Every function returns a PatchexResult (negative: error); patchex_last_error gives
 * the message, also passed to the log callback. A failed call records nothing and leaves the
 * context as it was before the call, usable; this includes PATCHEX_RESULT_ERROR_OUT_OF_MEMORY
 * from a driver allocation, and a failed patchex_create leaves no object behind. The exception
 * is PATCHEX_RESULT_ERROR_INTERNAL, after which only patchex_destroy is valid.
 */


#ifndef PATCHEX_H
#define PATCHEX_H

/* Generated by cbindgen from src/abi.rs, src/error.rs and src/ffi.rs. Do not edit. */

#include <stdint.h>
#include <vulkan/vulkan.h>

// Version of this ABI, returned by `patchex_abi_version`; bumped on any incompatible change.
#define PATCHEX_ABI_VERSION 15

// The warp settings a context uses unless told otherwise: a 3x3 gather; a texel keeps most of
// its weight within ~5% relative depth, ~0.1 of (1 - cos) of normal angle (about 25 degrees),
// and 1.5 pixel footprints of world position.
#define PATCHEX_DEFAULT_KERNEL_RADIUS 1

#define PATCHEX_DEFAULT_SIGMA_SPATIAL 0.75

#define PATCHEX_DEFAULT_SIGMA_DEPTH 0.05

#define PATCHEX_DEFAULT_SIGMA_NORMAL 0.1

#define PATCHEX_DEFAULT_SIGMA_POSITION 1.5

#define PATCHEX_DEFAULT_OCCLUSION_SEARCH_RADIUS 8

// The segmentation's default k_x and k_y. `patchex calibrate` measures a mover's wake (the
// high-variation background connected to it) at about a pixel on the generated training scenes,
// which these grow past at their speeds; motion does not predict it well enough to fit k.
#define PATCHEX_DEFAULT_GROWTH_X 1.9

#define PATCHEX_DEFAULT_GROWTH_Y 3.1

// Largest side of a PatchexSkyLight's map.
#define PATCHEX_MAX_SKY_SIDE 1024

// Most mips of a PatchexSkyLight's map patchex reads.
#define PATCHEX_MAX_SKY_MIPS 8

// Farneback optical-flow settings a context uses unless told otherwise: four pyramid levels
// (motion up to about 8 * window_radius texels of the finest level), one iteration per level
// (on the generated validation split, two iterations a level or a fifth level scored lower over
// the shadows), a 15x15 window, and a 5x5 polynomial fit with sigma 1.1 (Farneback's own
// choice for that size).
#define PATCHEX_DEFAULT_FLOW_LEVELS 4

#define PATCHEX_DEFAULT_FLOW_ITERATIONS 1

#define PATCHEX_DEFAULT_FLOW_WINDOW_RADIUS 7

#define PATCHEX_DEFAULT_FLOW_POLY_RADIUS 2

#define PATCHEX_DEFAULT_FLOW_POLY_SIGMA 1.1

// About 12 MiB of FP16 tensors for both shipped networks, whatever the frame size. Chosen on the
// generated validation scenes at 1920x1080: against 512 (37 MiB more), the same PSNR, SSIM and
// FLIP over every region, for a third of the inference time (README, memory).
#define PATCHEX_DEFAULT_NETWORK_MAX_PATCH_SIDE 256

// Every network's patch is a multiple of 2^(levels - 1) texels, at most 32.
#define PATCHEX_NETWORK_PATCH_SIDE_MULTIPLE 32

#define PATCHEX_MAX_NETWORK_PATCH_SIDE 4096

// Maximum number of extrapolations recorded from one submitted frame.
#define PATCHEX_MAX_EXTRAPOLATIONS_PER_FRAME 4

// Size of the `gpu_ms` arrays; stages added later take indices below it.
#define PATCHEX_STAGE_SLOTS 17

// Rectangles reported per extrapolation; the GPU segments every object id regardless.
#define PATCHEX_MAX_REPORTED_OBJECTS 16

#define PATCHEX_CAMERA_CUT_DEGREES 30.0

// Relative change of the vertical focal length (zoom) taken for a cut.
#define PATCHEX_CAMERA_CUT_ZOOM 0.25

#define PATCHEX_MAX_TRUSTED_HOLE_FRACTION 0.25

// Result of every `patchex_*` call. Zero is success, positive values are non-error statuses,
// negative values are errors; each error says what was wrong through `patchex_last_error`.
enum PatchexResult
#if defined(__cplusplus) || __STDC_VERSION__ >= 202311L
  : int32_t
#endif // defined(__cplusplus) || __STDC_VERSION__ >= 202311L
 {
  // The call did what it was asked.
  PATCHEX_RESULT_SUCCESS = 0,
  // The GPU has not finished the queried frame yet; ask again after the engine's fence.
  PATCHEX_RESULT_NOT_READY = 1,
  // The extrapolation was recorded, but its target is a camera cut from frame t: render
  // this instant instead of showing it (PATCHEX_RENDER_INSTEAD_CAMERA_CUT).
  PATCHEX_RESULT_RENDER_INSTEAD = 2,
  // A required pointer, Vulkan handle (command buffer, image view of a given image) or
  // required image is null.
  PATCHEX_RESULT_ERROR_NULL_POINTER = -1,
  // A struct's `struct_type` is not the one this argument (or chain link) takes.
  PATCHEX_RESULT_ERROR_INVALID_STRUCT_TYPE = -2,
  // A struct's `struct_size` is smaller than any version this library knows.
  PATCHEX_RESULT_ERROR_STRUCT_VERSION = -3,
  // A value outside its documented range: an enumeration, a PatchexBool, an extent, alpha,
  // a camera, a setting, a chain that is too long, or an image passed in two roles.
  PATCHEX_RESULT_ERROR_INVALID_ARGUMENT = -4,
  // An image's format is not in the header's FORMATS table for its role, or the device does
  // not support the format feature that role needs.
  PATCHEX_RESULT_ERROR_UNSUPPORTED_FORMAT = -5,
  // An engine image lacks a usage flag the plugin needs (SAMPLED for inputs, STORAGE for output).
  PATCHEX_RESULT_ERROR_MISSING_IMAGE_USAGE = -6,
  // An image's layout is UNDEFINED, PREINITIALIZED or not a core layout, does not fit the
  // image's aspect and usage (a depth/stencil layout for a colour image, COLOR_ATTACHMENT_OPTIMAL
  // without COLOR_ATTACHMENT usage), or one image comes in two layouts.
  PATCHEX_RESULT_ERROR_INVALID_LAYOUT = -7,
  // Images of one call, or the target and the submitted frame, differ in size.
  PATCHEX_RESULT_ERROR_MISMATCHED_EXTENT = -8,
  // The frame is larger than the maximum given to `patchex_create`.
  PATCHEX_RESULT_ERROR_EXTENT_TOO_LARGE = -9,
  // The command buffer's queue family is not the one the context was created for.
  PATCHEX_RESULT_ERROR_WRONG_QUEUE_FAMILY = -10,
  // A frame index that does not exceed the previous submit's, without the reset flag.
  PATCHEX_RESULT_ERROR_OUT_OF_ORDER = -11,
  // `patchex_extrapolate` before any `patchex_submit_gbuffers`.
  PATCHEX_RESULT_ERROR_NO_SOURCE_FRAME = -12,
  // A fifth `patchex_extrapolate` from one submitted frame (PATCHEX_MAX_EXTRAPOLATIONS_PER_FRAME).
  PATCHEX_RESULT_ERROR_TOO_MANY_EXTRAPOLATIONS = -13,
  // The engine's device lacks a function, queue capability or format feature the plugin needs.
  PATCHEX_RESULT_ERROR_MISSING_DEVICE_FEATURE = -14,
  // Host or device memory ran out (VK_ERROR_OUT_OF_HOST_MEMORY, VK_ERROR_OUT_OF_DEVICE_MEMORY
  // or the allocator's own); the context is unchanged and usable.
  PATCHEX_RESULT_ERROR_OUT_OF_MEMORY = -15,
  // A Vulkan call inside the plugin failed for another reason.
  PATCHEX_RESULT_ERROR_VULKAN = -16,
  // A frame index whose statistics are no longer (or not yet) held.
  PATCHEX_RESULT_ERROR_FRAME_NOT_FOUND = -17,
  // A bug inside the plugin was caught at the ABI boundary; the context can no longer be used.
  PATCHEX_RESULT_ERROR_INTERNAL = -18,
};
#ifndef __cplusplus
#if __STDC_VERSION__ >= 202311L
typedef enum PatchexResult PatchexResult;
#else
typedef int32_t PatchexResult;
#endif // __STDC_VERSION__ >= 202311L
#endif // __cplusplus

// A plugin context. Opaque to the engine; see `patchex_create`.
typedef struct PatchexContext PatchexContext;

// Tag in the first field of every versioned struct.
typedef uint32_t PatchexStructType;

// The first fields of every versioned struct, read before the rest.
typedef struct PatchexStructHeader {
  PatchexStructType struct_type;
  // `sizeof` the struct as the caller's header declares it.
  uint32_t struct_size;
  // Optional chain of extension structs, each starting with a `PatchexStructHeader`.
  const void *next;
} PatchexStructHeader;

// Trade of speed against accuracy: which sub-tasks a context can run, cheapest first (README,
// Speed against accuracy, has their measured cost and quality). The preset fixes what a context
// compiles and may allocate; per frame the engine runs less by leaving the shadow input off or
// switching networks off (PatchexNetworkSettings), and a frame without dynamic objects runs no
// network whatever the preset.
typedef uint32_t PatchexPreset;

// Severity passed to the log callback.
typedef uint32_t PatchexLogLevel;

// Called from the thread that made the call being reported; `message` is valid only during
// the callback. NULL for no logging.
typedef void (*PatchexLogCallback)(void *user_data, PatchexLogLevel level, const char *message);

// Arguments of `patchex_create`.
typedef struct PatchexCreateInfo {
  // PATCHEX_STRUCT_TYPE_CREATE_INFO, sizeof(PatchexCreateInfo), optional chain
  // (PatchexWarpSettings, PatchexSegmentationSettings and PatchexShadowFlowSettings set the
  // context's defaults).
  struct PatchexStructHeader header;
  VkInstance instance;
  VkPhysicalDevice physical_device;
  VkDevice device;
  // Required: every Vulkan function is loaded through it (or `get_device_proc_addr`).
  PFN_vkGetInstanceProcAddr get_instance_proc_addr;
  // Optional: device-level functions come from it when given (skips loader trampolines).
  PFN_vkGetDeviceProcAddr get_device_proc_addr;
  // Queue family of every command buffer the engine will pass; must support compute.
  uint32_t queue_family_index;
  // Largest frame the context will be given. Internal images grow to the largest frame seen.
  uint32_t max_width;
  uint32_t max_height;
  // How many frames the engine records ahead of the GPU (1 to 8): resources used by frame F
  // are reused at frame F + frames_in_flight.
  uint32_t frames_in_flight;
  PatchexPreset preset;
  PatchexLogCallback log_callback;
  void *log_user_data;
} PatchexCreateInfo;

// 0 or 1; any other value is rejected as an invalid argument.
typedef uint32_t PatchexBool;

// An engine-owned image, imported for one call. The plugin never takes ownership.
//
// `image == VK_NULL_HANDLE` means "not provided", allowed only for optional inputs.
// `width`/`height` are the image's full size; the plugin uses the top-left frame extent of it.
// `layout` is the layout the image is in when the recorded commands execute; the plugin's
// commands return it to that layout. UNDEFINED and PREINITIALIZED are rejected.
// `usage` is the usage the image was created with: inputs need SAMPLED, the output STORAGE.
typedef struct PatchexImage {
  VkImage image;
  // A 2D view of mip 0, layer 0; for depth/stencil formats, of the one aspect to read.
  VkImageView view;
  VkFormat format;
  uint32_t width;
  uint32_t height;
  VkImageLayout layout;
  VkImageUsageFlags usage;
} PatchexImage;

// How the normal image encodes unit world-space normals.
typedef uint32_t PatchexNormalEncoding;

// How the depth image encodes depth.
typedef uint32_t PatchexDepthConvention;

// Camera of one instant. Matrices are column-major (glam/GLM order), right- or left-handed,
// mapping to Vulkan clip space: NDC y grows down the image and depth follows `depth_convention`.
typedef struct PatchexCamera {
  // World to view.
  float view[16];
  // View to clip, including this instant's jitter, exactly as the G-buffer was rendered.
  float projection[16];
  // Sub-pixel offset of the sample positions, in pixels (x right, y down).
  float jitter[2];
  // Distance to the near plane, in world units, > 0. It must be where the projection puts
  // depth 0 (1 when reversed; either with linear depth), within 1%; otherwise the call fails
  // with PATCHEX_RESULT_ERROR_INVALID_ARGUMENT. Named `near_plane` because `<windows.h>` defines
  // `near` and `far` as empty macros.
  float near_plane;
  // Distance to the far plane, > near_plane; may be +infinity (infinite far plane).
  float far_plane;
  PatchexDepthConvention depth_convention;
} PatchexCamera;

// The geometry buffers of one instant.
typedef struct PatchexGeometry {
  // Single channel: R32_SFLOAT, R16_SFLOAT or D32_SFLOAT/D16_UNORM/D24_UNORM_S8_UINT/
  // D32_SFLOAT_S8_UINT through a depth-aspect view. Encoding given by the camera.
  struct PatchexImage depth;
  // World-space normals in RGB, encoded per `normal_encoding`.
  struct PatchexImage normal;
  PatchexNormalEncoding normal_encoding;
  // Optional: dynamic-object id, 0 for static geometry. R8_UINT, or the stencil aspect of
  // S8_UINT, D16_UNORM_S8_UINT, D24_UNORM_S8_UINT or D32_SFLOAT_S8_UINT.
  struct PatchexImage stencil;
  // Motion to the previous instant (for a target: to the submitted frame t). After scaling,
  // the position of the same surface point in the earlier frame minus this pixel, in pixels,
  // excluding jitter. Required by `patchex_extrapolate`, optional for submitted frames.
  struct PatchexImage motion_vectors;
  // Multiplies the stored motion vectors: (1, 1) for backward motion in pixels,
  // (width, height) for UV, negated for forward (current minus previous) vectors.
  float motion_vector_scale[2];
  struct PatchexCamera camera;
} PatchexGeometry;

// Frame t: what `patchex_submit_gbuffers` reads.
typedef struct PatchexFrameDesc {
  // PATCHEX_STRUCT_TYPE_FRAME_DESC, sizeof(PatchexFrameDesc), optional chain
  // (PatchexShadowInput turns the shadow sub-task on for this frame; PatchexShadowFlowSettings
  // overrides the context's flow settings for it; PatchexSunLight moves the sun's highlights
  // with the view; PatchexTranslucencyInput moves what is drawn over the surfaces by its own
  // motion).
  struct PatchexStructHeader header;
  // The engine's frame number. Without `reset` it must exceed the previous submit's
  // (PATCHEX_RESULT_ERROR_OUT_OF_ORDER otherwise); a gap (not previous + 1) drops history as
  // `reset` does. Any value is allowed with `reset`, including a lower or equal one and after
  // UINT64_MAX: a reset may restart the numbering. patchex_get_frame_stats finds frames by
  // this index (the newest frame of that index, when a reset repeated one).
  uint64_t frame_index;
  // 1 for a camera cut, teleport or level load: history from earlier frames is dropped, and
  // `frame_index` may start over.
  PatchexBool reset;
  // Queue family of the command buffer's pool.
  uint32_t queue_family_index;
  uint32_t width;
  uint32_t height;
  // Final linear HDR colour, before tone mapping and UI; non-negative, up to 65504. Best
  // taken before the translucency pass as well, the lit opaque surfaces alone: then draw the
  // translucency for the target instant over the extrapolated frame, as over a rendered one
  // (the integration guide says what that costs). Colour that holds its translucency wants a
  // PatchexTranslucencyInput.
  struct PatchexImage color;
  // Base colour (albedo) in RGB. patchex divides the colour by it (plus the specular
  // reflectance) to warp lighting rather than texture, and multiplies by the target's. Where
  // that sum is below 0.05 in every channel (black and emissive materials) the result is
  // never brighter than the colour the surface had, and HDR colour up to 65504 comes back
  // unchanged over any base colour.
  struct PatchexImage base_color;
  // Optional: R metallic, G specular, B roughness (Unreal's GBufferB). Absent means
  // metallic 0, specular 0.5, roughness 0.5. Roughness is read by the inpainting networks
  // only; a two-channel image reads roughness 0.
  struct PatchexImage material;
  struct PatchexGeometry geometry;
} PatchexFrameDesc;

// The target instant: what `patchex_extrapolate` reads and writes.
typedef struct PatchexExtrapolateDesc {
  // PATCHEX_STRUCT_TYPE_EXTRAPOLATE_DESC, sizeof(PatchexExtrapolateDesc), optional chain
  // (PatchexWarpSettings and PatchexSegmentationSettings override the context's defaults
  // for this call; PatchexDiagnostics and PatchexShadowDiagnostics ask for the per-pixel
  // intermediate results; PatchexTargetShadowInput gives the shadows at the target).
  struct PatchexStructHeader header;
  uint32_t queue_family_index;
  // Position of the target between frame t (0) and frame t+1 (1), in (0, 1].
  float alpha;
  // Must equal the submitted frame's extent.
  uint32_t width;
  uint32_t height;
  struct PatchexImage base_color;
  // As PatchexFrameDesc's, at the target instant.
  struct PatchexImage material;
  struct PatchexGeometry geometry;
  // Receives the extrapolated linear HDR colour. R16G16B16A16_SFLOAT with STORAGE usage.
  struct PatchexImage output;
} PatchexExtrapolateDesc;

// Why the history before a submitted frame was dropped.
typedef uint32_t PatchexResetReason;

// One dynamic object's near-background rectangle, in pixels of the target image.
typedef struct PatchexRegionRect {
  // The object's stencil id (1 to 255).
  uint32_t object_id;
  // Target pixels showing the object.
  uint32_t pixel_count;
  // The grown rectangle, clamped to the image: x to x + width, y to y + height.
  uint32_t x;
  uint32_t y;
  uint32_t width;
  uint32_t height;
  // Mean |motion| of the object's pixels, in pixels.
  float mean_motion_x;
  float mean_motion_y;
} PatchexRegionRect;

// Bits of `PatchexExtrapolationStats.render_instead_reasons`.
typedef uint32_t PatchexRenderInsteadReasons;

// What one extrapolation did.
typedef struct PatchexExtrapolationStats {
  float alpha;
  // Fraction of target pixels whose warped colour is a guess: the source fell off-screen or
  // no source texel's geometry agreed with the target's.
  float hole_fraction;
  // Fraction of target pixels whose source fell off-screen.
  float offscreen_fraction;
  // Target pixels whose base colour or material had to be sanitised (as for
  // `source_sanitized_pixels`; with frame t's PatchexSunLight or PatchexSkyLight, also the
  // roughness of the pixels its reflections are placed on), or whose result exceeded the
  // largest half float and was clamped to it. A pixel is counted once by each pass that
  // sanitised it.
  uint32_t sanitized_pixels;
  // Fraction of target pixels in the foreground-interaction region (dynamic objects).
  float fi_fraction;
  // Fraction of target pixels in the near-background region.
  float near_be_fraction;
  // Dynamic objects (distinct non-zero stencil ids) in the target.
  uint32_t object_count;
  // The first min(object_count, PATCHEX_MAX_REPORTED_OBJECTS) objects' rectangles, by id.
  struct PatchexRegionRect rects[PATCHEX_MAX_REPORTED_OBJECTS];
  // GPU milliseconds per stage (index PATCHEX_STAGE_*), 0 for stages that did not run: from
  // the moment all earlier work in the command buffer finished to the moment the stage's
  // finished, so the stages' times add up to the call's.
  float gpu_ms[PATCHEX_STAGE_SLOTS];
  // 0 when the extrapolated frame can be trusted; otherwise the PATCHEX_RENDER_INSTEAD_*
  // reasons to render this instant instead of showing the extrapolation.
  PatchexRenderInsteadReasons render_instead_reasons;
  // The longest motion vector of a target pixel towards frame t, in pixels (after
  // `motion_vector_scale`; NaN and infinite vectors left out): how far this extrapolation
  // reaches back.
  float largest_motion;
  // The stages this extrapolation ran, as bits 1 << PATCHEX_STAGE_*.
  uint32_t stages_run;
  // Fraction of target pixels whose colour an inpainting network replaced (FI and near-BE
  // pixels of the networks that ran; 1 with PatchexNetworkSettings.whole_frame); 0 without
  // networks or dynamic objects.
  float repaired_fraction;
  // Target pixels whose depth is NaN or outside its convention's range (linear depth <= 0,
  // hardware depth outside [0, 1]; +infinity is sky in linear depth), or whose normal or
  // motion vector has a NaN or infinite component. Each is a hole, counted in
  // `hole_fraction`: its warp finds no agreeing source or falls off-screen, and the hole
  // fill gives it a finite colour.
  uint32_t invalid_geometry_pixels;
  // Frame pixels per network texel each network ran at, FI then near-BE: the requested
  // `resolution_divisor`, or a multiple of it where the patch was larger than
  // `PatchexNetworkMemory.max_patch_side`; 0 for a network that did not run.
  uint32_t network_divisors[2];
} PatchexExtrapolationStats;

// `PatchexFrameStats.shadow_history`.
typedef uint32_t PatchexShadowHistory;

// What one call's stages move and compute (index PATCHEX_STAGE_*), as their passes declare it:
// every image and buffer range a dispatch binds counts once, whole (an image at its extent),
// read where the shader may load through the binding and written where it may store. A pass
// over part of a resource counts that part: an iteration of the shadow flow, one level of its
// pyramid atlases; the hole fill, the texels around the holes the warp listed; the networks'
// passes and the blend, the share of the frame and of the tensors their patches span. A
// hardware-independent measure of a stage's memory traffic: a cache may save some of it, a
// gather that reads a texel twice costs more. The parts the GPU decided (the holes, the
// patches) are read back with the frame's statistics.
typedef struct PatchexStageTraffic {
  uint64_t bytes_read[PATCHEX_STAGE_SLOTS];
  uint64_t bytes_written[PATCHEX_STAGE_SLOTS];
  // Arithmetic operations: each shader's static count per invocation (every expression once,
  // per vector lane; every loop body and branch once) times the invocations dispatched. The
  // networks' layers (inference) count their 3x3 convolutions over the patches the GPU
  // planned, a multiply-add counting two.
  uint64_t arithmetic_operations[PATCHEX_STAGE_SLOTS];
  // Compute dispatches recorded, direct and indirect. On a GPU each costs a few microseconds
  // however little it does, which dominates a stage of small passes.
  uint32_t dispatches[PATCHEX_STAGE_SLOTS];
  // Pipeline barriers recorded, each before a command that waits for earlier ones: the GPU
  // drains its work there.
  uint32_t barriers[PATCHEX_STAGE_SLOTS];
} PatchexStageTraffic;

// Filled by `patchex_get_frame_stats`; the caller sets the header.
typedef struct PatchexFrameStats {
  // PATCHEX_STRUCT_TYPE_FRAME_STATS, sizeof(PatchexFrameStats), chain (none defined yet).
  struct PatchexStructHeader header;
  uint64_t frame_index;
  uint32_t width;
  uint32_t height;
  PatchexResetReason reset_reason;
  // 1 when the queue family writes timestamps; otherwise every `gpu_ms` is 0.
  PatchexBool timings_valid;
  // GPU milliseconds of the submit stages (index PATCHEX_STAGE_*).
  float submit_gpu_ms[PATCHEX_STAGE_SLOTS];
  // Pixels of frame t with an input patchex had to sanitise: a colour (or, with a shadow
  // input, a colour without dynamic shadows) that is NaN, negative, infinite or beyond the
  // largest half float (65504), or a base colour, metallic, specular or shadow-mask value
  // that is NaN or outside [0, 1] (with a PatchexSunLight, also the sun's visibility, and the
  // roughness of pixels the sun reaches; with a PatchexSkyLight, the roughness of every
  // pixel, and each texel of its map as a pixel; with a PatchexTranslucencyInput, also its
  // mask, and its motion vectors where not finite). NaN becomes 0, everything else the
  // nearest usable value. Bright colour within the half-float range is never changed,
  // whatever its base colour. A pixel is counted once by each pass that sanitised it.
  uint32_t source_sanitized_pixels;
  // Pixels of frame t whose depth is NaN or outside its convention's range, or whose normal
  // has a NaN or infinite component (as for `invalid_geometry_pixels`; its motion vectors are
  // not read). The warp takes nothing from them that is not finite.
  uint32_t source_invalid_geometry_pixels;
  uint32_t extrapolation_count;
  struct PatchexExtrapolationStats extrapolations[PATCHEX_MAX_EXTRAPOLATIONS_PER_FRAME];
  // Device memory the context holds now, in bytes.
  uint64_t device_memory_bytes;
  // The stages the submit ran, as bits 1 << PATCHEX_STAGE_*.
  uint32_t submit_stages_run;
  // What the shadow sub-task had to work with for this frame (PATCHEX_SHADOW_HISTORY_*).
  PatchexShadowHistory shadow_history;
  // What the submit's stages move and compute.
  struct PatchexStageTraffic submit_traffic;
  // The same for each extrapolation, in the order of `extrapolations`.
  struct PatchexStageTraffic extrapolation_traffic[PATCHEX_MAX_EXTRAPOLATIONS_PER_FRAME];
} PatchexFrameStats;

// Which backward warp carries frame t to the target instant.
typedef uint32_t PatchexWarpKind;

// `PatchexWarpSettings.resample`.
typedef uint32_t PatchexResample;

// `PatchexWarpSettings.hole_fill`.
typedef uint32_t PatchexHoleFill;

// How the networks store their tensors between layers. Either format is one every Vulkan device
// supports for storage images; the arithmetic is f32 in both.
typedef uint32_t PatchexTensorPrecision;

// Stage indices into the `gpu_ms` arrays.
typedef uint32_t PatchexStage;

// Chainable on PatchexCreateInfo (context default) or PatchexExtrapolateDesc (this call).
typedef struct PatchexWarpSettings {
  // PATCHEX_STRUCT_TYPE_WARP_SETTINGS, sizeof(PatchexWarpSettings), chain.
  struct PatchexStructHeader header;
  PatchexWarpKind kind;
  // G-buffer-guided warp: gather radius in pixels, 0 to 3 (a (2r+1)^2 kernel).
  uint32_t kernel_radius;
  // Gaussian sigma of the spatial weight, in pixels (> 0).
  float sigma_spatial;
  // Tolerance on relative depth for dynamic objects (> 0).
  float sigma_depth;
  // Tolerance on 1 - dot(normals) (> 0).
  float sigma_normal;
  // Tolerance on world-position distance for static geometry, in pixel footprints on the
  // target's surface (> 0).
  float sigma_position;
  // Occlusion-motion-vector warp: radius in pixels searched for a better motion vector,
  // 0 to 16 (every second pixel is tried).
  uint32_t occlusion_search_radius;
  // G-buffer-guided warp: how a hole (a pixel whose own motion finds no agreeing surface in
  // frame t) is filled. PATCHEX_HOLE_FILL_BACKGROUND, 0, is the default.
  PatchexHoleFill hole_fill;
  // G-buffer-guided warp: how frame t is resampled on static surfaces.
  // PATCHEX_RESAMPLE_CATMULL_ROM, 0, is the default.
  PatchexResample resample;
} PatchexWarpSettings;

// Chainable on PatchexCreateInfo (context default) or PatchexExtrapolateDesc (this call).
// Foveated segmentation (PatchEX Algorithm 1): the near-background region of a dynamic object
// is its bounding rectangle grown by `growth_x * mean|v_x|` left and right and by
// `growth_y * mean|v_y|` above and below, where v is the motion of the object's pixels.
typedef struct PatchexSegmentationSettings {
  // PATCHEX_STRUCT_TYPE_SEGMENTATION_SETTINGS, sizeof(PatchexSegmentationSettings), chain.
  struct PatchexStructHeader header;
  // k_x, finite and 0 to 64. The default is fitted by `patchex calibrate`.
  float growth_x;
  // k_y, finite and 0 to 64.
  float growth_y;
} PatchexSegmentationSettings;

// Chainable on PatchexFrameDesc, with PATCHEX_PRESET_WARP_AND_SHADOWS or PATCHEX_PRESET_FULL:
// the shadows cast by dynamic objects in frame t. Warping moves what is painted on surfaces,
// but a moving character's shadow moves over ground whose motion vectors are zero; with this
// input patchex separates that shadow from frame t, estimates its motion from the masks of
// frames t-1 and t (Farneback dense optical flow, at half resolution, or coarser where the
// context's frames have been larger than 1280 pixels a side), moves it to the target
// instant with the occlusion-motion-vector warp, and swaps it for the shadow the frame's own
// warp carried along. Without it the shadow sub-task does
// not run and costs nothing; its motion is known from the second consecutive frame with it.
//
// Separation, per pixel of frame t, with m the demodulation factor of the frame's colour: the
// shadow layer is (color - color_without_dynamic_shadows) / m, on static pixels (dynamic
// objects keep the shadows on them, which move with them). Nothing is divided by the mask, so
// a fully shadowed pixel (mask 0) is as stable as a lit one. On static target pixels the
// shading becomes max(warped shading - carried layer + moved layer, 0), where the moved layer
// found a receiver.
//
// What an engine provides: the mask is the sun's visibility through dynamic casters only
// (1 lit, 0 fully shadowed; static casters excluded), and the colour is frame t lit as if
// dynamic casters cast no shadow. A deferred renderer gets both from its directional light's
// pass: evaluate the light once with the dynamic-caster shadow term and once without it
// (Unreal: a second projection of the movable-object shadow into its own screen shadow mask,
// and SceneColor plus (1 - mask) times the light's contribution; see plugin-unreal/README.md).
typedef struct PatchexShadowInput {
  // PATCHEX_STRUCT_TYPE_SHADOW_INPUT, sizeof(PatchexShadowInput), chain.
  struct PatchexStructHeader header;
  // Visibility of the sun through dynamic casters, in [0, 1], in the first channel. Float or
  // UNORM formats. Values outside [0, 1] or NaN are sanitised and counted.
  struct PatchexImage mask;
  // Frame t's linear HDR colour without the shadows of dynamic casters; formats as `color`.
  struct PatchexImage color_without_dynamic_shadows;
} PatchexShadowInput;

// Chainable on PatchexExtrapolateDesc, when frame t came with a PatchexShadowInput: the
// dynamic casters' shadows at the target instant, in place of the shadows the flow moves there.
// The flow moves frame t's shadows but keeps their shape; this mask has the target's shape (a
// walking character's legs cast where they are now). Optional, and a trade: it costs the
// engine a pass, and patchex two small passes (the sun's share of frame t's light, then the
// shadows placed), against shadows that match the target.
//
// How patchex uses it, on static target pixels: the shading warped without the dynamic
// shadows loses (1 - mask) times the share of its light that the sun gives. That share is frame
// t's own where the warp carried it from a shadowed texel (the layer over the darkness there),
// and the mean over frame t's shadows elsewhere. Dynamic objects keep the shadows on them, as
// without this input. It takes effect from the second consecutive frame with a shadow input,
// as the flow does (before that, shadows stay where the warp carries them), or from the first
// with the flow off (PatchexShadowFlowSettings.levels 0), which an engine that gives this
// input on every extrapolation should choose: its submits then run no flow.
//
// What an engine provides: the same mask as PatchexShadowInput's, at the target instant: the
// sun's visibility through dynamic casters only, at the target's pixels. A depth-only pass of
// the dynamic casters into the sun's shadow map at their target pose, projected against the
// target depth the engine already has for the G-buffer.
typedef struct PatchexTargetShadowInput {
  // PATCHEX_STRUCT_TYPE_TARGET_SHADOW_INPUT, sizeof(PatchexTargetShadowInput), chain.
  struct PatchexStructHeader header;
  // Visibility of the sun through dynamic casters at the target, in [0, 1], in the first
  // channel. Float or UNORM formats. Values outside [0, 1] or NaN are sanitised and counted.
  struct PatchexImage mask;
} PatchexTargetShadowInput;

// Chainable on PatchexFrameDesc: the sun (one directional light) that lit frame t, so that its
// highlights move with the view instead of staying where frame t saw them. Without it, patchex
// warps the light a surface reflects towards the camera as if it did not depend on the view: a
// glossy floor's highlight stays on the floor where frame t saw it, and a moving camera sees it
// stuck to the surface instead of sliding.
//
// How patchex uses it: in frame t it takes the sun's specular reflection out of the shading it
// warps, and at the target it adds the reflection back as the target's view sees it, times the
// visibility carried from frame t by the motion vectors (and, with a shadow input, times the
// dynamic shadows' share at the target). The reflection is the one the glTF metallic-roughness
// model and Unreal's default lit shading evaluate: a GGX distribution of alpha = roughness^2
// (roughness below 0.02 evaluated as 0.02), height-correlated Smith visibility and Schlick's
// Fresnel from a specular colour of lerp(0.08 * specular, base colour, metallic), read from
// `base_color` and `material` (R metallic, G specular, B roughness; without a material image,
// metallic 0, specular 0.5, roughness 0.5). The target's `material` should be given too. Light
// from the sky (without a PatchexSkyLight) and other lights stays in the warped shading. A
// renderer with another specular model leaves the difference where frame t had it.
//
// On moving objects (a non-zero stencil id), whose surfaces may turn towards or away from the
// sun between frames, it also relights the sun's diffuse reflection: Lambert's, base colour
// times (1 - metallic) over pi, times the sun's illuminance and the cosine to the sun. It adds
// the difference between that term at the target's normal and at frame t's normal where the
// warp took the pixel from, times the same visibility. Static surfaces do not turn: their
// diffuse light is warped as it is.
//
// It costs patchex one pass over frame t's pixels in the submit, and one over the target's.
typedef struct PatchexSunLight {
  // PATCHEX_STRUCT_TYPE_SUN_LIGHT, sizeof(PatchexSunLight), chain.
  struct PatchexStructHeader header;
  // World-space direction from a surface towards the sun, in the normals' space; any finite
  // length above 0 (patchex normalises it).
  float direction[3];
  // The light's colour times its intensity, in linear RGB, as the engine shades with it and in
  // the units of `color` (with any pre-exposure): a white Lambertian surface facing the sun
  // shows illuminance / pi. Finite, >= 0.
  float illuminance[3];
  // Visibility of the sun at frame t's pixels, in [0, 1], in the first channel: the shadow
  // term the engine lit `color` with, through every caster; with a PatchexShadowInput, through
  // the static casters alone (the term `color_without_dynamic_shadows` was lit with). Float or
  // UNORM formats. Values outside [0, 1] or NaN are sanitised and counted.
  struct PatchexImage visibility;
} PatchexSunLight;

// Chainable on PatchexFrameDesc: the sky that lit frame t, so that its reflection in glossy
// surfaces moves with the view, as PatchexSunLight moves the sun's highlights. Without it, the
// sky a floor or a car body mirrors stays where frame t saw it, carried with the surface.
//
// How patchex uses it: in frame t it takes the sky's specular reflection out of the shading it
// warps, and at the target it adds the reflection the target's view sees, from the target's own
// normals and material. The reflection is the sky's radiance in the mirror direction (read from
// the map bilinearly, and between its two mips around the pixel's roughness when it has
// several) times the split-sum environment BRDF in Karis' analytic fit, the one Unreal's
// mobile renderer uses, from the specular colour and roughness PatchexSunLight describes
// (roughness below 0.02 evaluated as 0.02). No shadow or occlusion takes from it. An engine
// whose sky reflection differs (occluded, a lookup-table BRDF, prefiltered other than the mips
// say) leaves the difference where frame t had it; reflection captures and screen-space
// reflections stay in the warped shading. Given with or without a PatchexSunLight.
//
// It costs patchex nothing more than PatchexSunLight's two passes (which run for it alone when
// there is no sun), and a copy of the map, which the first pass makes.
typedef struct PatchexSkyLight {
  // PATCHEX_STRUCT_TYPE_SKY_LIGHT, sizeof(PatchexSkyLight), chain.
  struct PatchexStructHeader header;
  // The sky's radiance by direction, in linear RGB and the units of `color`: a square
  // octahedral map of the normals' world space, 2 to PATCHEX_MAX_SKY_SIDE texels a side,
  // whole (not the frame's extent). Texel (i, j) of a map of side n shows the direction
  // normalize(x, y, 1 - |x| - |y|) for (x, y) = 2 * (i + 0.5, j + 0.5) / n - 1, where
  // |x| + |y| <= 1; elsewhere the direction normalize(sx * (1 - |y|), sy * (1 - |x|),
  // 1 - |x| - |y|), sx and sy the signs of x and y (+ for 0). The formats `color` takes;
  // texels that are NaN, negative, infinite or beyond 65504 are sanitised and counted in
  // `source_sanitized_pixels`. `view` shows the map's first `mip_levels` mips.
  struct PatchexImage radiance;
  // 0 or 1: one map, the sky as a mirror reflects it, read whatever the roughness. 2 to
  // PATCHEX_MAX_SKY_MIPS: mip m (an octahedral map of side >> m texels a side, at least 2)
  // holds the sky as a surface of roughness m / (mip_levels - 1) reflects it, prefiltered as
  // the engine prefilters its sky light; patchex reads between the two mips around each
  // pixel's roughness.
  uint32_t mip_levels;
} PatchexSkyLight;

// Chainable on PatchexFrameDesc: where frame t's colour holds something drawn over the opaque
// surface of the G-buffer after lighting: alpha-blended glass and foliage, particles (smoke,
// sparks, fire), emissive effects composited over the scene. Without it, patchex takes every
// pixel's colour for the light of the surface in the G-buffer: it divides a smoke puff by the
// albedo of the wall behind it and moves it with the wall.
//
// How patchex uses it: in frame t, where the mask covers a pixel, it takes the opaque surface
// behind for the shading it warps: `opaque_color` where the engine gives it, else an estimate
// from the shading of nearby uncovered texels of the same surface. It keeps the rest as a
// premultiplied layer over it: colour = layer + (1 - mask) * surface. At the target, it moves
// that layer by its own motion, extrapolated at constant velocity to the target instant (each
// texel splatted where its motion takes it), or, without motion vectors of its own, as the
// target's motion vectors say the surface behind it moves; then blends it over the
// extrapolated frame. Without `opaque_color`, a layer the same all around a pixel (inside a
// pane of glass, a full-screen tint), one covering a pixel less than a fifth (thin smoke), one
// whose own motion is that of the surface behind it to within half a pixel (given frame t's
// geometry motion vectors), and a fully covered region far from any uncovered texel stay in the
// colour and move with the surface behind them, where the estimate would only add its errors.
// With `opaque_color`, only a layer whose motion is the surface's to within a tenth of a pixel
// stays (glass set in a wall, a decal): the warp follows that surface's geometry more sharply
// than the splat would.
//
// What an engine provides, after the conventions of FSR's transparency-and-composition mask:
// the mask's first channel is the opacity with which everything drawn after the G-buffer's
// lighting covers the pixel: 1 - the product of (1 - alpha) over the translucent draws there
// (additive draws: their luminance over the pixel's, held to 1). A forward pass writes it with
// the blend state it draws colour with, into one more render target. The motion vectors are
// those draws' own, written the same way (alpha-weighted), in the convention of the geometry's.
//
// It costs patchex one pass over frame t's covered pixels in the submit and one over the
// target's in each extrapolation, and 12 bytes a pixel of memory from the first frame with it.
// `opaque_color` costs the engine a copy of its scene colour before the translucency pass
// (none where that pass draws into a target of its own), and saves patchex the estimate.
//
// It is for colour handed over after the translucency pass. An engine that hands over its
// colour from before that pass and draws its translucency over the extrapolated frame gives no
// mask: nothing in that colour is translucent, and every translucent pixel is then as it is at
// the target, which this input only estimates.
typedef struct PatchexTranslucencyInput {
  // PATCHEX_STRUCT_TYPE_TRANSLUCENCY_INPUT, sizeof(PatchexTranslucencyInput), chain.
  struct PatchexStructHeader header;
  // Coverage of frame t's pixels by translucency, in [0, 1], in the first channel: 0 shows the
  // G-buffer's surface alone. Float or UNORM formats. Values outside [0, 1] or NaN are
  // sanitised and counted.
  struct PatchexImage mask;
  // Optional: the translucency's own motion to the previous instant, read where the mask is
  // above 0; formats, meaning and scale as PatchexGeometry.motion_vectors. Non-finite vectors
  // are taken as zero and counted.
  struct PatchexImage motion_vectors;
  float motion_vector_scale[2];
  // Optional: frame t's lit colour before the translucency pass, in the colour's space (the
  // engine's scene colour copied before it draws its translucency). Given it, patchex takes
  // the layer apart exactly, layer = colour - (1 - mask) * opaque colour, where without it it
  // estimates the surface behind. Formats as PatchexFrameDesc.color; texels that are NaN,
  // negative, infinite or beyond 65504 are sanitised and counted.
  struct PatchexImage opaque_color;
} PatchexTranslucencyInput;

// Chainable on PatchexCreateInfo (context default) or PatchexFrameDesc (this frame), with a
// shadows preset (PATCHEX_PRESET_WARP_AND_SHADOWS or FULL): the dense optical flow that
// tracks the dynamic-caster shadow mask between frames t-1 and t.
typedef struct PatchexShadowFlowSettings {
  // PATCHEX_STRUCT_TYPE_SHADOW_FLOW_SETTINGS, sizeof(PatchexShadowFlowSettings), chain.
  struct PatchexStructHeader header;
  // Pyramid levels, 1 to 6; each halves the resolution and doubles the motion it can follow.
  // 0 switches the flow off, for an engine that chains a PatchexTargetShadowInput on every
  // extrapolation: its submit then costs no flow, and needs no frame t-1.
  uint32_t levels;
  // Flow refinements per level, 1 to 10.
  uint32_t iterations;
  // Half-size of the window the flow is fitted over, 1 to 15 (a (2r+1)^2 window).
  uint32_t window_radius;
  // Half-size of the polynomial expansion's neighbourhood, 1 to 3.
  uint32_t poly_radius;
  // Gaussian sigma of the polynomial expansion's weights, in pixels, 0.1 to 4.
  float poly_sigma;
} PatchexShadowFlowSettings;

// Chainable on PatchexCreateInfo with a networks preset (PATCHEX_PRESET_NETWORKS or FULL): the
// networks' weights from files instead of the ones built into the library (safetensors written
// by training/train.py; the file names its topology). A null path keeps that network's
// built-in weights.
typedef struct PatchexNetworkWeights {
  // PATCHEX_STRUCT_TYPE_NETWORK_WEIGHTS, sizeof(PatchexNetworkWeights), chain.
  struct PatchexStructHeader header;
  // UTF-8 path of the foreground-interaction network, or null.
  const char *fi_path;
  // UTF-8 path of the near-background network, or null.
  const char *near_be_path;
} PatchexNetworkWeights;

// Chainable on PatchexCreateInfo (context default) or PatchexExtrapolateDesc (this call) with
// a networks preset (PATCHEX_PRESET_NETWORKS or FULL): which region's network runs. A network
// that is off leaves its region as the warp made it. Both run by default, each on its region's
// patch.
typedef struct PatchexNetworkSettings {
  // PATCHEX_STRUCT_TYPE_NETWORK_SETTINGS, sizeof(PatchexNetworkSettings), chain.
  struct PatchexStructHeader header;
  PatchexBool run_fi;
  PatchexBool run_near_be;
  // Runs the FI network over the whole frame and takes its result for every pixel; the
  // near-BE network does not run. The paper's ablation of foveated segmentation: it costs
  // the whole frame's inference and is less accurate (README, evaluation); a frame wider or
  // taller than `PatchexNetworkMemory.max_patch_side` runs at a coarser divisor. Needs run_fi.
  PatchexBool whole_frame;
  // Frame pixels per network texel on each axis: 1 (the frame's resolution, the default), 2
  // or 4. A network at divisor d reads each d x d block's mean, and its correction is
  // upsampled bilinearly and added to the warped colour: about 1/d^2 of the inference time
  // for a smoother correction (README, Speed against accuracy). A patch larger than
  // `PatchexNetworkMemory.max_patch_side` runs at a multiple of it.
  uint32_t resolution_divisor;
  // PATCHEX_FALSE (the default): a network's correction replaces only the warp's holes,
  // where the warp found no agreeing source in frame t; every other pixel keeps the warp,
  // which a correction there did not improve on scenes the networks never saw (README,
  // generated scenes). PATCHEX_TRUE: the paper's blend, the correction over every pixel of
  // its region.
  PatchexBool correct_valid_pixels;
} PatchexNetworkSettings;

// Chainable on PatchexCreateInfo with a networks preset (PATCHEX_PRESET_NETWORKS or FULL): the
// storage precision of the networks' tensors, fixed when the context compiles them.
typedef struct PatchexNetworkPrecision {
  // PATCHEX_STRUCT_TYPE_NETWORK_PRECISION, sizeof(PatchexNetworkPrecision), chain.
  struct PatchexStructHeader header;
  PatchexTensorPrecision tensors;
} PatchexNetworkPrecision;

// Chainable on PatchexCreateInfo with a networks preset (PATCHEX_PRESET_NETWORKS or FULL): how
// large a patch the networks' tensors hold, fixed when the context makes them. A patch that
// spans more than `max_patch_side` network texels on either axis runs at twice the resolution
// divisor, doubled until it fits (`PatchexExtrapolationStats.network_divisors` reports the
// divisor each network ran at). The tensors' memory and the inference's time stay bounded
// whatever the frame size, and a large patch gets a smoother correction (README, memory).
typedef struct PatchexNetworkMemory {
  // PATCHEX_STRUCT_TYPE_NETWORK_MEMORY, sizeof(PatchexNetworkMemory), chain.
  struct PatchexStructHeader header;
  // Network texels per axis: a multiple of PATCHEX_NETWORK_PATCH_SIDE_MULTIPLE from
  // PATCHEX_NETWORK_PATCH_SIDE_MULTIPLE to PATCHEX_MAX_NETWORK_PATCH_SIDE.
  uint32_t max_patch_side;
} PatchexNetworkMemory;

// Chainable on PatchexExtrapolateDesc: an engine image that receives per-pixel intermediate
// results, for debug views and evaluation. R16G16B16A16_SFLOAT with STORAGE usage, the size of
// the output. R = hole (1, the warp's colour is a guess) or valid (0); G = region (0 far
// background, 0.5 near background, 1 foreground interaction); B = LBP code / 255; A = 1.
typedef struct PatchexDiagnostics {
  // PATCHEX_STRUCT_TYPE_DIAGNOSTICS, sizeof(PatchexDiagnostics), chain.
  struct PatchexStructHeader header;
  struct PatchexImage image;
} PatchexDiagnostics;

// Chainable on PatchexExtrapolateDesc: an engine image that receives the shadow sub-task's
// intermediate results, written only when frame t came with a PatchexShadowInput.
// R16G16B16A16_SFLOAT with STORAGE usage, the size of the output. RG = the shadow mask's flow at
// this pixel of frame t (its displacement to frame t-1, in pixels); B = luminance of frame t's
// shadow layer (the share of light the dynamic shadows take away, in [-1, 0]); A = luminance of
// that share at the target instant (the layer moved by its flow where it found a receiver, as
// the frame's warp carried it elsewhere).
typedef struct PatchexShadowDiagnostics {
  // PATCHEX_STRUCT_TYPE_SHADOW_DIAGNOSTICS, sizeof(PatchexShadowDiagnostics), chain.
  struct PatchexStructHeader header;
  struct PatchexImage image;
} PatchexShadowDiagnostics;

#define PATCHEX_STRUCT_TYPE_CREATE_INFO 1

#define PATCHEX_STRUCT_TYPE_FRAME_DESC 2

#define PATCHEX_STRUCT_TYPE_EXTRAPOLATE_DESC 3

#define PATCHEX_STRUCT_TYPE_WARP_SETTINGS 4

#define PATCHEX_STRUCT_TYPE_FRAME_STATS 5

#define PATCHEX_STRUCT_TYPE_SEGMENTATION_SETTINGS 6

#define PATCHEX_STRUCT_TYPE_DIAGNOSTICS 7

#define PATCHEX_STRUCT_TYPE_SHADOW_INPUT 8

#define PATCHEX_STRUCT_TYPE_SHADOW_FLOW_SETTINGS 9

#define PATCHEX_STRUCT_TYPE_SHADOW_DIAGNOSTICS 10

#define PATCHEX_STRUCT_TYPE_NETWORK_WEIGHTS 11

#define PATCHEX_STRUCT_TYPE_NETWORK_SETTINGS 12

#define PATCHEX_STRUCT_TYPE_NETWORK_PRECISION 13

#define PATCHEX_STRUCT_TYPE_NETWORK_MEMORY 14

#define PATCHEX_STRUCT_TYPE_TARGET_SHADOW_INPUT 15

#define PATCHEX_STRUCT_TYPE_SUN_LIGHT 16

#define PATCHEX_STRUCT_TYPE_TRANSLUCENCY_INPUT 17

#define PATCHEX_STRUCT_TYPE_SKY_LIGHT 18

// Demodulate, warp (PatchexWarpSettings), remodulate. Holes keep the warp's nearest colour.
#define PATCHEX_PRESET_WARP_ONLY 0

// The warp, then PatchEX's two inpainting networks repair the foreground-interaction and
// near-background patches around dynamic objects (far background keeps the warp). Compiles
// the networks at create (seconds on a CPU driver) and holds their tensors for a patch as
// large as the maximum extent.
#define PATCHEX_PRESET_NETWORKS 1

// The warp, and the shadow sub-task on frames that come with a PatchexShadowInput: the shadows
// of dynamic objects tracked and moved on their own. Presets without it refuse the input.
#define PATCHEX_PRESET_WARP_AND_SHADOWS 2

// Everything, PatchEX as published: the warp, the shadow sub-task (with a shadow input) and the
// inpainting networks.
#define PATCHEX_PRESET_FULL 3

// Linear view-space depth: distance along the camera's forward axis, in world units.
#define PATCHEX_DEPTH_LINEAR_VIEW_Z 0

// Hardware depth, 0 at the near plane and 1 at the far plane.
#define PATCHEX_DEPTH_HARDWARE 1

// Reversed hardware depth, 1 at the near plane and 0 at the far plane (or at infinity).
#define PATCHEX_DEPTH_HARDWARE_REVERSED 2

// xyz in [-1, 1] (float formats, or SNORM).
#define PATCHEX_NORMAL_SIGNED 0

// xyz * 0.5 + 0.5 (UNORM formats).
#define PATCHEX_NORMAL_UNORM 1

// Joint bilateral gather guided by the target's G-buffer (ExtraSS). The default.
#define PATCHEX_WARP_GBUFFER_GUIDED 0

// Plain motion-vector reprojection (bilinear); ghosts at disocclusions.
#define PATCHEX_WARP_MOTION_VECTOR 1

// Occlusion motion vectors (Zeng et al. 2021): disoccluded pixels borrow the neighbourhood's
// motion that lands on matching geometry instead of ghosting the occluder.
#define PATCHEX_WARP_OCCLUSION_MOTION_VECTOR 2

#define PATCHEX_LOG_ERROR 0

#define PATCHEX_LOG_WARNING 1

#define PATCHEX_LOG_INFO 2

// Catmull-Rom over the 16 texels around the source point, held within the range of the four
// nearest, where all 16 show the pixel's static surface; bilinear elsewhere and on moving
// objects. Keeps the finest detail, which bilinear halves at a half-texel shift: lower FLIP,
// for more texel reads in the warp.
#define PATCHEX_RESAMPLE_CATMULL_ROM 0

// The four nearest texels, weighted by position: the cheaper fetch.
#define PATCHEX_RESAMPLE_BILINEAR 1

// From the side the disocclusion uncovers: a mean of frame t's texels within 12 pixels of the
// pixel's own source point, each weighted by how closely its normal, depth and object id match
// the target pixel's own surface and by its distance. The occluder that hid the pixel is
// nearer than the surface it uncovers, so it is not smeared into the hole; scenery entering at
// the frame's edge (an off-screen source point) takes the texels inside the edge that face the
// same way. Where no texel within 12 pixels shows the pixel's surface (sky entering beside an
// occluder that filled frame t's edge), texels within 96 pixels are weighed instead.
#define PATCHEX_HOLE_FILL_BACKGROUND 0

// The source texel nearest to where the pixel's own motion lands: usually the occluder itself,
// which leaves a halo of it around moving silhouettes. For comparison.
#define PATCHEX_HOLE_FILL_NEAREST 1

// RGBA16F: half the memory and bandwidth of FP32. The default; it changes the repaired colour by
// well under what the networks repair (README, the inpainting networks).
#define PATCHEX_TENSOR_PRECISION_FP16 0

// RGBA32F for every layer's output (the gathered input stays RGBA16F): the networks as trained.
#define PATCHEX_TENSOR_PRECISION_FP32 1

// Demodulation of frame t; with a PatchexShadowInput, the shadow separation in its place.
#define PATCHEX_STAGE_DEMODULATE 0

#define PATCHEX_STAGE_PACK_SOURCE_GBUFFER 1

// No longer recorded (ABI 8): the warps read the target's G-buffer themselves.
#define PATCHEX_STAGE_PACK_TARGET_GBUFFER 2

// The frame's warp. With a shadow input it carries the shadow layer beside the frame, with the
// same weights. With nothing between it and the output (no shadow input, networks or
// diagnostics) it also remodulates, and PATCHEX_STAGE_REMODULATE does not run. Its holes are
// filled in PATCHEX_STAGE_FILL_HOLES.
#define PATCHEX_STAGE_WARP 3

// The warped shading times the target's own material: the output. With nothing between it and
// the warp the warp does it, with the networks the blend.
#define PATCHEX_STAGE_REMODULATE 4

// Foveated segmentation: object bounds, grown rectangles, region masks; with the networks,
// their patches.
#define PATCHEX_STAGE_SEGMENT 5

// The warped frame's LBP map, only when a PatchexDiagnostics image is chained (the networks make
// their LBP code as they gather their input).
#define PATCHEX_STAGE_LBP 6

// Only when a PatchexDiagnostics image is chained.
#define PATCHEX_STAGE_DIAGNOSTICS 7

// Submit, with a PatchexShadowInput and the flow on: mask pyramid, polynomial expansion and
// Farneback flow.
#define PATCHEX_STAGE_SHADOW_FLOW 8

// Extrapolation of a frame with a shadow input and the flow's measure of its drift, without a
// PatchexTargetShadowInput, before the frame's warp: the shadow layer moved by its flow, which
// the frame's warp completes where the flow found no receiver. With
// PATCHEX_SHADOW_HISTORY_STARTED, only the clearing of the shadows' share.
#define PATCHEX_STAGE_SHADOW_WARP 9

// A networks preset (PATCHEX_PRESET_NETWORKS or FULL), a frame with dynamic objects: the
// networks' input gathering and both networks (their patches are planned in
// PATCHEX_STAGE_SEGMENT).
#define PATCHEX_STAGE_INFERENCE 10

// The networks' results blended back under the region masks, the frame remodulated as it is
// written: with the networks, PATCHEX_STAGE_REMODULATE does not run. It runs when no network
// found a patch too.
#define PATCHEX_STAGE_BLEND 11

// An output in a packed format (every output format but R16G16B16A16_SFLOAT): the frame
// packed into the format's texels and copied into the output image.
#define PATCHEX_STAGE_PACK_OUTPUT 12

// The G-buffer-guided warp's hole fill (PATCHEX_HOLE_FILL_BACKGROUND): a pass over the holes
// the frame's warp listed, remodulating them when the warp does, and filling the shadow layer
// it carries.
#define PATCHEX_STAGE_FILL_HOLES 13

// Extrapolation with a PatchexTargetShadowInput, after the warp that carries the shadow layer:
// the sun's share of frame t's light over its shadows, then the shadows placed from the
// target's mask.
#define PATCHEX_STAGE_TARGET_SHADOWS 14

// Extrapolation of a frame that came with a PatchexSunLight or a PatchexSkyLight, after
// remodulation: the sun's highlights and the sky's reflection, evaluated for the target's view.
// (Frame t's are taken out of its shading in PATCHEX_STAGE_DEMODULATE.)
#define PATCHEX_STAGE_HIGHLIGHTS 15

// Extrapolation of a frame that came with a PatchexTranslucencyInput, last before the output's
// packing: frame t's translucency moved by its own motion and blended over the extrapolated
// frame. (It is taken apart from the opaque surface behind it in PATCHEX_STAGE_DEMODULATE.)
#define PATCHEX_STAGE_TRANSLUCENCY 16

#define PATCHEX_RESET_NONE 0

#define PATCHEX_RESET_FIRST_FRAME 1

#define PATCHEX_RESET_REQUESTED 2

#define PATCHEX_RESET_FRAME_GAP 3

// The target camera looks more than PATCHEX_CAMERA_CUT_DEGREES away from frame t's, or its
// field of view differs by more than PATCHEX_CAMERA_CUT_ZOOM: a camera cut. Known when the
// call is recorded, so `patchex_extrapolate` also returns PATCHEX_RESULT_RENDER_INSTEAD.
#define PATCHEX_RENDER_INSTEAD_CAMERA_CUT 1

// More than PATCHEX_MAX_TRUSTED_HOLE_FRACTION of the frame is hole: disoccluded, or coming
// from outside frame t's view. Known once the GPU has run the frame.
#define PATCHEX_RENDER_INSTEAD_DISOCCLUSION 2

// The frame came without a PatchexShadowInput: the shadow sub-task did not run.
#define PATCHEX_SHADOW_HISTORY_NONE 0

// The frame had a shadow input but frame t-1 did not (or a reset or gap came between, or the
// frame size changed): its shadows' drift is unknown, so they stay on their receivers and move
// only as the frame's warp moves the surfaces (the shadow layer is not warped).
#define PATCHEX_SHADOW_HISTORY_STARTED 1

// Frame t-1 had a shadow input too: the shadows' motion was tracked.
#define PATCHEX_SHADOW_HISTORY_TRACKED 2

// The flow was switched off (PatchexShadowFlowSettings.levels 0): the shadows were separated
// for a PatchexTargetShadowInput to place; an extrapolation without one keeps them where the
// frame's warp carries them.
#define PATCHEX_SHADOW_HISTORY_SEPARATED 3

#ifdef __cplusplus
extern "C" {
#endif // __cplusplus

// Version of the ABI this library implements (PATCHEX_ABI_VERSION of its header). Compare it
// with PATCHEX_ABI_VERSION once, right after loading the library and before any other call;
// refuse the library when they differ. Any thread, any time.
uint32_t patchex_abi_version(void);

// A static, human-readable description of `result`. Never null.
const char *patchex_result_string(int32_t result);

// The message of the last failed call on `context`, or of the last failed call on this thread
// that had no context (`context` NULL: a failed `patchex_create`, a call with a NULL context).
// Empty after a successful call. Valid until the next call on the same context or thread.
//
// # Safety
// `context` is null or a live context.
const char *patchex_last_error(const struct PatchexContext *context);

// Creates a context on the engine's device. Records nothing and submits nothing. Creates
// compute pipelines (tens of milliseconds on a CPU driver), so call it at load time.
// `*out_context` is written only on success; on failure it keeps what the caller put there,
// and `patchex_last_error(NULL)` says why.
//
// Returns SUCCESS, or ERROR_NULL_POINTER, ERROR_INVALID_STRUCT_TYPE, ERROR_STRUCT_VERSION,
// ERROR_INVALID_ARGUMENT (preset, extent, frames_in_flight, a chained setting or weights file),
// ERROR_MISSING_DEVICE_FEATURE, ERROR_OUT_OF_MEMORY, ERROR_VULKAN or ERROR_INTERNAL.
//
// # Safety
// `info` points to a PatchexCreateInfo whose handles are live; `out_context` is writable.
PatchexResult patchex_create(const struct PatchexCreateInfo *info,
                             struct PatchexContext **out_context);

// Destroys a context and every Vulkan object it made. The engine must first make sure the GPU
// has finished every command buffer into which this context recorded (wait on their fences or
// the device). NULL is ignored. Returns nothing; it cannot fail.
//
// # Safety
// `context` is null or a live context, not used again afterwards.
void patchex_destroy(struct PatchexContext *context);

// Records frame t's ingestion into `command_buffer`: demodulation of its colour and packing of
// its G-buffer into the context's own images. Inputs are read when the command buffer runs and
// are not needed afterwards. See the header's overview for layouts and state.
//
// Returns SUCCESS, or ERROR_NULL_POINTER, ERROR_INVALID_STRUCT_TYPE, ERROR_STRUCT_VERSION,
// ERROR_INVALID_ARGUMENT, ERROR_UNSUPPORTED_FORMAT, ERROR_MISSING_IMAGE_USAGE,
// ERROR_INVALID_LAYOUT, ERROR_MISMATCHED_EXTENT, ERROR_EXTENT_TOO_LARGE,
// ERROR_WRONG_QUEUE_FAMILY, ERROR_OUT_OF_ORDER, ERROR_OUT_OF_MEMORY, ERROR_VULKAN or
// ERROR_INTERNAL.
//
// # Safety
// `context` is live; `command_buffer` is recording, from a pool of the context's queue family;
// `desc` points to a PatchexFrameDesc whose images are live until the command buffer completes.
PatchexResult patchex_submit_gbuffers(struct PatchexContext *context,
                                      VkCommandBuffer command_buffer,
                                      const struct PatchexFrameDesc *desc);

// Records one extrapolation from the last submitted frame to the target instant described by
// `desc` into `command_buffer`, writing `desc->output`. Up to
// PATCHEX_MAX_EXTRAPOLATIONS_PER_FRAME calls per submitted frame (alpha 1/3 then 2/3, say).
// Returns PATCHEX_RESULT_RENDER_INSTEAD (positive: the output is still written) when the
// target is a camera cut from frame t, which no extrapolation can bridge.
//
// Returns SUCCESS, RENDER_INSTEAD, or ERROR_NULL_POINTER, ERROR_INVALID_STRUCT_TYPE,
// ERROR_STRUCT_VERSION, ERROR_INVALID_ARGUMENT, ERROR_UNSUPPORTED_FORMAT,
// ERROR_MISSING_IMAGE_USAGE, ERROR_INVALID_LAYOUT, ERROR_MISMATCHED_EXTENT,
// ERROR_EXTENT_TOO_LARGE, ERROR_WRONG_QUEUE_FAMILY, ERROR_NO_SOURCE_FRAME,
// ERROR_TOO_MANY_EXTRAPOLATIONS, ERROR_OUT_OF_MEMORY, ERROR_VULKAN or ERROR_INTERNAL.
//
// # Safety
// As for `patchex_submit_gbuffers`; the command buffer must execute after the one holding the
// submit (same command buffer, or a later submission on the same queue).
PatchexResult patchex_extrapolate(struct PatchexContext *context,
                                  VkCommandBuffer command_buffer,
                                  const struct PatchexExtrapolateDesc *desc);

// Fills `out_stats` (whose header the caller sets) with the GPU times and statistics of
// `frame_index` and its extrapolations. Call it after the engine's fence for that frame has
// signalled. The newest frames_in_flight submitted frames are held; after a reset that repeated
// an index, the newest frame of that index answers.
//
// Returns SUCCESS; NOT_READY (positive, `*out_stats` filled but its GPU results not final)
// while the GPU has not finished the frame; or ERROR_FRAME_NOT_FOUND once the frame has left
// the ring (or was never submitted), ERROR_NULL_POINTER, ERROR_INVALID_STRUCT_TYPE,
// ERROR_STRUCT_VERSION or ERROR_INTERNAL.
//
// # Safety
// `context` is live; `out_stats` points to a writable PatchexFrameStats.
PatchexResult patchex_get_frame_stats(struct PatchexContext *context,
                                      uint64_t frame_index,
                                      struct PatchexFrameStats *out_stats);

#ifdef __cplusplus
}  // extern "C"
#endif  // __cplusplus

#endif  /* PATCHEX_H */
