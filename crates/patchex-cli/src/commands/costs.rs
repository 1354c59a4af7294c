//! What each stage costs in a hardware-independent form, for `patchex bench`: the bytes its
//! passes declare they read and write, its arithmetic and the dispatches and barriers it records
//! (`PatchexStageTraffic`), and from them a lower bound on named GPUs; and the device memory a
//! context holds.

use std::fmt::Write as _;

use patchex::abi::*;
use patchex::passes::STAGES;

/// A GPU's published peak figures.
pub struct PeakFigures {
    pub name: &'static str,
    pub bytes_per_second: f64,
    /// FP32 operations per second (an FMA counts two, as vendors count it).
    pub operations_per_second: f64,
    pub source: &'static str,
}

/// A current high-end gaming card.
pub const RTX_4090: PeakFigures = PeakFigures {
    name: "RTX 4090",
    bytes_per_second: 1008e9,
    operations_per_second: 82.6e12,
    source: "NVIDIA Ada GPU Architecture whitepaper (2022), appendix A: 1008 GB/s GDDR6X, \
             82.6 TFLOPS peak FP32",
};

/// The data-centre GPUs of the lent machines.
pub const H100_SXM: PeakFigures = PeakFigures {
    name: "H100 SXM",
    bytes_per_second: 3.35e12,
    operations_per_second: 67e12,
    source: "NVIDIA H100 Tensor Core GPU datasheet (2023): 3.35 TB/s HBM3, 67 TFLOPS FP32",
};

pub const H200: PeakFigures = PeakFigures {
    name: "H200",
    bytes_per_second: 4.8e12,
    operations_per_second: 67e12,
    source: "NVIDIA H200 Tensor Core GPU datasheet (2024): 4.8 TB/s HBM3e, 67 TFLOPS FP32",
};

/// The GPUs the bench bounds each stage on.
pub const BOUND_GPUS: [&PeakFigures; 3] = [&H200, &H100_SXM, &RTX_4090];

/// What a GPU pays per command however little it does, added to the roofline: a dispatch
/// starts its grid on the front end; a barrier drains the machine before the next command.
/// An assumption: NVIDIA quotes about 3 µs for launching an empty CUDA kernel from the host
/// (developer forums, "Too much time for kernel launch latency", 2022); a dispatch recorded in
/// a command buffer skips the host's part. `patchex bench` measures both on the device it runs
/// on (`fixed_costs`) and prints them beside the bounds; a GPU's measurement replaces this
/// assumption for that GPU's bound.
pub const SECONDS_PER_DISPATCH: f64 = 1e-6;
pub const SECONDS_PER_BARRIER: f64 = 1e-6;

/// One stage's costs, summed over the targets measured.
#[derive(Clone, Copy, Default)]
pub struct StageCost {
    pub gpu_ms: f64,
    pub bytes_read: f64,
    pub bytes_written: f64,
    pub operations: f64,
    pub dispatches: f64,
    pub barriers: f64,
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
                cost.dispatches += region.dispatches[stage] as f64;
                cost.barriers += region.barriers[stage] as f64;
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
            dispatches: cost.dispatches / n,
            barriers: cost.barriers / n,
        }
    }

    /// Every stage's costs together, per target.
    pub fn total(&self) -> StageCost {
        STAGES
            .iter()
            .map(|stage| self.mean(stage.id))
            .fold(StageCost::default(), |sum, cost| StageCost {
                gpu_ms: sum.gpu_ms + cost.gpu_ms,
                bytes_read: sum.bytes_read + cost.bytes_read,
                bytes_written: sum.bytes_written + cost.bytes_written,
                operations: sum.operations + cost.operations,
                dispatches: sum.dispatches + cost.dispatches,
                barriers: sum.barriers + cost.barriers,
            })
    }

    /// Bytes read and written per target over every stage.
    pub fn bytes(&self) -> f64 {
        let total = self.total();
        total.bytes_read + total.bytes_written
    }

    /// The bound per target over every stage, in seconds.
    pub fn bound_seconds(&self, gpu: &PeakFigures) -> f64 {
        STAGES
            .iter()
            .map(|stage| self.mean(stage.id).bound_seconds(gpu))
            .sum()
    }
}

