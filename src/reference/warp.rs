//! Mirror of the backward warps: `shaders/include/surface.wgsl`, `shaders/include/warp.wgsl`,
//! `shaders/include/fill.wgsl` and the three warp passes.

use glam::{IVec2, Vec2, Vec3, Vec4};

use super::gbuffer::{is_sky, round_vec3_to_f16};
use super::pack_gbuffer::Packed;
use super::{round_to_f16, Image};
use crate::abi::*;
use crate::shaders::warp_gbuffer::Params;

pub const AGREEMENT_THRESHOLD: f32 = 0.5;
const MIN_FACING: f32 = 0.25;
pub const BILINEAR_ACCEPT: f32 = 0.5;
const MIN_TOTAL_WEIGHT: f32 = 1e-6;
/// The hole fill's window radius and tap spacing, and the cost of another object's texel; the
/// cheapest cost above which a window holds none of the target's surface, and the wider window
/// looked at then (`include/fill.wgsl`).
const FILL_RADIUS: i32 = 12;
const FILL_STEP: usize = 3;
const FILL_OTHER_OBJECT: f32 = 20.0;
const FILL_NO_MATCH: f32 = 9.0;
const FILL_WIDE_RADIUS: i32 = 96;
const FILL_WIDE_STEP: usize = 12;
/// The object id of a target pixel whose geometry is unusable: no 8-bit stencil holds it.
const NO_OBJECT: f32 = 256.0;

pub struct Warped {
    /// (shading, 1 for valid or 0 for hole).
    pub warped: Image,
    /// Per pixel, row by row: the divisor of its warped shading (`demodulated`), as the GPU holds
    /// it in the frame's alpha with the hole flag (`frame_alpha` in gbuffer.wgsl).
    pub divisor: Vec<f32>,
    /// The best geometry agreement each pixel found: how close it came to the hole threshold.
    pub best_agreement: Vec<f32>,
    /// G-buffer-guided warp only: the agreeing share of each pixel's bilinear footprint, how
    /// close it came to switching to the bilateral gather.
    pub bilinear_weight: Vec<f32>,
    pub hole_pixels: u32,
    pub offscreen_pixels: u32,
    /// The largest finite |motion| of a target pixel, in pixels.
    pub largest_motion: f32,
}

/// Frame t's packed images.
pub struct WarpSources<'a> {
    pub shading: &'a Image,
    pub geometry: &'a Image,
    pub normal_id: &'a Image,
}

/// The target's packed images, motion vectors and camera position.
pub struct WarpTarget<'a> {
    pub geometry: &'a Image,
    pub normal_id: &'a Image,
    pub motion: &'a Image,
    pub camera_position: Vec3,
    /// Per pixel, row by row: whether its geometry is usable (`Packed::valid`). A pixel whose
    /// geometry is not agrees with no source texel (`NO_OBJECT` in warp.wgsl): a hole.
    pub valid: &'a [bool],
}

impl<'a> WarpSources<'a> {
    /// `shading` of frame t, with frame t's packed G-buffer.
    pub fn of(shading: &'a Image, packed: &'a Packed) -> Self {
        Self {
            shading,
            geometry: &packed.geometry,
            normal_id: &packed.normal_id,
        }
    }
}

impl<'a> WarpTarget<'a> {
    /// The target's packed G-buffer with `motion`, which the warp follows.
    pub fn of(packed: &'a Packed, motion: &'a Image) -> Self {
        Self {
            geometry: &packed.geometry,
            normal_id: &packed.normal_id,
            motion,
            camera_position: packed.camera_position,
            valid: &packed.valid,
        }
    }
}

struct WarpedPixel {
    shading: Vec4,
    best_agreement: f32,
    bilinear_weight: f32,
    offscreen: bool,
}

/// One pixel's warp: the shared helpers of `include/warp.wgsl`, bound to one target pixel.
struct PixelWarp<'a> {
    params: &'a Params,
    source: &'a WarpSources<'a>,
    target: &'a WarpTarget<'a>,
    p: IVec2,
    target_geo: Vec4,
    target_nid: Vec4,
}

