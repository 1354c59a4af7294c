//! Where each pass's counters sit in one region's range of the frame ring's counter buffer (a
//! submit or one extrapolation). Every offset is a multiple of 256, the largest storage- and
//! uniform-buffer offset alignment Vulkan allows.

use crate::passes::{inpaint, segmentation, shadow_flow, target_shadows, warp};

/// The frame warp's counts and largest motion (`warp::*_OFFSET`): holes, off-screen pixels, the
/// target's invalid geometry, and what it sanitised when it remodulates.
pub const WARP: u64 = 0;
/// Submit: demodulation's; extrapolation: remodulation's.
pub const SANITIZE: u64 = 256;
/// Holes of the shadow layer's move by its flow, kept apart from the frame's.
pub const SHADOW_WARP: u64 = 512;
/// Submit: the G-buffer packing's count of NaN and infinite geometry.
pub const GEOMETRY: u64 = 768;
pub const OBJECT_TABLE: u64 = 1024;
/// The networks' patch records (`inpaint::PATCH_SLOT_*`).
pub const PATCHES: u64 = (OBJECT_TABLE + segmentation::TABLE_BYTES).next_multiple_of(256);
/// The warps' uniform block (`warp::Cameras`), written by the extrapolation.
pub const CAMERAS: u64 = (PATCHES + inpaint::PATCH_SLOTS_BYTES).next_multiple_of(256);
/// The holes the G-buffer warp left to the fill (`warp::HoleList`).
pub const DEFERRED_HOLES: u64 = (CAMERAS + warp::CAMERAS_BYTES).next_multiple_of(256);
/// With a target shadow input: the sun's share summed over frame t's shadows.
pub const SUN_SHARE: u64 = DEFERRED_HOLES + 256;
/// Submit: the shadow flow's expansion constants (`shadow_flow::ExpansionConstants`), a uniform
/// block.
pub const EXPANSION: u64 = (SUN_SHARE + target_shadows::SUN_SHARE_BYTES).next_multiple_of(256);
/// One region's counters, which the frame ring allocates per region.
pub const REGION_BYTES: u64 = EXPANSION + shadow_flow::EXPANSION_BYTES;

// An extrapolation writes its region in one vkCmdUpdateBuffer (`plan::starting_counters`), which
// takes a multiple of 4 bytes under 65536.
const _: () = assert!(REGION_BYTES < 65536 && REGION_BYTES % 4 == 0);
