//! Every `extern "C"` entry point. Each one is a panic boundary, checks its pointers and struct
//! headers, and turns any failure into a result code plus a message that `patchex_last_error`
//! returns and the log callback receives.

use std::cell::RefCell;
use std::ffi::{c_char, c_void, CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;

use crate::abi::*;
use crate::context::{Context, Extensions, NetworkSwitches, NetworkWeightPaths};
use crate::error::{bail, Error, PatchexResult, Result};
use crate::inputs::boolean;
use crate::network::TensorPrecision;
use crate::passes::segmentation::SegmentationSettings;
use crate::passes::shadow_flow::FlowSettings;
use crate::passes::warp::WarpSettings;

/// A plugin context. Opaque to the engine; see `patchex_create`.
pub struct PatchexContext {
    context: Option<Context>,
    last_error: CString,
    log_callback: PatchexLogCallback,
    log_user_data: *mut c_void,
}

thread_local! {
    /// Errors of calls that have no context to hold them (a failed create, a null context).
    static THREAD_LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

fn to_cstring(message: &str) -> CString {
    CString::new(message.replace('\0', " ")).unwrap_or_default()
}

fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".to_string())
}

fn log(
    callback: PatchexLogCallback,
    user_data: *mut c_void,
    level: PatchexLogLevel,
    message: &CString,
) {
    if let Some(callback) = callback {
        // SAFETY: the engine gave this callback for exactly this use. A panic cannot unwind out
        // of an `extern "C"` callee into Rust, so there is nothing to catch here.
        unsafe { callback(user_data, level, message.as_ptr()) };
    }
}

/// Reads a versioned struct: checks the pointer, the type tag and that the caller's struct is
/// at least as large as the version this library reads.
///
/// # Safety
/// `pointer` is null or points to a readable struct that starts with a `PatchexStructHeader`.
unsafe fn read_versioned<T: Copy>(
    pointer: *const T,
    expected: PatchexStructType,
    what: &str,
) -> Result<T> {
    if pointer.is_null() {
        bail!(ErrorNullPointer, "{what} is null");
    }
    let header = pointer.cast::<PatchexStructHeader>().read();
    if header.struct_type != expected {
        bail!(
            ErrorInvalidStructType,
            "{what}.header.struct_type is {}, expected {expected}",
            header.struct_type
        );
    }
    if (header.struct_size as usize) < std::mem::size_of::<T>() {
        bail!(
            ErrorStructVersion,
            "{what}.header.struct_size is {}, smaller than this library's {} bytes",
            header.struct_size,
            std::mem::size_of::<T>()
        );
    }
    Ok(pointer.read())
}

/// A path given as a nul-terminated UTF-8 string, or `None` for a null pointer.
///
/// # Safety
/// `path` is null or points to a nul-terminated string.
unsafe fn optional_path(path: *const c_char, what: &str) -> Result<Option<PathBuf>> {
    if path.is_null() {
        return Ok(None);
    }
    match CStr::from_ptr(path).to_str() {
        Ok(text) if !text.is_empty() => Ok(Some(PathBuf::from(text))),
        _ => bail!(ErrorInvalidArgument, "{what} is not a non-empty UTF-8 path"),
    }
}

/// Longest `next` chain followed; a longer one is taken for a cycle.
const MAX_CHAIN_LENGTH: usize = 16;

/// Walks a `next` chain and returns the extensions in it. `accepted` lists the struct types
/// the chained-to struct takes, each at most once; any other link is an error, so a caller never
/// believes an extension was honoured when it was not.
///
/// # Safety
/// Every link is null or points to a readable struct starting with a `PatchexStructHeader`.
unsafe fn read_chain(
    mut next: *const c_void,
    accepted: &[PatchexStructType],
    what: &str,
) -> Result<Extensions> {
    let mut extensions = Extensions::default();
    let mut seen: Vec<PatchexStructType> = Vec::new();
    for _ in 0..MAX_CHAIN_LENGTH {
        if next.is_null() {
            return Ok(extensions);
        }
        let header = next.cast::<PatchexStructHeader>().read();
        let kind = header.struct_type;
        if !accepted.contains(&kind) || seen.contains(&kind) {
            bail!(
                ErrorInvalidStructType,
                "{what}.header.next chains struct_type {kind}, which this struct does not take \
                 (or takes only once)"
            );
        }
        seen.push(kind);
        match kind {
            PATCHEX_STRUCT_TYPE_WARP_SETTINGS => {
                let settings = read_versioned(
                    next.cast::<PatchexWarpSettings>(),
                    kind,
                    "PatchexWarpSettings",
                )?;
                extensions.warp = Some(WarpSettings::from_abi(&settings)?);
            }
            PATCHEX_STRUCT_TYPE_SEGMENTATION_SETTINGS => {
                let settings = read_versioned(
                    next.cast::<PatchexSegmentationSettings>(),
                    kind,
                    "PatchexSegmentationSettings",
                )?;
                extensions.segmentation = Some(SegmentationSettings::from_abi(&settings)?);
            }
            PATCHEX_STRUCT_TYPE_DIAGNOSTICS => {
                let diagnostics = read_versioned(
                    next.cast::<PatchexDiagnostics>(),
                    kind,
                    "PatchexDiagnostics",
                )?;
                extensions.diagnostics = Some(diagnostics.image);
            }
            PATCHEX_STRUCT_TYPE_SHADOW_DIAGNOSTICS => {
                let diagnostics = read_versioned(
                    next.cast::<PatchexShadowDiagnostics>(),
                    kind,
                    "PatchexShadowDiagnostics",
                )?;
                extensions.shadow_diagnostics = Some(diagnostics.image);
            }
            PATCHEX_STRUCT_TYPE_SHADOW_INPUT => {
                let input = read_versioned(
                    next.cast::<PatchexShadowInput>(),
                    kind,
                    "PatchexShadowInput",
                )?;
                extensions.shadow = Some(input);
            }
            PATCHEX_STRUCT_TYPE_TARGET_SHADOW_INPUT => {
                let input = read_versioned(
                    next.cast::<PatchexTargetShadowInput>(),
                    kind,
                    "PatchexTargetShadowInput",
                )?;
                extensions.target_shadow_mask = Some(input.mask);
            }
            PATCHEX_STRUCT_TYPE_SUN_LIGHT => {
                let input =
                    read_versioned(next.cast::<PatchexSunLight>(), kind, "PatchexSunLight")?;
                extensions.sun = Some(input);
            }
            PATCHEX_STRUCT_TYPE_SKY_LIGHT => {
                let input =
                    read_versioned(next.cast::<PatchexSkyLight>(), kind, "PatchexSkyLight")?;
                extensions.sky = Some(input);
            }
            PATCHEX_STRUCT_TYPE_TRANSLUCENCY_INPUT => {
                let input = read_versioned(
                    next.cast::<PatchexTranslucencyInput>(),
                    kind,
                    "PatchexTranslucencyInput",
                )?;
                extensions.translucency = Some(input);
            }
            PATCHEX_STRUCT_TYPE_SHADOW_FLOW_SETTINGS => {
                let settings = read_versioned(
                    next.cast::<PatchexShadowFlowSettings>(),
                    kind,
                    "PatchexShadowFlowSettings",
                )?;
                extensions.flow = Some(FlowSettings::from_abi(&settings)?);
            }
            PATCHEX_STRUCT_TYPE_NETWORK_WEIGHTS => {
                let weights = read_versioned(
                    next.cast::<PatchexNetworkWeights>(),
                    kind,
                    "PatchexNetworkWeights",
                )?;
                extensions.network_weights = Some(NetworkWeightPaths {
                    fi: optional_path(weights.fi_path, "PatchexNetworkWeights.fi_path")?,
                    near_be: optional_path(
                        weights.near_be_path,
                        "PatchexNetworkWeights.near_be_path",
                    )?,
                });
            }
            PATCHEX_STRUCT_TYPE_NETWORK_SETTINGS => {
                let settings = read_versioned(
                    next.cast::<PatchexNetworkSettings>(),
                    kind,
                    "PatchexNetworkSettings",
                )?;
                let switches = NetworkSwitches {
                    fi: boolean(settings.run_fi, "PatchexNetworkSettings.run_fi")?,
                    near_be: boolean(settings.run_near_be, "PatchexNetworkSettings.run_near_be")?,
                    whole_frame: boolean(
                        settings.whole_frame,
                        "PatchexNetworkSettings.whole_frame",
                    )?,
                    divisor: settings.resolution_divisor,
                    correct_valid_pixels: boolean(
                        settings.correct_valid_pixels,
                        "PatchexNetworkSettings.correct_valid_pixels",
                    )?,
                };
                if ![1, 2, 4].contains(&switches.divisor) {
                    bail!(
                        ErrorInvalidArgument,
                        "PatchexNetworkSettings.resolution_divisor {} must be 1, 2 or 4",
                        switches.divisor
                    );
                }
                if switches.whole_frame && !switches.fi {
                    bail!(
                        ErrorInvalidArgument,
                        "PatchexNetworkSettings.whole_frame runs the FI network over the whole \
                         frame: it needs run_fi"
                    );
                }
                extensions.networks = Some(switches);
            }
            PATCHEX_STRUCT_TYPE_NETWORK_PRECISION => {
                let precision = read_versioned(
                    next.cast::<PatchexNetworkPrecision>(),
                    kind,
                    "PatchexNetworkPrecision",
                )?;
                extensions.network_precision = Some(match precision.tensors {
                    PATCHEX_TENSOR_PRECISION_FP16 => TensorPrecision::F16,
                    PATCHEX_TENSOR_PRECISION_FP32 => TensorPrecision::F32,
                    other => bail!(
                        ErrorInvalidArgument,
                        "PatchexNetworkPrecision.tensors {other} is not a precision: \
                         PATCHEX_TENSOR_PRECISION_FP16 (0) or PATCHEX_TENSOR_PRECISION_FP32 (1)"
                    ),
                });
            }
            PATCHEX_STRUCT_TYPE_NETWORK_MEMORY => {
                let memory = read_versioned(
                    next.cast::<PatchexNetworkMemory>(),
                    kind,
                    "PatchexNetworkMemory",
                )?;
                let side = memory.max_patch_side;
                let multiple = PATCHEX_NETWORK_PATCH_SIDE_MULTIPLE;
                if !(multiple..=PATCHEX_MAX_NETWORK_PATCH_SIDE).contains(&side)
                    || side % multiple != 0
                {
                    bail!(
                        ErrorInvalidArgument,
                        "PatchexNetworkMemory.max_patch_side {side} must be a multiple of \
                         {multiple} from {multiple} to {PATCHEX_MAX_NETWORK_PATCH_SIDE}"
                    );
                }
                extensions.network_max_patch_side = Some(side);
            }
            _ => unreachable!("every accepted struct type is handled"),
        }
        next = header.next;
    }
    bail!(
        ErrorInvalidArgument,
        "{what}.header.next chain is longer than {MAX_CHAIN_LENGTH} links (a cycle?)"
    )
}

/// Runs `call` on a live context inside a panic boundary and records any error.
///
/// # Safety
/// `context` is null or a pointer returned by `patchex_create` and not yet destroyed.
unsafe fn with_context(
    context: *mut PatchexContext,
    call: impl FnOnce(&mut Context) -> Result<PatchexResult>,
) -> PatchexResult {
    let Some(handle) = context.as_mut() else {
        return record_thread_error(Error::new(
            PatchexResult::ErrorNullPointer,
            "context is null",
        ));
    };
    let Some(inner) = handle.context.as_mut() else {
        let error = Error::new(
            PatchexResult::ErrorInternal,
            "the context hit an internal error earlier and can only be destroyed",
        );
        handle.last_error = to_cstring(&error.message);
        return error.code;
    };
    let outcome = catch_unwind(AssertUnwindSafe(|| call(inner)));
    let error = match outcome {
        Ok(Ok(code)) => {
            handle.last_error = CString::default();
            return code;
        }
        Ok(Err(error)) => error,
        Err(payload) => {
            // A bug inside the plugin: the context's state is unknown, so it is retired. Its
            // Vulkan objects are leaked rather than destroyed while the GPU may use them.
            std::mem::forget(handle.context.take());
            Error::new(
                PatchexResult::ErrorInternal,
                format!("internal error: {}", panic_message(&*payload)),
            )
        }
    };
    handle.last_error = to_cstring(&error.message);
    log(
        handle.log_callback,
        handle.log_user_data,
        PATCHEX_LOG_ERROR,
        &handle.last_error,
    );
    error.code
}

fn record_thread_error(error: Error) -> PatchexResult {
    THREAD_LAST_ERROR.with(|last| *last.borrow_mut() = to_cstring(&error.message));
    error.code
}

/// Version of the ABI this library implements (PATCHEX_ABI_VERSION of its header). Compare it
/// with PATCHEX_ABI_VERSION once, right after loading the library and before any other call;
/// refuse the library when they differ. Any thread, any time.
#[no_mangle]
pub extern "C" fn patchex_abi_version() -> u32 {
    PATCHEX_ABI_VERSION
}

/// A static, human-readable description of `result`. Never null.
#[no_mangle]
pub extern "C" fn patchex_result_string(result: i32) -> *const c_char {
    PatchexResult::ALL
        .iter()
        .find(|code| **code as i32 == result)
        .map_or(c"unknown result code".as_ptr(), |code| {
            code.description().as_ptr()
        })
}

/// The message of the last failed call on `context`, or of the last failed call on this thread
/// that had no context (`context` NULL: a failed `patchex_create`, a call with a NULL context).
/// Empty after a successful call. Valid until the next call on the same context or thread.
///
/// # Safety
/// `context` is null or a live context.
#[no_mangle]
pub unsafe extern "C" fn patchex_last_error(context: *const PatchexContext) -> *const c_char {
    match context.as_ref() {
        Some(handle) => handle.last_error.as_ptr(),
        None => THREAD_LAST_ERROR.with(|last| last.borrow().as_ptr()),
    }
}

/// Creates a context on the engine's device. Records nothing and submits nothing. Creates
/// compute pipelines (tens of milliseconds on a CPU driver), so call it at load time.
/// `*out_context` is written only on success; on failure it keeps what the caller put there,
/// and `patchex_last_error(NULL)` says why.
///
/// Returns SUCCESS, or ERROR_NULL_POINTER, ERROR_INVALID_STRUCT_TYPE, ERROR_STRUCT_VERSION,
/// ERROR_INVALID_ARGUMENT (preset, extent, frames_in_flight, a chained setting or weights file),
/// ERROR_MISSING_DEVICE_FEATURE, ERROR_OUT_OF_MEMORY, ERROR_VULKAN or ERROR_INTERNAL.
///
/// # Safety
/// `info` points to a PatchexCreateInfo whose handles are live; `out_context` is writable.
#[no_mangle]
pub unsafe extern "C" fn patchex_create(
    info: *const PatchexCreateInfo,
    out_context: *mut *mut PatchexContext,
) -> PatchexResult {
    let outcome = catch_unwind(AssertUnwindSafe(|| -> Result<PatchexContext> {
        if out_context.is_null() {
            bail!(ErrorNullPointer, "out_context is null");
        }
        let info = read_versioned(info, PATCHEX_STRUCT_TYPE_CREATE_INFO, "PatchexCreateInfo")?;
        let handle = PatchexContext {
            context: None,
            last_error: CString::default(),
            log_callback: info.log_callback,
            log_user_data: info.log_user_data,
        };
        let created = read_chain(
            info.header.next,
            &[
                PATCHEX_STRUCT_TYPE_WARP_SETTINGS,
                PATCHEX_STRUCT_TYPE_SEGMENTATION_SETTINGS,
                PATCHEX_STRUCT_TYPE_SHADOW_FLOW_SETTINGS,
                PATCHEX_STRUCT_TYPE_NETWORK_WEIGHTS,
                PATCHEX_STRUCT_TYPE_NETWORK_SETTINGS,
                PATCHEX_STRUCT_TYPE_NETWORK_PRECISION,
                PATCHEX_STRUCT_TYPE_NETWORK_MEMORY,
            ],
            "PatchexCreateInfo",
        )
        .and_then(|defaults| Context::new(&info, defaults));
        match created {
            Ok(context) => Ok(PatchexContext {
                context: Some(context),
                ..handle
            }),
            Err(error) => {
                let message = to_cstring(&error.message);
                log(
                    handle.log_callback,
                    handle.log_user_data,
                    PATCHEX_LOG_ERROR,
                    &message,
                );
                Err(error)
            }
        }
    }));
    match outcome {
        Ok(Ok(handle)) => {
            *out_context = Box::into_raw(Box::new(handle));
            THREAD_LAST_ERROR.with(|last| *last.borrow_mut() = CString::default());
            PatchexResult::Success
        }
        Ok(Err(error)) => record_thread_error(error),
        Err(payload) => record_thread_error(Error::new(
            PatchexResult::ErrorInternal,
            format!("internal error: {}", panic_message(&*payload)),
        )),
    }
}

/// Destroys a context and every Vulkan object it made. The engine must first make sure the GPU
/// has finished every command buffer into which this context recorded (wait on their fences or
/// the device). NULL is ignored. Returns nothing; it cannot fail.
///
/// # Safety
/// `context` is null or a live context, not used again afterwards.
#[no_mangle]
pub unsafe extern "C" fn patchex_destroy(context: *mut PatchexContext) {
    if context.is_null() {
        return;
    }
    let handle = Box::from_raw(context);
    // A panic while destroying must not unwind into the engine; what it leaks stays leaked.
    let _ = catch_unwind(AssertUnwindSafe(move || drop(handle)));
}

/// Records frame t's ingestion into `command_buffer`: demodulation of its colour and packing of
/// its G-buffer into the context's own images. Inputs are read when the command buffer runs and
/// are not needed afterwards. See the header's overview for layouts and state.
///
/// Returns SUCCESS, or ERROR_NULL_POINTER, ERROR_INVALID_STRUCT_TYPE, ERROR_STRUCT_VERSION,
/// ERROR_INVALID_ARGUMENT, ERROR_UNSUPPORTED_FORMAT, ERROR_MISSING_IMAGE_USAGE,
/// ERROR_INVALID_LAYOUT, ERROR_MISMATCHED_EXTENT, ERROR_EXTENT_TOO_LARGE,
/// ERROR_WRONG_QUEUE_FAMILY, ERROR_OUT_OF_ORDER, ERROR_OUT_OF_MEMORY, ERROR_VULKAN or
/// ERROR_INTERNAL.
///
/// # Safety
/// `context` is live; `command_buffer` is recording, from a pool of the context's queue family;
/// `desc` points to a PatchexFrameDesc whose images are live until the command buffer completes.
#[no_mangle]
pub unsafe extern "C" fn patchex_submit_gbuffers(
    context: *mut PatchexContext,
    command_buffer: VkCommandBuffer,
    desc: *const PatchexFrameDesc,
) -> PatchexResult {
    with_context(context, |context| {
        if command_buffer == VkCommandBuffer::null() {
            bail!(ErrorNullPointer, "command_buffer is VK_NULL_HANDLE");
        }
        let desc = read_versioned(desc, PATCHEX_STRUCT_TYPE_FRAME_DESC, "PatchexFrameDesc")?;
        let extensions = read_chain(
            desc.header.next,
            &[
                PATCHEX_STRUCT_TYPE_SHADOW_INPUT,
                PATCHEX_STRUCT_TYPE_SHADOW_FLOW_SETTINGS,
                PATCHEX_STRUCT_TYPE_SUN_LIGHT,
                PATCHEX_STRUCT_TYPE_SKY_LIGHT,
                PATCHEX_STRUCT_TYPE_TRANSLUCENCY_INPUT,
            ],
            "PatchexFrameDesc",
        )?;
        context.submit(command_buffer, &desc, extensions)?;
        Ok(PatchexResult::Success)
    })
}

/// Records one extrapolation from the last submitted frame to the target instant described by
/// `desc` into `command_buffer`, writing `desc->output`. Up to
/// PATCHEX_MAX_EXTRAPOLATIONS_PER_FRAME calls per submitted frame (alpha 1/3 then 2/3, say).
/// Returns PATCHEX_RESULT_RENDER_INSTEAD (positive: the output is still written) when the
/// target is a camera cut from frame t, which no extrapolation can bridge.
///
/// Returns SUCCESS, RENDER_INSTEAD, or ERROR_NULL_POINTER, ERROR_INVALID_STRUCT_TYPE,
/// ERROR_STRUCT_VERSION, ERROR_INVALID_ARGUMENT, ERROR_UNSUPPORTED_FORMAT,
/// ERROR_MISSING_IMAGE_USAGE, ERROR_INVALID_LAYOUT, ERROR_MISMATCHED_EXTENT,
/// ERROR_EXTENT_TOO_LARGE, ERROR_WRONG_QUEUE_FAMILY, ERROR_NO_SOURCE_FRAME,
/// ERROR_TOO_MANY_EXTRAPOLATIONS, ERROR_OUT_OF_MEMORY, ERROR_VULKAN or ERROR_INTERNAL.
///
/// # Safety
/// As for `patchex_submit_gbuffers`; the command buffer must execute after the one holding the
/// submit (same command buffer, or a later submission on the same queue).
#[no_mangle]
pub unsafe extern "C" fn patchex_extrapolate(
    context: *mut PatchexContext,
    command_buffer: VkCommandBuffer,
    desc: *const PatchexExtrapolateDesc,
) -> PatchexResult {
    with_context(context, |context| {
        if command_buffer == VkCommandBuffer::null() {
            bail!(ErrorNullPointer, "command_buffer is VK_NULL_HANDLE");
        }
        let desc = read_versioned(
            desc,
            PATCHEX_STRUCT_TYPE_EXTRAPOLATE_DESC,
            "PatchexExtrapolateDesc",
        )?;
        let extensions = read_chain(
            desc.header.next,
            &[
                PATCHEX_STRUCT_TYPE_WARP_SETTINGS,
                PATCHEX_STRUCT_TYPE_SEGMENTATION_SETTINGS,
                PATCHEX_STRUCT_TYPE_DIAGNOSTICS,
                PATCHEX_STRUCT_TYPE_SHADOW_DIAGNOSTICS,
                PATCHEX_STRUCT_TYPE_TARGET_SHADOW_INPUT,
                PATCHEX_STRUCT_TYPE_NETWORK_SETTINGS,
            ],
            "PatchexExtrapolateDesc",
        )?;
        context.extrapolate(command_buffer, &desc, extensions)
    })
}

/// Fills `out_stats` (whose header the caller sets) with the GPU times and statistics of
/// `frame_index` and its extrapolations. Call it after the engine's fence for that frame has
/// signalled. The newest frames_in_flight submitted frames are held; after a reset that repeated
/// an index, the newest frame of that index answers.
///
/// Returns SUCCESS; NOT_READY (positive, `*out_stats` filled but its GPU results not final)
/// while the GPU has not finished the frame; or ERROR_FRAME_NOT_FOUND once the frame has left
/// the ring (or was never submitted), ERROR_NULL_POINTER, ERROR_INVALID_STRUCT_TYPE,
/// ERROR_STRUCT_VERSION or ERROR_INTERNAL.
///
/// # Safety
/// `context` is live; `out_stats` points to a writable PatchexFrameStats.
#[no_mangle]
pub unsafe extern "C" fn patchex_get_frame_stats(
    context: *mut PatchexContext,
    frame_index: u64,
    out_stats: *mut PatchexFrameStats,
) -> PatchexResult {
    with_context(context, |context| {
        let mut stats = read_versioned(
            out_stats.cast_const(),
            PATCHEX_STRUCT_TYPE_FRAME_STATS,
            "PatchexFrameStats",
        )?;
        let status = context.frame_stats(frame_index, &mut stats)?;
        out_stats.write(stats);
        Ok(status)
    })
}