/// The Catmull-Rom weights of four texels in a row, for a point at `f` between the middle two.
fn catmull_rom_weights(f: f32) -> [f32; 4] {
    let (f2, f3) = (f * f, f * f * f);
    [
        -0.5 * f3 + f2 - 0.5 * f,
        1.5 * f3 - 2.5 * f2 + 1.0,
        -1.5 * f3 + 2.0 * f2 + 0.5 * f,
        0.5 * f3 - 0.5 * f2,
    ]
}

fn texel(image: &Image, s: IVec2) -> Vec4 {
    Vec4::from_slice(image.clamped(s.x, s.y))
}

/// The widths of `surface_cost`'s terms (`include/surface_match.wgsl`).
const MATCH_SIGMA_DEPTH: f32 = 0.03;
const MATCH_SIGMA_NORMAL: f32 = 0.15;

/// Mirror of `surface_cost` (`include/surface_match.wgsl`): how far a texel of frame t with
/// (linear depth, unit normal) `source` is from showing the surface `surface`, seen from `offset`
/// in a window of `radius`, as -log of a weight.
pub fn surface_cost(surface: (f32, Vec3), source: (f32, Vec3), offset: IVec2, radius: i32) -> f32 {
    let ((depth, normal), (source_w, source_normal)) = (surface, source);
    let relative = (source_w - depth).abs() / source_w.max(depth).max(1e-30);
    let depth_term = if relative <= 1.0 { relative } else { 1.0 } / MATCH_SIGMA_DEPTH;
    let normal_delta = source_normal - normal;
    let normal_term = normal_delta.dot(normal_delta) / (MATCH_SIGMA_NORMAL * MATCH_SIGMA_NORMAL);
    let distance_term = offset.dot(offset) as f32 / (radius * radius) as f32;
    depth_term * depth_term + normal_term + distance_term
}

/// One target pixel of a warp, as `include/surface.wgsl` and `include/fill.wgsl` see it: for
/// the passes beside the warps that test agreement and spread values as the warps do.
pub struct TargetPixel<'a>(PixelWarp<'a>);

impl<'a> TargetPixel<'a> {
    pub fn new(
        params: &'a Params,
        sources: &'a WarpSources<'a>,
        target: &'a WarpTarget<'a>,
        p: IVec2,
    ) -> Self {
        Self(PixelWarp::new(params, sources, target, p))
    }

    /// `agreement_at`: the agreement of frame t's texel `s` with the target's surface.
    pub fn agreement_at(&self, s: IVec2) -> f32 {
        self.0.agreement_at(s)
    }

    /// `fill_hole` of `include/fill.wgsl`: `sources.shading`'s texels spread to the pixel from
    /// source point `q` as the fill spreads shading there.
    pub fn fill_hole(&self, q: Vec2) -> Vec4 {
        self.0.fill_hole(q)
    }
}

impl<'a> PixelWarp<'a> {
    fn new(
        params: &'a Params,
        source: &'a WarpSources<'a>,
        target: &'a WarpTarget<'a>,
        p: IVec2,
    ) -> Self {
        let (x, y) = (p.x as usize, p.y as usize);
        let normal_id = Vec4::from_slice(target.normal_id.at(x, y));
        Self {
            params,
            source,
            target,
            p,
            target_geo: Vec4::from_slice(target.geometry.at(x, y)),
            target_nid: if target.valid[x + y * target.geometry.width] {
                normal_id
            } else {
                normal_id.with_w(NO_OBJECT)
            },
        }
    }

    fn extent(&self) -> IVec2 {
        IVec2::new(self.params.extent[0] as i32, self.params.extent[1] as i32)
    }

