//! Loads a built patchex shared library and resolves its C entry points, so that tests and
//! tools call the plugin exactly as an engine does: through the C ABI of a dynamically loaded
//! library, not through Rust calls into this crate.

use std::ffi::{c_char, CStr};
use std::path::{Path, PathBuf};

use crate::abi::*;
use crate::error::PatchexResult;
use crate::ffi::PatchexContext;

/// The entry points of one loaded library. The library stays loaded while this lives.
pub struct PatchexLibrary {
    pub abi_version: unsafe extern "C" fn() -> u32,
    pub result_string: unsafe extern "C" fn(i32) -> *const c_char,
    pub last_error: unsafe extern "C" fn(*const PatchexContext) -> *const c_char,
    pub create:
        unsafe extern "C" fn(*const PatchexCreateInfo, *mut *mut PatchexContext) -> PatchexResult,
    pub destroy: unsafe extern "C" fn(*mut PatchexContext),
    pub submit_gbuffers: unsafe extern "C" fn(
        *mut PatchexContext,
        VkCommandBuffer,
        *const PatchexFrameDesc,
    ) -> PatchexResult,
    pub extrapolate: unsafe extern "C" fn(
        *mut PatchexContext,
        VkCommandBuffer,
        *const PatchexExtrapolateDesc,
    ) -> PatchexResult,
    pub get_frame_stats:
        unsafe extern "C" fn(*mut PatchexContext, u64, *mut PatchexFrameStats) -> PatchexResult,
    _library: libloading::Library,
}

impl PatchexLibrary {
    /// # Safety
    /// `path` must be a patchex library built from this source (its symbols have these types).
    pub unsafe fn open(path: &Path) -> Result<Self, String> {
        let library = libloading::Library::new(path)
            .map_err(|e| format!("cannot load {}: {e}", path.display()))?;
        macro_rules! symbol {
            ($name:literal) => {
                *library
                    .get($name)
                    .map_err(|e| format!("{}: {e}", String::from_utf8_lossy($name)))?
            };
        }
        Ok(Self {
            abi_version: symbol!(b"patchex_abi_version"),
            result_string: symbol!(b"patchex_result_string"),
            last_error: symbol!(b"patchex_last_error"),
            create: symbol!(b"patchex_create"),
            destroy: symbol!(b"patchex_destroy"),
            submit_gbuffers: symbol!(b"patchex_submit_gbuffers"),
            extrapolate: symbol!(b"patchex_extrapolate"),
            get_frame_stats: symbol!(b"patchex_get_frame_stats"),
            _library: library,
        })
    }

    /// The library next to the running executable: `target/<profile>/libpatchex.so` for a test
    /// in `target/<profile>/deps/` or a tool in `target/<profile>/`, and `PREFIX/lib/` for a
    /// tool installed in `PREFIX/bin/`.
    pub fn beside_current_exe() -> Result<PathBuf, String> {
        let exe = std::env::current_exe().map_err(|e| e.to_string())?;
        let name = libloading::library_filename("patchex");
        let folders = exe.ancestors().skip(1).take(2);
        folders
            .clone()
            .map(|dir| dir.join(&name))
            .chain(folders.skip(1).map(|prefix| prefix.join("lib").join(&name)))
            .find(|candidate| candidate.exists())
            .ok_or_else(|| format!("no {} beside {}", name.to_string_lossy(), exe.display()))
    }

    /// The message of the last failed call on `context` (or on this thread, for NULL).
    ///
    /// # Safety
    /// `context` is null or a live context of this library.
    pub unsafe fn last_error_message(&self, context: *const PatchexContext) -> String {
        CStr::from_ptr((self.last_error)(context))
            .to_string_lossy()
            .into_owned()
    }
}
