//! Mirror of the passes around the inpainting networks: `plan_patches.wgsl` (where each network
//! runs), `include/network_gather.wgsl` (what it reads) and `blend_patches.wgsl` (where its result
//! goes). The networks themselves are `reference::network::forward`.

use glam::Vec3;

use super::gbuffer::{sanitize, sanitize_color, MAX_HALF};
use super::network::{forward, Planes};
use super::{lbp, round_to_f16, Image};
use crate::abi::PATCHEX_DEFAULT_NETWORK_MAX_PATCH_SIDE;
use crate::network::{Network, TensorPrecision, INPUT_CHANNELS};
use crate::passes::inpaint::{patch_capacity, PATCH_MARGIN};
use crate::passes::segmentation::{REGION_FI, REGION_NEAR_BE};

/// Where a pass runs: `extent` texels from `origin` in the frame, each covering `divisor` x
/// `divisor` pixels, possibly reaching past the frame's right and bottom edges (those pixels
/// read as zero).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Patch {
    pub origin: [u32; 2],
    pub extent: [u32; 2],
    pub divisor: u32,
}

impl Default for Patch {
    fn default() -> Self {
        Self {
            origin: [0; 2],
            extent: [0; 2],
            divisor: 1,
        }
    }
}

impl Patch {
    pub fn is_empty(&self) -> bool {
        self.extent[0] == 0 || self.extent[1] == 0
    }

    fn contains(&self, x: usize, y: usize) -> bool {
        let inside = |p: usize, axis: usize| {
            let origin = self.origin[axis] as usize;
            p >= origin && p < origin + (self.extent[axis] * self.divisor) as usize
        };
        inside(x, 0) && inside(y, 1)
    }
}

/// `[lo, hi)` on both axes; `None` is the empty span.
type Span = Option<([u32; 2], [u32; 2])>;

fn union(a: Span, b: Span) -> Span {
    match (a, b) {
        (Some((alo, ahi)), Some((blo, bhi))) => Some((
            [alo[0].min(blo[0]), alo[1].min(blo[1])],
            [ahi[0].max(bhi[0]), ahi[1].max(bhi[1])],
        )),
        (a, None) => a,
        (None, b) => b,
    }
}

/// The networks a reference extrapolation runs (`PatchexNetworkSettings`); none by default.
#[derive(Clone, Copy, Debug)]
pub struct Networks<'a> {
    pub fi: Option<&'a Network>,
    pub near_be: Option<&'a Network>,
    /// The FI network over the whole frame, repairing every pixel; near-BE does not run.
    pub whole_frame: bool,
    /// How the layers' outputs are stored (`PatchexNetworkPrecision`).
    pub precision: TensorPrecision,
    /// Frame pixels per network texel on each axis (`resolution_divisor`).
    pub divisor: u32,
    /// The network texels a patch may span per axis (`PatchexNetworkMemory`).
    pub max_patch_side: u32,
    /// Corrections over every pixel of their region, not only the warp's holes.
    pub correct_valid_pixels: bool,
}

impl Default for Networks<'_> {
    fn default() -> Self {
        Self {
            fi: None,
            near_be: None,
            whole_frame: false,
            precision: TensorPrecision::default(),
            divisor: 1,
            max_patch_side: PATCHEX_DEFAULT_NETWORK_MAX_PATCH_SIDE,
            correct_valid_pixels: false,
        }
    }
}

impl Networks<'_> {
    pub fn any(&self) -> bool {
        self.fi.is_some() || self.near_be.is_some()
    }
}

/// The patches `plan_patches.wgsl` writes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Patches {
    pub fi: Patch,
    pub near_be: Patch,
    pub blend: Patch,
}