    fn source_point(&self, motion_at: IVec2) -> Vec2 {
        let motion = Vec2::from_slice(self.target.motion.clamped(motion_at.x, motion_at.y));
        self.p.as_vec2()
            + 0.5
            + motion * Vec2::from(self.params.motion_scale)
            + Vec2::from(self.params.jitter_delta)
    }

    fn is_offscreen(&self, q: Vec2) -> bool {
        let extent = self.extent().as_vec2();
        !(q.x >= 0.0 && q.y >= 0.0 && q.x < extent.x && q.y < extent.y)
    }

    fn texel_of(&self, q: Vec2) -> IVec2 {
        q.floor().as_ivec2().clamp(IVec2::ZERO, self.extent() - 1)
    }

    /// Agreement of the target's surface with a source texel (`agreement_at`).
    fn geometry_weight(&self, source_geo: Vec4, source_nid: Vec4) -> f32 {
        let (target_geo, target_nid) = (self.target_geo, self.target_nid);
        if target_nid.w != source_nid.w {
            return 0.0;
        }
        if is_sky(target_geo.w) || is_sky(source_geo.w) {
            return if is_sky(target_geo.w) && is_sky(source_geo.w) {
                1.0
            } else {
                0.0
            };
        }
        (-self.disagreement(source_geo, source_nid, self.params.in_plane_weight)).exp()
    }

    /// The exponent of the agreement of two surfaces neither of which is sky, with
    /// `in_plane_weight` as `Params::in_plane_weight`.
    fn disagreement(&self, source_geo: Vec4, source_nid: Vec4, in_plane_weight: f32) -> f32 {
        let (target_geo, target_nid, params) = (self.target_geo, self.target_nid, self.params);
        let normal_term =
            (1.0 - target_nid.truncate().dot(source_nid.truncate())) * params.inv_sigma_normal;
        let e = if target_nid.w == 0.0 {
            let view = (self.target.camera_position - target_geo.truncate()).normalize();
            let facing = target_nid.truncate().dot(view).abs().max(MIN_FACING);
            let footprint = target_geo.w * params.pixel_angle / facing;
            let normal = target_nid.truncate();
            let offset = source_geo.truncate() - target_geo.truncate();
            let across = normal.dot(offset) * normal;
            (across + in_plane_weight * (offset - across)).length() / footprint
                * params.inv_sigma_position
        } else {
            (target_geo.w - source_geo.w).abs() / target_geo.w.max(source_geo.w)
                * params.inv_sigma_depth
        };
        normal_term + e * e
    }

    fn agreement_at(&self, s: IVec2) -> f32 {
        self.geometry_weight(
            texel(self.source.geometry, s),
            texel(self.source.normal_id, s),
        )
    }

    /// Mirror of `on_static_surface`: texel `s` shows the static target surface somewhere on
    /// it.
    fn on_static_surface(&self, s: IVec2) -> bool {
        let (geometry, normal_id) = (
            texel(self.source.geometry, s),
            texel(self.source.normal_id, s),
        );
        normal_id.w == self.target_nid.w
            && !is_sky(self.target_geo.w)
            && !is_sky(geometry.w)
            && self.disagreement(geometry, normal_id, 0.0) <= -AGREEMENT_THRESHOLD.ln()
    }

    /// Mirror of `surface_around`: the 12 texels Catmull-Rom adds around q's four nearest show
    /// the static target surface.
    fn surface_around(&self, q: Vec2) -> bool {
        let corner = (q - 0.5).floor().as_ivec2();
        (-1..=2).all(|j| {
            (-1..=2).all(|i| {
                let nearest = (0..=1).contains(&i) && (0..=1).contains(&j);
                nearest
                    || self.on_static_surface(
                        corner
                            .wrapping_add(IVec2::new(i, j))
                            .clamp(IVec2::ZERO, self.extent() - 1),
                    )
            })
        })
    }

