//! `patchex_get_frame_stats`: what a frame's submit and extrapolations recorded, read back from
//! the frame ring's counters and timestamps once the GPU has finished them.

use crate::abi::*;
use crate::context::Context;
use crate::error::{bail, PatchexResult, Result};
use crate::frame::counters;
use crate::passes::{inpaint, segmentation, warp};
use crate::vk::access::StageRecord;
use crate::vk::buffer::Buffer;

impl Context {
    /// Fills `out` for `frame_index`; `NotReady` while the GPU has not finished it.
    pub fn frame_stats(
        &self,
        frame_index: u64,
        out: &mut PatchexFrameStats,
    ) -> Result<PatchexResult> {
        // After a reset that restarted the numbering, the newest frame of that index answers.
        let Some((slot, record)) = self
            .ring
            .slots
            .iter()
            .enumerate()
            .filter_map(|(slot, s)| Some((slot, s.record.as_ref()?)))
            .filter(|(_, r)| r.frame_index == frame_index)
            .max_by_key(|(_, r)| r.serial)
        else {
            bail!(
                ErrorFrameNotFound,
                "frame {frame_index} is not among the last {} submitted frames",
                self.ring.slots.len()
            );
        };
        let mut ready = true;
        let mut read_times = |region: usize,
                              stages: &[StageRecord],
                              gpu_ms: &mut [f32; PATCHEX_STAGE_SLOTS]|
         -> Result<()> {
            let Some(timer) = &self.ring.timer else {
                return Ok(());
            };
            for &StageRecord { stage, .. } in stages {
                match timer.read_ms(&self.gpu.device, self.ring.query(slot, region, stage))? {
                    Some(ms) => gpu_ms[stage as usize] = ms,
                    None => ready = false,
                }
            }
            Ok(())
        };
        let mut submit_gpu_ms = [0.0; PATCHEX_STAGE_SLOTS];
        read_times(0, &record.submit.stages, &mut submit_gpu_ms)?;
        let mut extrapolations =
            [PatchexExtrapolationStats::default(); PATCHEX_MAX_EXTRAPOLATIONS_PER_FRAME];
        let mut extrapolation_traffic =
            [PatchexStageTraffic::default(); PATCHEX_MAX_EXTRAPOLATIONS_PER_FRAME];
        for (region_record, traffic) in record.extrapolations.iter().zip(&mut extrapolation_traffic)
        {
            *traffic = stage_traffic(&region_record.stages, &self.ring.readback);
        }
        let pixels = (record.extent.width * record.extent.height) as f32;
        for (index, (region_record, stats)) in record
            .extrapolations
            .iter()
            .zip(&mut extrapolations)
            .enumerate()
        {
            let region = 1 + index;
            read_times(region, &region_record.stages, &mut stats.gpu_ms)?;
            let counters = self.ring.counter_offset(slot, region);
            stats.alpha = region_record.alpha;
            stats.hole_fraction =
                self.ring
                    .readback
                    .read_u32(counters + warp::HOLE_PIXELS_OFFSET) as f32
                    / pixels;
            stats.offscreen_fraction =
                self.ring
                    .readback
                    .read_u32(counters + warp::OFFSCREEN_PIXELS_OFFSET) as f32
                    / pixels;
            let segmented =
                segmentation::read_back(&self.ring.readback, counters + counters::OBJECT_TABLE);
            // Remodulation counts on its own, or in the warp when the warp remodulates.
            let frame_warp = |offset| self.ring.readback.read_u32(counters + offset);
            stats.sanitized_pixels = self.ring.readback.read_u32(counters + counters::SANITIZE)
                + frame_warp(warp::SANITIZED_OFFSET);
            stats.invalid_geometry_pixels = frame_warp(warp::INVALID_GEOMETRY_OFFSET);
            stats.largest_motion = f32::from_bits(
                self.ring
                    .readback
                    .read_u32(counters + warp::LARGEST_MOTION_OFFSET),
            );
            stats.stages_run = stage_bits(&region_record.stages);
            // The networks' stages were recorded, but dispatch nothing on empty patches.
            // The divisor each network ran at; 0 for one whose patch was empty.
            let patches = [inpaint::PATCH_SLOT_FI, inpaint::PATCH_SLOT_NEAR_BE].map(|slot| {
                inpaint::read_patch(
                    &self.ring.readback,
                    counters + counters::PATCHES + slot * inpaint::PATCH_SLOT_BYTES,
                )
            });
            let divisors = patches.map(|(extent, divisor)| {
                if extent.iter().all(|&side| side > 0) {
                    divisor
                } else {
                    0
                }
            });
            stats.network_divisors = divisors;
            // The layers run over the patches the GPU planned: their arithmetic is known now.
            if let Some(inpainting) = &self.inpainting {
                extrapolation_traffic[index].arithmetic_operations
                    [PATCHEX_STAGE_INFERENCE as usize] += patches
                    .iter()
                    .zip(&inpainting.pipelines.networks)
                    .map(|((extent, _), network)| network.operations(*extent))
                    .sum::<u64>();
            }
            let (fi_ran, near_be_ran) = (divisors[0] > 0, divisors[1] > 0);
            if !fi_ran && !near_be_ran {
                // The blend still remodulated the frame.
                stats.stages_run &= !(1 << PATCHEX_STAGE_INFERENCE);
            }
            if region_record.camera_cut {
                stats.render_instead_reasons |= PATCHEX_RENDER_INSTEAD_CAMERA_CUT;
            }
            if stats.hole_fraction > PATCHEX_MAX_TRUSTED_HOLE_FRACTION {
                stats.render_instead_reasons |= PATCHEX_RENDER_INSTEAD_DISOCCLUSION;
            }
            stats.fi_fraction = segmented.fi_pixels as f32 / pixels;
            stats.near_be_fraction = segmented.near_be_pixels as f32 / pixels;
            stats.repaired_fraction = if region_record.whole_frame {
                fi_ran as u32 as f32
            } else {
                (fi_ran as u32 * segmented.fi_pixels
                    + near_be_ran as u32 * segmented.near_be_pixels) as f32
                    / pixels
            };
            stats.object_count = segmented.rects.len() as u32;
            for (reported, rect) in stats.rects.iter_mut().zip(&segmented.rects) {
                *reported = *rect;
            }
        }
        *out = PatchexFrameStats {
            header: out.header,
            frame_index,
            width: record.extent.width,
            height: record.extent.height,
            reset_reason: record.reset_reason,
            timings_valid: self.ring.timer.is_some() as u32,
            submit_gpu_ms,
            source_sanitized_pixels: self
                .ring
                .readback
                .read_u32(self.ring.counter_offset(slot, 0) + counters::SANITIZE),
            source_invalid_geometry_pixels: self
                .ring
                .readback
                .read_u32(self.ring.counter_offset(slot, 0) + counters::GEOMETRY),
            extrapolation_count: record.extrapolations.len() as u32,
            extrapolations,
            device_memory_bytes: self.device_memory_bytes(),
            submit_stages_run: stage_bits(&record.submit.stages),
            shadow_history: record.shadow_history,
            submit_traffic: stage_traffic(&record.submit.stages, &self.ring.readback),
            extrapolation_traffic,
        };
        Ok(if ready {
            PatchexResult::Success
        } else {
            PatchexResult::NotReady
        })
    }

