//! Mirror of the Farneback flow passes (`shaders/shadow_mask_finest.wgsl`,
//! `shadow_mask_pyramid.wgsl`, `shadow_poly.wgsl`, `shadow_flow_iterate.wgsl`,
//! `include/flow.wgsl`, `include/expansion.wgsl` and `include/atlas.wgsl`), one image per level instead of one atlas per
//! quantity; the pyramid is built level by level here, and on the GPU in the finest level's pass,
//! whose workgroups halve their tiles in workgroup memory.
//! An iteration is three steps here (`equations`, `rows`, `solve`) and one pass on the GPU,
//! which keeps the equations and their row sums in workgroup memory.

use glam::{Vec2, Vec4};

use super::{round_to_f16, Image};
use crate::camera::PixelRays;
use crate::passes::shadow_flow::{ExpansionConstants, FlowSettings, REGULARIZATION};

/// A level's polynomial expansion: (b1, b2, a11, a22) and a12.
pub struct Expansion {
    pub coefficients: Image,
    pub xy: Image,
}

fn texel(image: &Image, x: i32, y: i32) -> Vec4 {
    let v = image.clamped(x, y);
    Vec4::new(
        v[0],
        *v.get(1).unwrap_or(&0.0),
        *v.get(2).unwrap_or(&0.0),
        *v.get(3).unwrap_or(&0.0),
    )
}

/// `level_bilinear`: texel centres at integers, borders replicated.
fn bilinear(image: &Image, pos: Vec2) -> Vec4 {
    let size = Vec2::new(image.width as f32, image.height as f32);
    let inside = pos.clamp(Vec2::splat(-1.0), size);
    let base = inside.floor();
    let f = inside - base;
    let (x, y) = (base.x as i32, base.y as i32);
    let top = texel(image, x, y) * (1.0 - f.x) + texel(image, x + 1, y) * f.x;
    let bottom = texel(image, x, y + 1) * (1.0 - f.x) + texel(image, x + 1, y + 1) * f.x;
    top * (1.0 - f.y) + bottom * f.y
}

/// The mask pyramid: level 0 the mean of the frame's mask over blocks of `mask_step` pixels a
/// side, each level the 2x2 mean of the finer one.
pub fn pyramid(mask: &Image, levels: u32, mask_step: u32) -> Vec<Image> {
    let mut result: Vec<Image> = Vec::new();
    for _ in 0..levels {
        let finer = result.last().unwrap_or(mask);
        let n = if result.is_empty() {
            mask_step as usize
        } else {
            2
        };
        let level = Image::from_fn(
            finer.width.div_ceil(n),
            finer.height.div_ceil(n),
            1,
            |x, y| {
                let (x, y) = (n * x, n * y);
                let mut sum = 0.0;
                for dy in 0..n {
                    for dx in 0..n {
                        sum += finer.clamped((x + dx) as i32, (y + dy) as i32)[0];
                    }
                }
                vec![sum / (n * n) as f32]
            },
        );
        result.push(level);
    }
    result
}

pub fn expand(level: &Image, params: &ExpansionConstants) -> Expansion {
    let weights = [
        params.weight0,
        params.weight1,
        params.weight2,
        params.weight3,
    ];
    let r = params.radius;
    let mut xy = Image::new(level.width, level.height, 1);
    let coefficients = Image::from_fn(level.width, level.height, 4, |px, py| {
        let (mut s0, mut sx, mut sy, mut sxx, mut syy, mut sxy) = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        for dy in -r..=r {
            for dx in -r..=r {
                let f = level.clamped(px as i32 + dx, py as i32 + dy)[0];
                let wf =
                    weights[dx.unsigned_abs() as usize] * weights[dy.unsigned_abs() as usize] * f;
                let (x, y) = (dx as f32, dy as f32);
                s0 += wf;
                sx += wf * x;
                sy += wf * y;
                sxx += wf * x * x;
                syy += wf * y * y;
                sxy += wf * x * y;
            }
        }
        xy.set(px, py, &[sxy * params.inv_sum_xxyy]);
        vec![
            sx * params.inv_sum_xx,
            sy * params.inv_sum_xx,
            params.a_from_sum * s0 + params.a_from_xx * sxx + params.a_from_yy * syy,
            params.a_from_sum * s0 + params.a_from_yy * sxx + params.a_from_xx * syy,
        ]
    });
    Expansion { coefficients, xy }
}

