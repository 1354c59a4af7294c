//! What each stage costs in a hardware-independent form, for `patchex bench`: the bytes its
//! passes declare they read and write (`PatchexStageTraffic`), its arithmetic, and from both a
//! roofline lower bound on a named GPU; and the device memory a context holds.

use std::fmt::Write as _;

use patchex::abi::*;
use patchex::passes::STAGE_NAMES;

/// A GPU's published peak figures.
pub struct PeakFigures {
    pub name: &'static str,
    pub bytes_per_second: f64,
    /// FP32 operations per second (an FMA counts two, as vendors count it).
    pub operations_per_second: f64,
    pub source: &'static str,
}

/// The roofline's GPU: a current high-end gaming card.
pub const RTX_4090: PeakFigures = PeakFigures {
    name: "NVIDIA GeForce RTX 4090",
    bytes_per_second: 1008e9,
    operations_per_second: 82.6e12,
    source: "NVIDIA Ada GPU Architecture whitepaper (2022), appendix A: 1008 GB/s GDDR6X, \
             82.6 TFLOPS peak FP32",
};

/// One stage's costs, summed over the targets measured.
#[derive(Clone, Copy, Default)]
pub struct StageCost {
    pub gpu_ms: f64,
    pub bytes_read: f64,
    pub bytes_written: f64,
    pub operations: f64,
}

/// Every stage's costs for one configuration at one size, per target.
#[derive(Clone, Default)]
pub struct Costs {
    /// Submit plus one extrapolation, summed over targets (index PATCHEX_STAGE_*).
    pub stages: [StageCost; PATCHEX_STAGE_SLOTS],
    pub targets: usize,
    /// The most the context held.
    pub device_memory_bytes: u64,
}

impl Costs {
    /// Adds one target: frame t's submit and the first extrapolation from it.
    pub fn add(&mut self, stats: &PatchexFrameStats) {
        let extrapolation = &stats.extrapolations[0];
        let traffic = [&stats.submit_traffic, &stats.extrapolation_traffic[0]];
        for (stage, cost) in self.stages.iter_mut().enumerate() {
            cost.gpu_ms += (stats.submit_gpu_ms[stage] + extrapolation.gpu_ms[stage]) as f64;
            for region in traffic {
                cost.bytes_read += region.bytes_read[stage] as f64;
                cost.bytes_written += region.bytes_written[stage] as f64;
                cost.operations += region.arithmetic_operations[stage] as f64;
            }
        }
        self.targets += 1;
        self.device_memory_bytes = self.device_memory_bytes.max(stats.device_memory_bytes);
    }

    /// The stage's costs per target.
    pub fn mean(&self, stage: PatchexStage) -> StageCost {
        let n = self.targets.max(1) as f64;
        let cost = self.stages[stage as usize];
        StageCost {
            gpu_ms: cost.gpu_ms / n,
            bytes_read: cost.bytes_read / n,
            bytes_written: cost.bytes_written / n,
            operations: cost.operations / n,
        }
    }

    /// Bytes read and written per target over every stage.
    pub fn bytes(&self) -> f64 {
        STAGE_NAMES
            .iter()
            .map(|(stage, _)| self.mean(*stage))
            .map(|cost| cost.bytes_read + cost.bytes_written)
            .sum()
    }

    /// The roofline bound per target over every stage, in seconds.
    pub fn bound_seconds(&self, gpu: &PeakFigures) -> f64 {
        STAGE_NAMES
            .iter()
            .map(|(stage, _)| self.mean(*stage).bound_seconds(gpu))
            .sum()
    }
}

impl StageCost {
    /// No GPU runs the stage faster than it can move its bytes or do its arithmetic.
    pub fn bound_seconds(&self, gpu: &PeakFigures) -> f64 {
        ((self.bytes_read + self.bytes_written) / gpu.bytes_per_second)
            .max(self.operations / gpu.operations_per_second)
    }
}

const MIB: f64 = 1024.0 * 1024.0;

