//! What a command reads and writes, by which `vk::recorder` orders commands: the resources a
//! descriptor or a transfer names, and whether it writes them.

use ash::vk;

use crate::vk::buffer::CounterRange;

/// What a command touches, for ordering.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Resource {
    /// A whole image (every layer), the plugin's or the engine's.
    Image(vk::Image),
    /// Bytes `start..end` of a buffer.
    Buffer {
        buffer: vk::Buffer,
        start: u64,
        end: u64,
    },
    /// Whatever earlier calls, or the engine, did before this call: conflicts with everything.
    Earlier,
}

impl Resource {
    pub fn range(range: &CounterRange) -> Self {
        Self::Buffer {
            buffer: range.buffer,
            start: range.offset,
            end: range.offset + range.range,
        }
    }

    pub fn overlaps(self, other: Self) -> bool {
        match (self, other) {
            (Self::Earlier, _) | (_, Self::Earlier) => true,
            (Self::Image(a), Self::Image(b)) => a == b,
            (
                Self::Buffer { buffer, start, end },
                Self::Buffer {
                    buffer: other,
                    start: other_start,
                    end: other_end,
                },
            ) => buffer == other && start < other_end && other_start < end,
            _ => false,
        }
    }
}

/// One resource a command reads or writes, in a pipeline stage.
#[derive(Clone, Copy, Debug)]
pub struct Access {
    pub resource: Resource,
    pub write: bool,
    pub stage: vk::PipelineStageFlags,
}