    fn device_memory_bytes(&self) -> u64 {
        self.images.size_bytes()
            + self.ring.retired_bytes()
            + self.ring.counters.size_bytes()
            + self.ring.readback.size_bytes()
            + self.inpainting.as_ref().map_or(0, |i| i.size_bytes())
    }
}

/// The stages that ran, as bits 1 << PATCHEX_STAGE_*.
fn stage_bits(stages: &[StageRecord]) -> u32 {
    stages
        .iter()
        .fold(0, |bits, record| bits | 1 << record.stage)
}

/// Each stage's traffic, dispatches over what the GPU decided counted for the shares
/// `counters` hold.
fn stage_traffic(stages: &[StageRecord], counters: &Buffer) -> PatchexStageTraffic {
    let mut out = PatchexStageTraffic::default();
    for StageRecord {
        stage,
        traffic,
        commands,
        shared,
    } in stages
    {
        let stage = *stage as usize;
        let mut total = *traffic;
        for part in shared {
            total += part.scaled(|offset| counters.read_u32(offset));
        }
        out.bytes_read[stage] += total.bytes_read;
        out.bytes_written[stage] += total.bytes_written;
        out.arithmetic_operations[stage] += total.operations;
        out.dispatches[stage] += commands.dispatches;
        out.barriers[stage] += commands.barriers;
    }
    out
}
