//! What a command reads and writes, by which `vk::recorder` orders commands: the resources a
//! descriptor or a transfer names, and whether it writes them.

use ash::vk;

use crate::abi::PatchexStage;
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

/// What commands move and compute, as their shaders and bindings declare it: each binding's
/// resource counts once per command, whole (an image at its extent, a buffer range at its
/// size), read if the shader may load through it, written if it may store through it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Traffic {
    pub bytes_read: u64,
    pub bytes_written: u64,
    /// Arithmetic operations, from the shaders' static counts (`ShaderInfo::arithmetic`) times
    /// the invocations dispatched; indirect dispatches count none.
    pub operations: u64,
}

impl std::ops::AddAssign for Traffic {
    fn add_assign(&mut self, other: Self) {
        self.bytes_read += other.bytes_read;
        self.bytes_written += other.bytes_written;
        self.operations += other.operations;
    }
}

/// The commands a stage recorded: what a GPU pays for besides bytes and arithmetic.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Commands {
    /// Compute dispatches, direct and indirect.
    pub dispatches: u32,
    /// Pipeline barriers, each placed before a command that must wait for earlier ones.
    pub barriers: u32,
}

/// A stage a recorder recorded, and what its commands move and cost. What the call records
/// before its first stage (zeroing its counters, writing its cameras) counts in that stage, so
/// that the stages add up to the call.
#[derive(Clone, Debug)]
pub struct StageRecord {
    pub stage: PatchexStage,
    pub traffic: Traffic,
    pub commands: Commands,
    /// Traffic of dispatches over what the GPU decided (a list's length, a patch), whose share
    /// is read back with the frame's counters.
    pub shared: Vec<SharedTraffic>,
}

/// Bytes a dispatch moves in a share the GPU decides: it touches its resources only around
/// the entries of a list or inside a patch that an earlier pass wrote into the frame's counters.
#[derive(Clone, Copy, Debug)]
pub struct SharedTraffic {
    /// The traffic of the whole resources.
    pub traffic: Traffic,
    pub share: GpuShare,
}

/// Which share of its resources a dispatch touches, from what the GPU wrote into the frame
/// ring's counters (offsets into them).
#[derive(Clone, Copy, Debug)]
pub enum GpuShare {
    /// One invocation per entry of a list of `capacity`: the u32 at `count` entries.
    Entries { count: u64, capacity: u64 },
    /// The frame pixels a patch covers, of a frame of `capacity` pixels: its extent (two u32
    /// at `extent`) times its divisor (a u32 at `divisor`) on each axis.
    PatchPixels {
        extent: u64,
        divisor: u64,
        capacity: u64,
    },
    /// The texels a patch spans (its extent, two u32 at `extent`), of `capacity` texels.
    PatchTexels { extent: u64, capacity: u64 },
}

impl GpuShare {
    /// The share as a fraction (numerator, denominator) of the whole, with `read_u32` reading
    /// the counters; never more than the whole.
    pub fn fraction(&self, read_u32: impl Fn(u64) -> u32) -> (u64, u64) {
        let read = |offset: u64| read_u32(offset) as u64;
        let area = |extent: u64| read(extent) * read(extent + 4);
        let (part, whole) = match *self {
            Self::Entries { count, capacity } => (read(count), capacity),
            Self::PatchPixels {
                extent,
                divisor,
                capacity,
            } => (area(extent) * read(divisor) * read(divisor), capacity),
            Self::PatchTexels { extent, capacity } => (area(extent), capacity),
        };
        (part.min(whole), whole.max(1))
    }
}

impl SharedTraffic {
    /// The traffic of the share the GPU decided.
    pub fn scaled(&self, read_u32: impl Fn(u64) -> u32) -> Traffic {
        let (part, whole) = self.share.fraction(read_u32);
        let share = |amount: u64| amount * part / whole;
        Traffic {
            bytes_read: share(self.traffic.bytes_read),
            bytes_written: share(self.traffic.bytes_written),
            operations: share(self.traffic.operations),
        }
    }
}