/// The device-memory table (configurations by sizes) and, at `detail_size`, the per-stage
/// cost table.
pub fn report(
    out: &mut String,
    sizes: &[(u32, u32)],
    labels: &[&str],
    costs: &[Vec<Costs>],
    detail_size: usize,
) {
    let gpu = &RTX_4090;
    writeln!(
        out,
        "\nDevice memory each configuration's context holds (its preset's images, counters and \
         tensors), MiB and bytes per pixel:\n"
    )
    .unwrap();
    write!(out, "| configuration |").unwrap();
    for size in sizes {
        write!(out, " {}x{} |", size.0, size.1).unwrap();
    }
    writeln!(out, "\n|{}", "---|".repeat(1 + sizes.len())).unwrap();
    for (c, label) in labels.iter().enumerate() {
        write!(out, "| {label} |").unwrap();
        for (size, row) in sizes.iter().zip(costs) {
            let bytes = row[c].device_memory_bytes as f64;
            let pixels = (size.0 * size.1) as f64;
            write!(out, " {:.1} ({:.0} B/px) |", bytes / MIB, bytes / pixels).unwrap();
        }
        writeln!(out).unwrap();
    }

    let (width, height) = sizes[detail_size];
    let pixels = (width * height) as f64;
    writeln!(
        out,
        "\nCost per stage at {width}x{height}, per target (submit plus one extrapolation): bytes \
         each stage's passes declare they read and write per pixel, counting the engine's \
         inputs and output (PatchexStageTraffic), arithmetic operations per pixel (a static \
         count), the time measured here, and the roofline lower bound on the {} ({}): the \
         larger of bytes over bandwidth and operations over peak. The networks' stages \
         (inference, blend) count their tensors whole, at the size the context holds them (the \
         largest patch, PatchexNetworkMemory), and their layers' arithmetic not at all: for them the bytes bound the traffic \
         from above and the roofline figure is no lower bound.\n\n\
         | configuration | stage | read B/px | written B/px | ops/px | measured ms | {} bound \
         µs |\n|---|---|---|---|---|---|---|",
        gpu.name, gpu.source, gpu.name
    )
    .unwrap();
    for (c, label) in labels.iter().enumerate() {
        let row = &costs[detail_size][c];
        if row.targets == 0 {
            continue;
        }
        for (stage, name) in STAGE_NAMES {
            let cost = row.mean(stage);
            if cost.bytes_read + cost.bytes_written + cost.gpu_ms == 0.0 {
                continue;
            }
            writeln!(
                out,
                "| {label} | {name} | {:.1} | {:.1} | {:.0} | {:.2} | {:.1} |",
                cost.bytes_read / pixels,
                cost.bytes_written / pixels,
                cost.operations / pixels,
                cost.gpu_ms,
                1e6 * cost.bound_seconds(gpu)
            )
            .unwrap();
        }
        let total_ms: f64 = STAGE_NAMES.iter().map(|(s, _)| row.mean(*s).gpu_ms).sum();
        writeln!(
            out,
            "| {label} | **total** | | **{:.1} B/px moved** | | **{total_ms:.2}** | **{:.1}** |",
            row.bytes() / pixels,
            1e6 * row.bound_seconds(gpu)
        )
        .unwrap();
    }
}

/// The same figures for bench.json.
pub fn json(costs: &Costs, pixels: f64) -> serde_json::Value {
    let stages: serde_json::Map<_, _> = STAGE_NAMES
        .iter()
        .filter_map(|(stage, name)| {
            let cost = costs.mean(*stage);
            (cost.bytes_read + cost.bytes_written + cost.gpu_ms > 0.0).then(|| {
                (
                    name.to_string(),
                    serde_json::json!({
                        "gpu_ms": cost.gpu_ms,
                        "bytes_read_per_pixel": cost.bytes_read / pixels,
                        "bytes_written_per_pixel": cost.bytes_written / pixels,
                        "operations_per_pixel": cost.operations / pixels,
                        "rtx_4090_bound_us": 1e6 * cost.bound_seconds(&RTX_4090),
                    }),
                )
            })
        })
        .collect();
    serde_json::json!({
        "device_memory_bytes": costs.device_memory_bytes,
        "bytes_per_pixel": costs.bytes() / pixels,
        "rtx_4090_bound_us": 1e6 * costs.bound_seconds(&RTX_4090),
        "stages": stages,
    })
}
