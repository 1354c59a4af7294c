//! The harness's engine and images described to patchex, as an engine fills in the plugin's
//! structs: one place for the tests, the fuzzer and the command-line tool.

use ash::vk;
use patchex::abi::{PatchexCreateInfo, PatchexImage};

use crate::{Engine, EngineImage};

impl Engine {
    /// A create info for this engine's device and queue, for frames up to
    /// `max_width` x `max_height`, with the plugin's defaults otherwise.
    pub fn create_info(&self, max_width: u32, max_height: u32) -> PatchexCreateInfo {
        PatchexCreateInfo::new(
            self.instance.handle(),
            self.physical_device,
            self.device.handle(),
            self.get_instance_proc_addr(),
            self.queue_family_index,
            max_width,
            max_height,
        )
    }
}

impl EngineImage {
    /// This image as being in `layout` when the plugin's commands run.
    pub fn describe(&self, layout: vk::ImageLayout) -> PatchexImage {
        PatchexImage {
            image: self.image,
            view: self.view,
            format: self.format,
            width: self.width,
            height: self.height,
            layout,
            usage: self.usage,
        }
    }
}