/// Plans the patches of a frame of `extent` from its segmentation: FI bounds the FI pixels of
/// `regions`, near-BE the grown `rects`; with `whole_frame`, FI bounds the frame. `levels` are
/// the FI and near-BE networks' level counts, 0 for a network that does not run; their texels
/// cover `divisor` pixels a side, or a multiple of it for a patch larger than `max_patch_side`
/// texels.
pub fn plan_patches(
    regions: &Image,
    rects: &[crate::abi::PatchexRegionRect],
    levels: [u32; 2],
    whole_frame: bool,
    divisor: u32,
    max_patch_side: u32,
) -> Patches {
    let extent = [regions.width as u32, regions.height as u32];
    let mut fi: Span = None;
    for y in 0..regions.height {
        for x in 0..regions.width {
            if regions.at(x, y)[0] as u32 == REGION_FI {
                let p = [x as u32, y as u32];
                fi = union(fi, Some((p, [p[0] + 1, p[1] + 1])));
            }
        }
    }
    if whole_frame {
        fi = Some(([0, 0], extent));
    }
    let near_be = rects.iter().fold(None, |span, r| {
        union(
            span,
            Some(([r.x, r.y], [r.x + r.width, r.y + r.height])).filter(|_| r.width * r.height > 0),
        )
    });
    let plan = |span: Span, levels: u32| -> Patch {
        let Some((lo, hi)) = span.filter(|_| levels > 0) else {
            return Patch::default();
        };
        let multiple = 1 << (levels - 1);
        let origin = lo.map(|v| v.saturating_sub(PATCH_MARGIN));
        let end = [0, 1].map(|a| (hi[a] + PATCH_MARGIN).min(extent[a]));
        let capacity = patch_capacity(extent, max_patch_side, multiple);
        let texels_at = |divisor: u32| {
            [0, 1].map(|a| {
                (end[a] - origin[a])
                    .div_ceil(divisor)
                    .next_multiple_of(multiple)
            })
        };
        let mut divisor = divisor;
        while (0..2).any(|a| texels_at(divisor)[a] > capacity[a]) {
            divisor *= 2;
        }
        Patch {
            origin,
            extent: texels_at(divisor),
            divisor,
        }
    };
    let fi = plan(fi, levels[0]);
    let near_be = plan(near_be, levels[1]);
    let as_span = |p: Patch| {
        (!p.is_empty()).then(|| {
            (
                p.origin,
                [0, 1].map(|a| p.origin[a] + p.extent[a] * p.divisor),
            )
        })
    };
    let blend = union(as_span(fi), as_span(near_be)).map_or(Patch::default(), |(lo, hi)| {
        let hi = [hi[0].min(extent[0]), hi[1].min(extent[1])];
        Patch {
            origin: lo,
            extent: [hi[0] - lo[0], hi[1] - lo[1]],
            divisor: 1,
        }
    });
    Patches { fi, near_be, blend }
}

/// The network's input planes over `patch` (`include/network_gather.wgsl`), rounded to f16 as the GPU
/// stores them: warped colour (held to the half-float range), hole, roughness, metallic, LBP,
/// zero. A texel is the mean of its `divisor` x `divisor` pixels, those outside the frame zero.
pub fn gather_inputs(warped: &Image, material: Option<&Image>, patch: Patch) -> Planes {
    let [width, height] = patch.extent.map(|v| v as usize);
    let d = patch.divisor as usize;
    let mut planes = Planes::zeros(INPUT_CHANNELS, width, height);
    for y in 0..height {
        for x in 0..width {
            let mut sum = [0.0f32; INPUT_CHANNELS];
            for j in 0..d {
                for i in 0..d {
                    let fx = patch.origin[0] as usize + x * d + i;
                    let fy = patch.origin[1] as usize + y * d + j;
                    if fx >= warped.width || fy >= warped.height {
                        continue;
                    }
                    let w = warped.at(fx, fy);
                    let (colour, _) = sanitize_color(Vec3::from_slice(w));
                    let (metallic, roughness) = match material {
                        Some(material) => {
                            let m = material.at(fx, fy);
                            let roughness = m.get(2).copied().unwrap_or(0.0);
                            let (v, _) = sanitize(Vec3::new(m[0], roughness, 0.0), 0.0, 1.0);
                            (v.x, v.y)
                        }
                        None => (0.0, 0.5),
                    };
                    let values = [
                        colour.x,
                        colour.y,
                        colour.z,
                        1.0 - w[3],
                        roughness,
                        metallic,
                        lbp::code(warped, fx as i32, fy as i32) as f32 / 255.0,
                        0.0,
                    ];
                    for (total, v) in sum.iter_mut().zip(values) {
                        *total += v;
                    }
                }
            }
            let mean = 1.0 / (d * d) as f32;
            for (c, total) in sum.into_iter().enumerate() {
                planes.values[(c * height + y) * width + x] = round_to_f16(total * mean);
            }
        }
    }
    planes
}

