//! Result codes of the C ABI and the internal error type that carries one plus a message.

use std::fmt;

use ash::vk;

/// Result of every `patchex_*` call. Zero is success, positive values are non-error statuses,
/// negative values are errors; each error says what was wrong through `patchex_last_error`.
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PatchexResult {
    /// The call did what it was asked.
    Success = 0,
    /// The GPU has not finished the queried frame yet; ask again after the engine's fence.
    NotReady = 1,
    /// The extrapolation was recorded, but its target is a camera cut from frame t: render
    /// this instant instead of showing it (PATCHEX_RENDER_INSTEAD_CAMERA_CUT).
    RenderInstead = 2,
    /// A required pointer, Vulkan handle (command buffer, image view of a given image) or
    /// required image is null.
    ErrorNullPointer = -1,
    /// A struct's `struct_type` is not the one this argument (or chain link) takes.
    ErrorInvalidStructType = -2,
    /// A struct's `struct_size` is smaller than any version this library knows.
    ErrorStructVersion = -3,
    /// A value outside its documented range: an enumeration, a PatchexBool, an extent, alpha,
    /// a camera, a setting, a chain that is too long, or an image passed in two roles.
    ErrorInvalidArgument = -4,
    /// An image's format is not in the header's FORMATS table for its role, or the device does
    /// not support the format feature that role needs.
    ErrorUnsupportedFormat = -5,
    /// An engine image lacks a usage flag the plugin needs (SAMPLED for inputs, STORAGE for output).
    ErrorMissingImageUsage = -6,
    /// An image's layout is UNDEFINED, PREINITIALIZED or not a core layout, does not fit the
    /// image's aspect and usage (a depth/stencil layout for a colour image, COLOR_ATTACHMENT_OPTIMAL
    /// without COLOR_ATTACHMENT usage), or one image comes in two layouts.
    ErrorInvalidLayout = -7,
    /// Images of one call, or the target and the submitted frame, differ in size.
    ErrorMismatchedExtent = -8,
    /// The frame is larger than the maximum given to `patchex_create`.
    ErrorExtentTooLarge = -9,
    /// The command buffer's queue family is not the one the context was created for.
    ErrorWrongQueueFamily = -10,
    /// A frame index that does not exceed the previous submit's, without the reset flag.
    ErrorOutOfOrder = -11,
    /// `patchex_extrapolate` before any `patchex_submit_gbuffers`.
    ErrorNoSourceFrame = -12,
    /// A fifth `patchex_extrapolate` from one submitted frame (PATCHEX_MAX_EXTRAPOLATIONS_PER_FRAME).
    ErrorTooManyExtrapolations = -13,
    /// The engine's device lacks a function, queue capability or format feature the plugin needs.
    ErrorMissingDeviceFeature = -14,
    /// Host or device memory ran out (VK_ERROR_OUT_OF_HOST_MEMORY, VK_ERROR_OUT_OF_DEVICE_MEMORY
    /// or the allocator's own); the context is unchanged and usable.
    ErrorOutOfMemory = -15,
    /// A Vulkan call inside the plugin failed for another reason.
    ErrorVulkan = -16,
    /// A frame index whose statistics are no longer (or not yet) held.
    ErrorFrameNotFound = -17,
    /// A bug inside the plugin was caught at the ABI boundary; the context can no longer be used.
    ErrorInternal = -18,
}