    /// Mirror of `fill_hole` in `include/fill.wgsl`: the window around q, or a wider one when
    /// it holds none of the target's surface.
    fn fill_hole(&self, q: Vec2) -> Vec4 {
        let centre = self.texel_of(q);
        let mut window = self.fill_window(centre, FILL_RADIUS, FILL_STEP);
        if window.least > FILL_NO_MATCH {
            let wide = self.fill_window(centre, FILL_WIDE_RADIUS, FILL_WIDE_STEP);
            if wide.least < window.least {
                window = wide;
            }
        }
        // As the shader, which spreads matrices too and so cannot divide.
        window.sum * (1.0 / window.total)
    }

    /// Mirror of `fill_window`: the window's texels weighted by exp(least cost - cost),
    /// rescaled as a cheaper texel appears.
    fn fill_window(&self, centre: IVec2, r: i32, step: usize) -> FillWindow {
        let mut window = FillWindow {
            sum: Vec4::ZERO,
            total: 0.0,
            least: 3.4e38,
        };
        for dy in (-r..=r).step_by(step) {
            for dx in (-r..=r).step_by(step) {
                let offset = IVec2::new(dx, dy);
                let s = centre
                    .wrapping_add(offset)
                    .clamp(IVec2::ZERO, self.extent() - 1);
                let cost = self.fill_cost(s, offset, r);
                if cost < window.least {
                    let rescale = (cost - window.least).exp();
                    window.sum *= rescale;
                    window.total *= rescale;
                    window.least = cost;
                }
                let w = (window.least - cost).exp();
                window.sum += w * texel(self.source.shading, s);
                window.total += w;
            }
        }
        window
    }

    /// Mirror of `fill_cost`: -log of texel `s`'s weight at offset `offset` in a window of
    /// radius `r`.
    fn fill_cost(&self, s: IVec2, offset: IVec2, r: i32) -> f32 {
        let source_nid = texel(self.source.normal_id, s);
        let other_object = if source_nid.w != self.target_nid.w {
            FILL_OTHER_OBJECT
        } else {
            0.0
        };
        let source = (texel(self.source.geometry, s).w, source_nid.truncate());
        let target = (self.target_geo.w, self.target_nid.truncate());
        surface_cost(target, source, offset, r) + other_object
    }

    fn bilinear_shading(&self, q: Vec2) -> Vec4 {
        let corner = (q - 0.5).floor().as_ivec2();
        let f = q - 0.5 - (q - 0.5).floor();
        let last = self.extent() - 1;
        let at = |offset: IVec2| {
            texel(
                self.source.shading,
                corner.wrapping_add(offset).clamp(IVec2::ZERO, last),
            )
        };
        let top = at(IVec2::new(0, 0)).lerp(at(IVec2::new(1, 0)), f.x);
        let bottom = at(IVec2::new(0, 1)).lerp(at(IVec2::new(1, 1)), f.x);
        top.lerp(bottom, f.y)
    }

    /// q's bilinear footprint with each texel weighted by its agreement: the weighted shading
    /// and weight sums, the best agreement of a texel with a share of it and the least of the
    /// four (`agreeing_footprint`).
    fn agreeing_footprint(&self, q: Vec2) -> (Vec4, f32, f32, f32) {
        // A huge motion vector saturates the conversion to i32: the neighbours' offsets wrap,
        // as WGSL's integer arithmetic does, and the clamp brings them back into the image.
        let corner = (q - 0.5).floor().as_ivec2();
        let f = q - 0.5 - (q - 0.5).floor();
        let mut shading_sum = Vec4::ZERO;
        let mut weight_sum = 0.0;
        let mut best_agreement: f32 = 0.0;
        let mut least_agreement: f32 = 1.0;
        for i in 0..4 {
            let offset = IVec2::new(i & 1, i >> 1);
            let s = corner
                .wrapping_add(offset)
                .clamp(IVec2::ZERO, self.extent() - 1);
            let agreement = self.agreement_at(s);
            let bx = if offset.x == 1 { f.x } else { 1.0 - f.x };
            let by = if offset.y == 1 { f.y } else { 1.0 - f.y };
            let footprint = bx * by;
            shading_sum += footprint * agreement * texel(self.source.shading, s);
            weight_sum += footprint * agreement;
            if footprint > 0.0 {
                best_agreement = best_agreement.max(agreement);
            }
            least_agreement = least_agreement.min(agreement);
        }
        (shading_sum, weight_sum, best_agreement, least_agreement)
    }