/// Every level's expansion of a mask, as the submit computes it.
pub fn expand_pyramid(mask: &Image, settings: &FlowSettings, mask_step: u32) -> Vec<Expansion> {
    let levels = pyramid(mask, settings.levels, mask_step);
    let constants = settings.expansion();
    levels
        .iter()
        .map(|level| expand(level, &constants))
        .collect()
}

/// Where the flow starts: frame t's linear depth (channel 3 of the packed geometry) and
/// `Camera::reprojection_into` from frame t's camera into frame t-1's.
pub struct FlowStart<'a> {
    pub geometry: &'a Image,
    pub reprojection: PixelRays,
}

impl FlowStart<'_> {
    /// `camera_motion` of shadow_flow_iterate.wgsl: where static surfaces under texel p of a
    /// level of `step` frame pixels a texel moved into frame t-1, in that level's texels.
    fn camera_motion(&self, p: Vec2, step: u32) -> Vec2 {
        let step = step as f32;
        let r = &self.reprojection;
        let pixel = (p + 0.5) * step - 0.5;
        let nearest = (pixel + 0.5).floor();
        let depth = self.geometry.clamped(nearest.x as i32, nearest.y as i32)[3];
        let w = r.position + depth * (r.at_origin + pixel.x * r.per_x + pixel.y * r.per_y);
        let motion = (Vec2::new(w.y, w.z) / w.x - pixel) / step;
        // NaN fails both comparisons.
        let usable = w.x > 0.0 && motion.abs().cmplt(Vec2::splat(1e6)).all();
        if usable {
            motion
        } else {
            Vec2::ZERO
        }
    }
}

/// One iteration's per-texel equations: (G11, G12, G22, h1) and h2. `prior` is the flow the
/// estimate comes from (this level's or the coarser one); without one, the static receivers'
/// motion from `start` (with the level's frame pixels per texel).
pub fn equations(
    current: &Expansion,
    previous: &Expansion,
    prior: Option<&Image>,
    (start, step): (&FlowStart, u32),
) -> (Image, Image) {
    let (w, h) = (current.coefficients.width, current.coefficients.height);
    let mut h2_image = Image::new(w, h, 1);
    let eps = REGULARIZATION;
    let g = Image::from_fn(w, h, 4, |px, py| {
        let p = Vec2::new(px as f32, py as f32);
        let d = match prior {
            Some(prior) => {
                let ratio = Vec2::new(w as f32, h as f32)
                    / Vec2::new(prior.width as f32, prior.height as f32);
                let pos = (p + 0.5) / ratio - 0.5;
                let v = bilinear(prior, pos);
                Vec2::new(v.x, v.y) * ratio
            }
            None => start.camera_motion(p, step),
        };
        let c = texel(&current.coefficients, px as i32, py as i32);
        let c_xy = current.xy.at(px, py)[0];
        let at = p + d;
        let pr = bilinear(&previous.coefficients, at);
        let pr_xy = bilinear(&previous.xy, at).x;
        let a11 = 0.5 * (c.z + pr.z);
        let a22 = 0.5 * (c.w + pr.w);
        let a12 = 0.25 * (c_xy + pr_xy);
        let db = -0.5 * (Vec2::new(pr.x, pr.y) - Vec2::new(c.x, c.y))
            + Vec2::new(a11 * d.x + a12 * d.y, a12 * d.x + a22 * d.y);
        let g11 = a11 * a11 + a12 * a12 + eps;
        let g12 = a12 * (a11 + a22);
        let g22 = a22 * a22 + a12 * a12 + eps;
        let h1 = a11 * db.x + a12 * db.y + eps * d.x;
        let h2 = a12 * db.x + a22 * db.y + eps * d.y;
        h2_image.set(px, py, &[h2]);
        vec![g11, g12, g22, h1]
    });
    (g, h2_image)
}