impl StageCost {
    /// No GPU runs the stage faster than it can move its bytes or do its arithmetic, plus what
    /// its commands cost however little they do.
    pub fn bound_seconds(&self, gpu: &PeakFigures) -> f64 {
        ((self.bytes_read + self.bytes_written) / gpu.bytes_per_second)
            .max(self.operations / gpu.operations_per_second)
            + self.dispatches * SECONDS_PER_DISPATCH
            + self.barriers * SECONDS_PER_BARRIER
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
         inputs and output (PatchexStageTraffic), arithmetic operations per pixel (the \
         shaders' static counts; for inference, the layers' convolutions over the patches \
         run), the dispatches and barriers recorded, the time measured here, and a lower \
         bound on three GPUs: the larger of bytes over bandwidth and operations over peak, \
         plus {:.0} µs per dispatch and {:.0} µs per barrier (an assumption; see the speed \
         guide). The passes over the networks' patches count the share of the frame and \
         of their tensors that the patches span. Peak figures: {}.\n",
        SECONDS_PER_DISPATCH * 1e6,
        SECONDS_PER_BARRIER * 1e6,
        BOUND_GPUS
            .iter()
            .map(|gpu| gpu.source)
            .collect::<Vec<_>>()
            .join("; ")
    )
    .unwrap();
    write!(
        out,
        "| configuration | stage | read B/px | written B/px | ops/px | dispatches | barriers | \
         measured ms |"
    )
    .unwrap();
    for gpu in BOUND_GPUS {
        write!(out, " {} bound µs |", gpu.name).unwrap();
    }
    writeln!(out, "\n|{}", "---|".repeat(8 + BOUND_GPUS.len())).unwrap();
    let bounds = |bound: &dyn Fn(&PeakFigures) -> f64| {
        BOUND_GPUS
            .iter()
            .map(|gpu| format!(" {:.1} |", 1e6 * bound(gpu)))
            .collect::<String>()
    };
    for (c, label) in labels.iter().enumerate() {
        let row = &costs[detail_size][c];
        if row.targets == 0 {
            continue;
        }
        for stage in STAGES {
            let (cost, name) = (row.mean(stage.id), stage.name);
            if cost.dispatches + cost.gpu_ms == 0.0 {
                continue;
            }
            writeln!(
                out,
                "| {label} | {name} | {:.1} | {:.1} | {:.0} | {:.0} | {:.0} | {:.2} |{}",
                cost.bytes_read / pixels,
                cost.bytes_written / pixels,
                cost.operations / pixels,
                cost.dispatches,
                cost.barriers,
                cost.gpu_ms,
                bounds(&|gpu| cost.bound_seconds(gpu))
            )
            .unwrap();
        }
        let total = row.total();
        writeln!(
            out,
            "| {label} | **total** | | **{:.1} B/px moved** | | **{:.0}** | **{:.0}** | **{:.2}** |{}",
            row.bytes() / pixels,
            total.dispatches,
            total.barriers,
            total.gpu_ms,
            bounds(&|gpu| row.bound_seconds(gpu))
        )
        .unwrap();
    }
}

/// The same figures for bench.json.
pub fn json(costs: &Costs, pixels: f64) -> serde_json::Value {
    let stages: serde_json::Map<_, _> = STAGES
        .iter()
        .filter_map(|stage| {
            let (cost, name) = (costs.mean(stage.id), stage.name);
            (cost.dispatches + cost.gpu_ms > 0.0).then(|| {
                (
                    name.to_string(),
                    serde_json::json!({
                        "gpu_ms": cost.gpu_ms,
                        "bytes_read_per_pixel": cost.bytes_read / pixels,
                        "bytes_written_per_pixel": cost.bytes_written / pixels,
                        "operations_per_pixel": cost.operations / pixels,
                        "dispatches": cost.dispatches,
                        "barriers": cost.barriers,
                        "bound_us": bounds_json(&|gpu| cost.bound_seconds(gpu)),
                    }),
                )
            })
        })
        .collect();
    serde_json::json!({
        "device_memory_bytes": costs.device_memory_bytes,
        "bytes_per_pixel": costs.bytes() / pixels,
        "dispatches": costs.total().dispatches,
        "barriers": costs.total().barriers,
        "bound_us": bounds_json(&|gpu| costs.bound_seconds(gpu)),
        "stages": stages,
    })
}

/// Each bound GPU's figure in µs, by name.
fn bounds_json(bound: &dyn Fn(&PeakFigures) -> f64) -> serde_json::Value {
    BOUND_GPUS
        .iter()
        .map(|gpu| (gpu.name.to_string(), serde_json::json!(1e6 * bound(gpu))))
        .collect::<serde_json::Map<_, _>>()
        .into()
}
