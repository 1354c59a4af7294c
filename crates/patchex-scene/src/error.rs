//! The crate's error type: every failure carries enough context to act on without a backtrace.

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error("Vulkan: {context}: {result}")]
    Vulkan {
        context: &'static str,
        result: ash::vk::Result,
    },
    #[error("Vulkan loader: {0}")]
    Loader(String),
    #[error("no Vulkan 1.3 device with a graphics and compute queue was found")]
    NoDevice,
    #[error("no GPU memory type fits {0}")]
    NoMemoryType(&'static str),
    #[error("glTF {path}: {message}")]
    Gltf { path: PathBuf, message: String },
    #[error("scene {path}: {message}")]
    Scene { path: PathBuf, message: String },
    #[error("EXR {path}: {message}")]
    Exr { path: PathBuf, message: String },
    #[error("dataset {path}: {message}")]
    Dataset { path: PathBuf, message: String },
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
}

pub type Result<T> = std::result::Result<T, Error>;

/// Adds the failing call's name to a raw `vk::Result`.
pub(crate) trait VkContext<T> {
    fn vk(self, context: &'static str) -> Result<T>;
}

impl<T> VkContext<T> for std::result::Result<T, ash::vk::Result> {
    fn vk(self, context: &'static str) -> Result<T> {
        self.map_err(|result| Error::Vulkan { context, result })
    }
}

pub(crate) fn io_error(path: impl Into<PathBuf>) -> impl FnOnce(std::io::Error) -> Error {
    let path = path.into();
    move |source| Error::Io { path, source }
}
