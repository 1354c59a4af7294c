//! Opens a written sequence.

use super::{read_exr, FrameLayers, Manifest};
use crate::error::{io_error, Error, Result};
use std::path::{Path, PathBuf};

pub struct Dataset {
    pub dir: PathBuf,
    pub manifest: Manifest,
}

impl Dataset {
    pub fn open(dir: impl AsRef<Path>) -> Result<Self> {
        let dir = dir.as_ref().to_path_buf();
        let manifest_path = dir.join("manifest.json");
        let text = std::fs::read_to_string(&manifest_path).map_err(io_error(&manifest_path))?;
        let manifest = serde_json::from_str(&text).map_err(|e| Error::Dataset {
            path: manifest_path,
            message: e.to_string(),
        })?;
        Ok(Self { dir, manifest })
    }

    pub fn frame_path(&self, index: usize) -> PathBuf {
        self.dir.join(frame_file_name(index))
    }

    pub fn read_frame(&self, index: usize) -> Result<FrameLayers> {
        if index >= self.manifest.frames.len() {
            return Err(Error::Dataset {
                path: self.dir.clone(),
                message: format!("frame {index} of {}", self.manifest.frames.len()),
            });
        }
        read_exr(&self.frame_path(index))
    }
}

pub(crate) fn frame_file_name(index: usize) -> String {
    format!("frame_{index:04}.exr")
}