/// A network's correction at frame pixel (x, y) of `patch` (`blend_patches.wgsl`), upsampled
/// bilinearly from its texels.
fn corrected(correction: &Planes, patch: &Patch, x: usize, y: usize) -> [f32; 3] {
    let d = patch.divisor as f32;
    let q = [x - patch.origin[0] as usize, y - patch.origin[1] as usize];
    let last = [correction.width - 1, correction.height - 1];
    let t = [0, 1].map(|a| ((q[a] as f32 + 0.5) / d - 0.5).clamp(0.0, last[a] as f32));
    let lo = t.map(|v| v.floor() as usize);
    let hi = [0, 1].map(|a| (lo[a] + 1).min(last[a]));
    let f = [0, 1].map(|a| t[a] - t[a].floor());
    let mix = |a: f32, b: f32, t: f32| a * (1.0 - t) + b * t;
    [0, 1, 2].map(|c| {
        let at = |x: usize, y: usize| correction.at(c, x, y);
        let top = mix(at(lo[0], lo[1]), at(hi[0], lo[1]), f[0]);
        let bottom = mix(at(lo[0], hi[1]), at(hi[0], hi[1]), f[0]);
        mix(top, bottom, f[1])
    })
}

/// What the networks did to one frame.
pub struct Inpainted {
    pub patches: Patches,
    /// The FI and near-BE networks' corrections over their patches: output colour minus input
    /// colour (empty when they did not run).
    pub corrections: [Planes; 2],
    /// The warped frame with the repaired pixels blended in.
    pub blended: Image,
}

/// Runs the networks on their patches and blends their results into `warped`
/// (`blend_patches.wgsl`).
pub fn inpaint(
    networks: Networks,
    warped: &Image,
    material: Option<&Image>,
    regions: &Image,
    rects: &[crate::abi::PatchexRegionRect],
) -> Inpainted {
    let near_be = networks.near_be.filter(|_| !networks.whole_frame);
    let levels = [networks.fi, near_be].map(|n| n.map_or(0, |n| n.widths.len() as u32));
    let patches = plan_patches(
        regions,
        rects,
        levels,
        networks.whole_frame,
        networks.divisor,
        networks.max_patch_side,
    );
    let corrections = [(networks.fi, patches.fi), (near_be, patches.near_be)].map(
        |(network, patch)| match network {
            Some(network) if !patch.is_empty() => {
                let input = gather_inputs(warped, material, patch);
                let mut output =
                    forward(network, &input, networks.precision == TensorPrecision::F16);
                // The colour planes come first in both.
                for (o, i) in output.values.iter_mut().zip(&input.values) {
                    *o -= i;
                }
                output
            }
            _ => Planes::zeros(0, 0, 0),
        },
    );
    let mut blended = warped.clone();
    let sources = [
        (REGION_FI, patches.fi, &corrections[0]),
        (REGION_NEAR_BE, patches.near_be, &corrections[1]),
    ];
    for y in 0..warped.height {
        for x in 0..warped.width {
            let hole = warped.at(x, y)[3] == 0.0;
            if !patches.blend.contains(x, y) || !(hole || networks.correct_valid_pixels) {
                continue;
            }
            let region = regions.at(x, y)[0] as u32;
            let region = if networks.whole_frame {
                REGION_FI
            } else {
                region
            };
            for (id, patch, correction) in &sources {
                if region == *id && !patch.is_empty() && patch.contains(x, y) {
                    let c = corrected(correction, patch, x, y);
                    let w = warped.at(x, y);
                    // Into the RGBA16F frame, stopping at zero as blend_patches.wgsl does.
                    let sum = [0, 1, 2].map(|i| round_to_f16((w[i] + c[i]).clamp(0.0, MAX_HALF)));
                    blended.set(x, y, &[sum[0], sum[1], sum[2], w[3]]);
                }
            }
        }
    }
    Inpainted {
        patches,
        corrections,
        blended,
    }
}