    /// Mirror of `catmull_rom_shading`: Catmull-Rom over the 4x4 texels around q, held within
    /// the range of the four nearest.
    fn catmull_rom_shading(&self, q: Vec2) -> Vec4 {
        let corner = (q - 0.5).floor().as_ivec2();
        let f = q - 0.5 - (q - 0.5).floor();
        let (wx, wy) = (catmull_rom_weights(f.x), catmull_rom_weights(f.y));
        let mut sum = Vec4::ZERO;
        let mut low = Vec4::splat(f32::MAX);
        let mut high = Vec4::splat(f32::MIN);
        for j in 0..4 {
            for i in 0..4 {
                let s = corner
                    .wrapping_add(IVec2::new(i - 1, j - 1))
                    .clamp(IVec2::ZERO, self.extent() - 1);
                let shading = texel(self.source.shading, s);
                sum += wx[i as usize] * wy[j as usize] * shading;
                if (1..=2).contains(&i) && (1..=2).contains(&j) {
                    low = low.min(shading);
                    high = high.max(shading);
                }
            }
        }
        sum.clamp(low, high)
    }

    /// Mirror of `warp_gbuffer.wgsl`.
    fn gbuffer_guided(&self) -> WarpedPixel {
        let extent = self.extent();
        let q = self.source_point(self.p);
        let (mut shading_sum, mut weight_sum, mut best_agreement, least_agreement) =
            self.agreeing_footprint(q);
        let bilinear_weight = weight_sum;
        if weight_sum < BILINEAR_ACCEPT {
            shading_sum = Vec4::ZERO;
            weight_sum = 0.0;
            let centre = self.texel_of(q);
            let r = self.params.kernel_radius;
            for dy in -r..=r {
                for dx in -r..=r {
                    let s = centre
                        .wrapping_add(IVec2::new(dx, dy))
                        .clamp(IVec2::ZERO, extent - 1);
                    let agreement = self.agreement_at(s);
                    let d = s.as_vec2() + 0.5 - q;
                    let weight =
                        (-d.dot(d) * self.params.inv_two_sigma_spatial_sq).exp() * agreement;
                    shading_sum += weight * texel(self.source.shading, s);
                    weight_sum += weight;
                    best_agreement = best_agreement.max(agreement);
                }
            }
        }
        let sharp = self.params.resample == PATCHEX_RESAMPLE_CATMULL_ROM
            && self.target_nid.w == 0.0
            && least_agreement >= AGREEMENT_THRESHOLD
            && self.surface_around(q);
        let mut shading = if sharp {
            self.catmull_rom_shading(q)
        } else if weight_sum > MIN_TOTAL_WEIGHT {
            shading_sum / weight_sum
        } else {
            texel(self.source.shading, self.texel_of(q))
        };
        let offscreen = self.is_offscreen(q);
        let hole = offscreen || best_agreement < AGREEMENT_THRESHOLD;
        if hole && self.params.hole_fill == PATCHEX_HOLE_FILL_BACKGROUND {
            shading = self.fill_hole(q);
        }
        WarpedPixel {
            shading,
            best_agreement,
            bilinear_weight,
            offscreen,
        }
    }

    /// Mirror of `warp_motion_vector.wgsl`.
    fn motion_vector(&self) -> WarpedPixel {
        let q = self.source_point(self.p);
        WarpedPixel {
            shading: self.bilinear_shading(q),
            best_agreement: self.agreement_at(self.texel_of(q)),
            bilinear_weight: f32::NAN,
            offscreen: self.is_offscreen(q),
        }
    }