impl PatchexResult {
    pub fn description(self) -> &'static std::ffi::CStr {
        match self {
            Self::Success => c"success",
            Self::NotReady => c"not ready: the GPU has not finished that frame",
            Self::RenderInstead => {
                c"recorded, but the target is a camera cut: render this frame instead"
            }
            Self::ErrorNullPointer => c"a required pointer or handle is null",
            Self::ErrorInvalidStructType => c"a struct has the wrong struct_type",
            Self::ErrorStructVersion => c"a struct's struct_size matches no known version",
            Self::ErrorInvalidArgument => c"an argument is out of range",
            Self::ErrorUnsupportedFormat => c"an image format is not supported for that input",
            Self::ErrorMissingImageUsage => c"an image lacks a required usage flag",
            Self::ErrorInvalidLayout => c"an image is in a layout the plugin cannot use",
            Self::ErrorMismatchedExtent => c"image extents do not match",
            Self::ErrorExtentTooLarge => c"the frame exceeds the maximum extent given at creation",
            Self::ErrorWrongQueueFamily => c"the command buffer belongs to another queue family",
            Self::ErrorOutOfOrder => c"calls or frame indices are out of order",
            Self::ErrorNoSourceFrame => c"no frame has been submitted to extrapolate from",
            Self::ErrorTooManyExtrapolations => c"too many extrapolations from one frame",
            Self::ErrorMissingDeviceFeature => c"the device lacks a required feature",
            Self::ErrorOutOfMemory => c"out of host or device memory",
            Self::ErrorVulkan => c"a Vulkan call failed",
            Self::ErrorFrameNotFound => c"no statistics are held for that frame index",
            Self::ErrorInternal => c"internal error; the context is no longer usable",
        }
    }

    /// Every result code, for `patchex_result_string` and tests.
    /// cbindgen:ignore
    pub const ALL: [PatchexResult; 21] = [
        Self::Success,
        Self::NotReady,
        Self::RenderInstead,
        Self::ErrorNullPointer,
        Self::ErrorInvalidStructType,
        Self::ErrorStructVersion,
        Self::ErrorInvalidArgument,
        Self::ErrorUnsupportedFormat,
        Self::ErrorMissingImageUsage,
        Self::ErrorInvalidLayout,
        Self::ErrorMismatchedExtent,
        Self::ErrorExtentTooLarge,
        Self::ErrorWrongQueueFamily,
        Self::ErrorOutOfOrder,
        Self::ErrorNoSourceFrame,
        Self::ErrorTooManyExtrapolations,
        Self::ErrorMissingDeviceFeature,
        Self::ErrorOutOfMemory,
        Self::ErrorVulkan,
        Self::ErrorFrameNotFound,
        Self::ErrorInternal,
    ];
}

/// An error with its result code and a message naming the argument and the value at fault.
#[derive(Debug, Clone)]
pub struct Error {
    pub code: PatchexResult,
    pub message: String,
}

impl Error {
    pub fn new(code: PatchexResult, message: impl Into<String>) -> Self {
        Self {
            code,
            message: message.into(),
        }
    }

    /// Prefixes the message with what the plugin was doing, so that a failed Vulkan call says
    /// which object it was making.
    pub fn during(mut self, what: impl fmt::Display) -> Self {
        self.message = format!("{what}: {}", self.message);
        self
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:?}: {}", self.code, self.message)
    }
}

impl std::error::Error for Error {}

impl From<vk::Result> for Error {
    fn from(result: vk::Result) -> Self {
        let code = match result {
            vk::Result::ERROR_OUT_OF_HOST_MEMORY | vk::Result::ERROR_OUT_OF_DEVICE_MEMORY => {
                PatchexResult::ErrorOutOfMemory
            }
            _ => PatchexResult::ErrorVulkan,
        };
        Error::new(code, format!("Vulkan returned {result}"))
    }
}

impl From<gpu_allocator::AllocationError> for Error {
    fn from(error: gpu_allocator::AllocationError) -> Self {
        let code = match error {
            gpu_allocator::AllocationError::OutOfMemory => PatchexResult::ErrorOutOfMemory,
            _ => PatchexResult::ErrorVulkan,
        };
        Error::new(code, format!("GPU memory allocation failed: {error}"))
    }
}

pub type Result<T> = std::result::Result<T, Error>;

/// Returns early with an error built from a code and a format string.
macro_rules! bail {
    ($code:ident, $($message:tt)+) => {
        return Err($crate::error::Error::new(
            $crate::error::PatchexResult::$code,
            format!($($message)+),
        ))
    };
}
pub(crate) use bail;