/// Whether `next` must wait for `earlier`: one of them writes a resource the other touches.
pub fn conflict(earlier: &[Access], next: &[Access]) -> bool {
    next.iter().any(|n| {
        earlier
            .iter()
            .any(|e| (e.write || n.write) && e.resource.overlaps(n.resource))
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use ash::vk::Handle;

    fn image(handle: u64, write: bool) -> Access {
        Access {
            resource: Resource::Image(vk::Image::from_raw(handle)),
            write,
            stage: vk::PipelineStageFlags::COMPUTE_SHADER,
        }
    }

    fn bytes(start: u64, end: u64, write: bool) -> Access {
        Access {
            resource: Resource::Buffer {
                buffer: vk::Buffer::from_raw(7),
                start,
                end,
            },
            write,
            stage: vk::PipelineStageFlags::COMPUTE_SHADER,
        }
    }

    #[test]
    fn reads_share_and_writes_wait() {
        // Two passes reading one image, each writing its own, run side by side.
        let warp = [image(1, false), image(2, true)];
        let shadow_warp = [image(1, false), image(3, true)];
        assert!(!conflict(&warp, &shadow_warp));
        // Reading what was written, writing what was read or written: a barrier.
        assert!(conflict(&warp, &[image(2, false)]));
        assert!(conflict(&warp, &[image(1, true)]));
        assert!(conflict(&warp, &[image(2, true)]));
    }

    #[test]
    fn counters_conflict_only_where_their_bytes_overlap() {
        let warp_counters = [bytes(0, 12, true)];
        assert!(!conflict(&warp_counters, &[bytes(12, 24, true)]));
        assert!(conflict(&warp_counters, &[bytes(8, 16, false)]));
        assert!(!conflict(&[bytes(0, 256, false)], &[bytes(0, 256, false)]));
        // Another buffer's bytes are other bytes.
        let other = Access {
            resource: Resource::Buffer {
                buffer: vk::Buffer::from_raw(8),
                start: 0,
                end: 12,
            },
            ..warp_counters[0]
        };
        assert!(!conflict(&warp_counters, &[other]));
    }

    #[test]
    fn earlier_work_conflicts_with_everything() {
        let earlier = [Access {
            resource: Resource::Earlier,
            write: true,
            stage: vk::PipelineStageFlags::COMPUTE_SHADER,
        }];
        assert!(conflict(&earlier, &[image(1, false)]));
        assert!(conflict(&earlier, &[bytes(0, 4, false)]));
    }

    /// A patch of 24 x 10 texels (at offset 264) at divisor 2 (at 272), and a list of 30 entries
    /// (at 0).
    fn counters(offset: u64) -> u32 {
        match offset {
            0 => 30,
            264 => 24,
            268 => 10,
            272 => 2,
            _ => 0,
        }
    }

    #[test]
    fn gpu_shares_read_what_the_gpu_wrote() {
        let list = GpuShare::Entries {
            count: 0,
            capacity: 120,
        };
        assert_eq!(list.fraction(counters), (30, 120));
        let texels = GpuShare::PatchTexels {
            extent: 264,
            capacity: 64 * 64,
        };
        assert_eq!(texels.fraction(counters), (240, 4096));
        // 24 x 10 texels of 2 x 2 pixels each.
        let pixels = GpuShare::PatchPixels {
            extent: 264,
            divisor: 272,
            capacity: 160 * 90,
        };
        assert_eq!(pixels.fraction(counters), (960, 14400));
        // A patch padded past the frame counts the frame, no more.
        let small_frame = GpuShare::PatchPixels {
            extent: 264,
            divisor: 272,
            capacity: 900,
        };
        assert_eq!(small_frame.fraction(counters), (900, 900));
    }

    #[test]
    fn shared_traffic_scales_bytes_and_operations() {
        let shared = SharedTraffic {
            traffic: Traffic {
                bytes_read: 1200,
                bytes_written: 400,
                operations: 40,
            },
            share: GpuShare::Entries {
                count: 0,
                capacity: 120,
            },
        };
        let expected = Traffic {
            bytes_read: 300,
            bytes_written: 100,
            operations: 10,
        };
        assert_eq!(shared.scaled(counters), expected);
    }
}