    /// Mirror of `warp_occlusion_motion.wgsl`.
    fn occlusion_motion_vector(&self) -> WarpedPixel {
        let mut q = self.source_point(self.p);
        let mut best_agreement = if self.is_offscreen(q) {
            0.0
        } else {
            self.agreement_at(self.texel_of(q))
        };
        if best_agreement < AGREEMENT_THRESHOLD {
            let r = self.params.occlusion_search_radius;
            for dy in (-r..=r).step_by(2) {
                for dx in (-r..=r).step_by(2) {
                    let neighbour =
                        (self.p + IVec2::new(dx, dy)).clamp(IVec2::ZERO, self.extent() - 1);
                    let candidate = self.source_point(neighbour);
                    if self.is_offscreen(candidate) {
                        continue;
                    }
                    let agreement = self.agreement_at(self.texel_of(candidate));
                    if agreement > best_agreement {
                        best_agreement = agreement;
                        q = candidate;
                    }
                }
            }
        }
        let weighted = (self.params.agreeing_bilinear != 0)
            .then(|| self.agreeing_footprint(q))
            .filter(|&(_, weight_sum, _, _)| weight_sum > MIN_TOTAL_WEIGHT);
        let shading = weighted.map_or_else(
            || self.bilinear_shading(q),
            |(shading_sum, weight_sum, _, _)| shading_sum / weight_sum,
        );
        WarpedPixel {
            shading,
            best_agreement,
            bilinear_weight: f32::NAN,
            offscreen: self.is_offscreen(q),
        }
    }
}

/// Runs the warp `kind` over the whole frame.
pub fn warp(
    kind: PatchexWarpKind,
    source: &WarpSources,
    target: &WarpTarget,
    params: &Params,
) -> Warped {
    let (width, height) = (params.extent[0] as usize, params.extent[1] as usize);
    let mut best_agreement = Vec::with_capacity(width * height);
    let mut bilinear_weight = Vec::with_capacity(width * height);
    let (mut hole_pixels, mut offscreen_pixels) = (0, 0);
    let mut divisor = Vec::with_capacity(width * height);
    let mut largest_motion = 0.0f32;
    let warped = Image::from_fn(width, height, 4, |x, y| {
        let pixel = PixelWarp::new(params, source, target, IVec2::new(x as i32, y as i32));
        let result = match kind {
            PATCHEX_WARP_MOTION_VECTOR => pixel.motion_vector(),
            PATCHEX_WARP_OCCLUSION_MOTION_VECTOR => pixel.occlusion_motion_vector(),
            _ => pixel.gbuffer_guided(),
        };
        let hole = result.offscreen || result.best_agreement < AGREEMENT_THRESHOLD;
        hole_pixels += hole as u32;
        offscreen_pixels += result.offscreen as u32;
        best_agreement.push(result.best_agreement);
        bilinear_weight.push(result.bilinear_weight);
        let motion = Vec2::from_slice(target.motion.at(x, y)) * Vec2::from(params.motion_scale);
        let reach = motion.dot(motion).sqrt();
        if reach <= f32::MAX {
            largest_motion = largest_motion.max(reach);
        }
        // As the frame's alpha holds it (`frame_alpha` in gbuffer.wgsl).
        let fetched = result.shading.w;
        divisor.push(if hole {
            -1.0 - round_to_f16(-1.0 - fetched)
        } else {
            round_to_f16(fetched)
        });
        // Stored in an RGBA16F image (the frame, or a shadow layer).
        round_vec3_to_f16(result.shading.truncate())
            .extend(if hole { 0.0 } else { 1.0 })
            .to_array()
            .to_vec()
    });
    Warped {
        warped,
        divisor,
        best_agreement,
        bilinear_weight,
        hole_pixels,
        offscreen_pixels,
        largest_motion,
    }
}

/// A fill window's weighted sum, its total weight and its cheapest texel's cost.
struct FillWindow {
    sum: Vec4,
    total: f32,
    least: f32,
}