/// The box sum along x (`horizontal`) or y of both equation images.
fn box_sum(equations: &Image, h2: &Image, radius: i32, horizontal: bool) -> (Image, Image) {
    let mut sums_h2 = Image::new(h2.width, h2.height, 1);
    let sums = Image::from_fn(equations.width, equations.height, 4, |x, y| {
        let mut sum = Vec4::ZERO;
        let mut sum_h2 = 0.0;
        for k in -radius..=radius {
            let (qx, qy) = if horizontal {
                (x as i32 + k, y as i32)
            } else {
                (x as i32, y as i32 + k)
            };
            sum += texel(equations, qx, qy);
            sum_h2 += h2.clamped(qx, qy)[0];
        }
        sums_h2.set(x, y, &[sum_h2]);
        sum.to_array().to_vec()
    });
    (sums, sums_h2)
}

pub fn rows(equations: &Image, h2: &Image, radius: i32) -> (Image, Image) {
    box_sum(equations, h2, radius, true)
}

/// The column sums of `rows` and the solve: the level's flow, (dx, dy, 0, 0).
pub fn solve(rows: &Image, rows_h2: &Image, radius: i32) -> Image {
    let (sum, h2) = box_sum(rows, rows_h2, radius, false);
    Image::from_fn(sum.width, sum.height, 4, |x, y| {
        let s = sum.at(x, y);
        let (g11, g12, g22, h1) = (s[0], s[1], s[2], s[3]);
        let h2 = h2.at(x, y)[0];
        let det = g11 * g22 - g12 * g12;
        vec![
            (g22 * h1 - g12 * h2) / det,
            (g11 * h2 - g12 * h1) / det,
            0.0,
            0.0,
        ]
    })
}

/// The flow of the pyramid's finest level, coarse to fine, from frame t's and frame t-1's
/// expansions, started at `start` (with the finest level's frame pixels per texel).
pub fn flow(
    current: &[Expansion],
    previous: &[Expansion],
    settings: &FlowSettings,
    (start, step): (&FlowStart, u32),
) -> Image {
    let radius = settings.window_radius as i32;
    let mut coarser: Option<Image> = None;
    for (index, (c, p)) in current.iter().zip(previous).enumerate().rev() {
        let mut estimate = coarser.take();
        for _ in 0..settings.iterations {
            let (g, h2) = equations(c, p, estimate.as_ref(), (start, step << index));
            let (r, r_h2) = rows(&g, &h2, radius);
            estimate = Some(solve(&r, &r_h2, radius));
        }
        coarser = estimate;
    }
    coarser.expect("at least one level")
}

/// The finest level's flow scaled up to `width` x `height`, as the shadow layer's warp reads it
/// (`frame_flow` in `include/atlas.wgsl`).
pub fn upsample(flow: &Image, width: usize, height: usize) -> Image {
    let ratio =
        Vec2::new(width as f32, height as f32) / Vec2::new(flow.width as f32, flow.height as f32);
    Image::from_fn(width, height, 4, |x, y| {
        let pos = (Vec2::new(x as f32, y as f32) + 0.5) / ratio - 0.5;
        let v = bilinear(flow, pos);
        let d = Vec2::new(v.x, v.y) * ratio;
        vec![round_to_f16(d.x), round_to_f16(d.y), 0.0, 0.0]
    })
}

/// Each pixel's displacement from frame t to frame t-1, from the two frames' masks as the flow
/// sees them (`separate_shadows::flow_mask`), with the finest level at a `mask_step`-th of the
/// frame's resolution, started at `start`.
pub fn frame_flow(
    current: &Image,
    previous: &Image,
    settings: &FlowSettings,
    mask_step: u32,
    start: &FlowStart,
) -> Image {
    let finest = flow(
        &expand_pyramid(current, settings, mask_step),
        &expand_pyramid(previous, settings, mask_step),
        settings,
        (start, mask_step),
    );
    upsample(&finest, current.width, current.height)
}
