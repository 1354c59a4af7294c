//! Mirror of `shaders/separate_translucency.wgsl` and `shaders/place_translucency.wgsl`.

use glam::{IVec2, Vec2, Vec3, Vec4};

use super::gbuffer::{
    demodulated, pixel_modulation, sanitize, sanitize_color, sanitize_input_color, MAX_HALF,
};
use super::warp::{surface_cost, TargetPixel, WarpSources, WarpTarget, AGREEMENT_THRESHOLD};
use super::{round_to_f16, Image};
use crate::passes::warp::Params;

const BEHIND_RADIUS: i32 = 48;
const BEHIND_STEP: usize = 8;
const BEHIND_MAX_COST: f32 = 9.0;
const MIN_COVERAGE: f32 = 0.05;
const MIN_ESTIMATED_COVERAGE: f32 = 0.2;
const FLAT_REACH: i32 = 8;
const FLAT_TOLERANCE: f32 = 0.01;
const SAME_MOTION: f32 = 0.5;
const SAME_MOTION_EXACT: f32 = 0.1;
const MOTION_SEARCH_STEP: i32 = 2;
const GAP_REACH: i32 = 4;

/// A `PatchexTranslucencyInput`: the mask, and the motion vectors with their scale.
#[derive(Clone, Copy)]
pub struct Input<'a> {
    pub mask: &'a Image,
    pub motion: Option<(&'a Image, [f32; 2])>,
    /// Frame t's colour before its translucency pass.
    pub opaque: Option<&'a Image>,
}

/// Frame t's inputs to the separation.
pub struct SourceTranslucency<'a> {
    pub color: &'a Image,
    pub base_color: &'a Image,
    pub material: Option<&'a Image>,
    pub mask: &'a Image,
    /// The motion vectors and their scale.
    pub motion: Option<(&'a Image, [f32; 2])>,
    /// Frame t's geometry motion vectors and their scale, when it came with them.
    pub surface_motion: Option<(&'a Image, [f32; 2])>,
    /// Frame t's colour before its translucency pass, when the engine gave it.
    pub opaque: Option<&'a Image>,
    /// Frame t's packed G-buffer: (position, linear depth) and (normal, object id).
    pub geometry: &'a Image,
    pub normal_id: &'a Image,
}

/// What the separation leaves: the shading with covered texels replaced, the layer (premultiplied
/// colour, coverage), its motion, and the pixels sanitised.
pub struct Separated {
    pub shading: Image,
    pub layer: Image,
    pub motion: Image,
    pub sanitized: u32,
}

/// `coverage`: the mask, sanitised, and 0 below MIN_COVERAGE.
fn coverage(mask: &Image, x: usize, y: usize) -> (f32, bool) {
    let (v, changed) = sanitize(Vec3::new(mask.at(x, y)[0], 0.0, 0.0), 0.0, 1.0);
    (if v.x >= MIN_COVERAGE { v.x } else { 0.0 }, changed)
}

/// `uniform_layer`: whether the coverage FLAT_REACH pixels away in every direction is `a`'s.
fn uniform_layer(mask: &Image, p: IVec2, a: f32) -> bool {
    let last = IVec2::new(mask.width as i32, mask.height as i32) - 1;
    (0..9).all(|i| {
        let s = p + FLAT_REACH * IVec2::new(i % 3 - 1, i / 3 - 1);
        let outside = s.cmplt(IVec2::ZERO).any() || s.cmpgt(last).any();
        outside || (coverage(mask, s.x as usize, s.y as usize).0 - a).abs() <= FLAT_TOLERANCE
    })
}

/// `shading_behind`: the weighted mean shading of the uncovered texels of p's object around it.
fn shading_behind(shading: &Image, inputs: &SourceTranslucency, p: IVec2) -> Option<Vec3> {
    let at = |image: &Image, s: IVec2| Vec4::from_slice(image.at(s.x as usize, s.y as usize));
    let (depth, own) = (at(inputs.geometry, p).w, at(inputs.normal_id, p));
    let last = IVec2::new(shading.width as i32, shading.height as i32) - 1;
    let mut least = 3.4e38f32;
    let (mut sum, mut total) = (Vec3::ZERO, 0.0f32);
    for dy in (-BEHIND_RADIUS..=BEHIND_RADIUS).step_by(BEHIND_STEP) {
        for dx in (-BEHIND_RADIUS..=BEHIND_RADIUS).step_by(BEHIND_STEP) {
            let offset = IVec2::new(dx, dy);
            let s = p + offset;
            if s.cmplt(IVec2::ZERO).any() || s.cmpgt(last).any() {
                continue;
            }
            if coverage(inputs.mask, s.x as usize, s.y as usize).0 > 0.0 {
                continue;
            }
            let theirs = at(inputs.normal_id, s);
            if theirs.w != own.w {
                continue;
            }
            let source = (at(inputs.geometry, s).w, theirs.truncate());
            let cost = surface_cost((depth, own.truncate()), source, offset, BEHIND_RADIUS);
            if cost > BEHIND_MAX_COST {
                continue;
            }
            if cost < least {
                let rescale = (cost - least).exp();
                sum *= rescale;
                total *= rescale;
                least = cost;
            }
            let w = (least - cost).exp();
            sum += w * at(shading, s).truncate();
            total += w;
        }
    }
    (total != 0.0).then(|| sum / total)
}

/// Takes frame t's translucency apart from the surfaces in `shading` (its demodulated shading).
pub fn separate(shading: &Image, inputs: &SourceTranslucency) -> Separated {
    let (width, height) = (shading.width, shading.height);
    let mut out = Separated {
        shading: shading.clone(),
        layer: Image::new(width, height, 4),
        motion: Image::new(width, height, 2),
        sanitized: 0,
    };
    // Given the colour before the translucency pass, the layer is taken apart exactly, and only
    // a layer lying on its surface is left in the colour.
    let exact = inputs.opaque.is_some();
    let same_motion = if exact {
        SAME_MOTION_EXACT
    } else {
        SAME_MOTION
    };
    for y in 0..height {
        for x in 0..width {
            let p = IVec2::new(x as i32, y as i32);
            let (mut a, mut changed) = coverage(inputs.mask, x, y);
            if !exact && (a < MIN_ESTIMATED_COVERAGE || uniform_layer(inputs.mask, p, a)) {
                a = 0.0;
            }
            let mut own = Vec2::ZERO;
            if let Some((motion, scale)) = inputs.motion {
                let stored = Vec2::from_slice(motion.at(x, y)) * Vec2::from(scale);
                let usable = stored.abs().cmple(Vec2::splat(MAX_HALF)).all();
                if usable {
                    own = Vec2::new(round_to_f16(stored.x), round_to_f16(stored.y));
                }
                changed |= a > 0.0 && !usable;
                if let Some((surface_motion, scale)) = inputs.surface_motion {
                    let surface = Vec2::from_slice(surface_motion.at(x, y)) * Vec2::from(scale);
                    if usable && (own - surface).length() <= same_motion {
                        a = 0.0;
                    }
                }
            }
            if a > 0.0 {
                let (c, color_changed) =
                    sanitize_input_color(Vec3::from_slice(&inputs.color.at(x, y)[..3]));
                changed |= color_changed;
                let mut surface = c;
                let (factor, _) = pixel_modulation(inputs.base_color, inputs.material, x, y);
                if let Some(opaque) = inputs.opaque {
                    let (o, opaque_changed) =
                        sanitize_input_color(Vec3::from_slice(&opaque.at(x, y)[..3]));
                    changed |= opaque_changed;
                    surface = o;
                    out.shading
                        .set(x, y, &demodulated(surface, factor).to_array());
                } else if let Some(behind) = shading_behind(shading, inputs, p) {
                    surface = (behind * factor).min(Vec3::splat(MAX_HALF));
                    out.shading
                        .set(x, y, &demodulated(surface, factor).to_array());
                }
                let over = (c - (1.0 - a) * surface).clamp(Vec3::ZERO, c);
                let rounded = over.to_array().map(round_to_f16);
                out.layer
                    .set(x, y, &[rounded[0], rounded[1], rounded[2], round_to_f16(a)]);
                out.motion.set(x, y, &own.to_array());
            }
            out.sanitized += changed as u32;
        }
    }
    out
}

/// What the layer is placed at the target with.
pub struct TargetTranslucency<'a> {
    pub layer: &'a Image,
    /// The layer's own motion, when frame t gave one.
    pub motion: Option<&'a Image>,
    /// Frame t's packed G-buffer (`Packed::geometry` and `normal_id`).
    pub source_geometry: &'a Image,
    pub source_normal_id: &'a Image,
    /// The target's packed G-buffer and motion vectors, as the warp reads them.
    pub target: WarpTarget<'a>,
    /// The call's warp (`WarpSettings::params`): motion scale, jitter and agreement test.
    pub warp: &'a Params,
    pub alpha: f32,
}

/// `step_from`: where the motion of the most covered texel around `x` leads from `centre`.
fn step_from(inputs: &TargetTranslucency, motion: &Image, x: Vec2, centre: Vec2) -> Vec2 {
    let layer = inputs.layer;
    let extent = Vec2::new(layer.width as f32, layer.height as f32);
    let around = x.clamp(Vec2::ZERO, extent).floor().as_ivec2();
    let (mut best, mut found) = (0.0f32, x);
    for i in 0..9 {
        let s = around + MOTION_SEARCH_STEP * IVec2::new(i % 3 - 1, i / 3 - 1);
        let a = layer.clamped(s.x, s.y)[3];
        if a > best {
            best = a;
            found = centre + inputs.alpha * Vec2::from_slice(motion.clamped(s.x, s.y));
        }
    }
    found
}

fn layer_at(layer: &Image, x: Vec2) -> Vec4 {
    let extent = Vec2::new(layer.width as f32, layer.height as f32);
    if x.cmplt(Vec2::ZERO).any() || x.cmpgt(extent).any() {
        return Vec4::ZERO;
    }
    let corner = (x - 0.5).floor().as_ivec2();
    let f = x - 0.5 - (x - 0.5).floor();
    let at = |offset: IVec2| {
        let s = corner + offset;
        Vec4::from_slice(layer.clamped(s.x, s.y))
    };
    // WGSL's mix, term for term.
    let mix = |a: Vec4, b: Vec4, t: f32| a * (1.0 - t) + b * t;
    mix(
        mix(at(IVec2::ZERO), at(IVec2::X), f.x),
        mix(at(IVec2::Y), at(IVec2::ONE), f.x),
        f.y,
    )
}

/// `object_takes_layer`: whether the dynamic object `id`, which frame t showed at `x`, takes the
/// layer: where the layer covers the texel under `x`, or, where it covers `x` read bilinear,
/// where one of the 3x3 texels around shows the object under the layer.
fn object_takes_layer(inputs: &TargetTranslucency, x: Vec2, id: f32) -> bool {
    let layer = inputs.layer;
    let extent = IVec2::new(layer.width as i32, layer.height as i32);
    let under = x.floor().as_ivec2().clamp(IVec2::ZERO, extent - 1);
    if layer.at(under.x as usize, under.y as usize)[3] > 0.0 {
        return true;
    }
    layer_at(layer, x).w > 0.0
        && (0..9).any(|i| {
            let s = under + IVec2::new(i % 3 - 1, i / 3 - 1);
            inputs.source_normal_id.clamped(s.x, s.y)[3] == id && layer.clamped(s.x, s.y)[3] > 0.0
        })
}

/// `inside_layer`: whether the layer covers `q` and the 8 points `GAP_REACH` pixels around it.
fn inside_layer(layer: &Image, q: Vec2) -> bool {
    let centre = q.floor().as_ivec2();
    let extent = IVec2::new(layer.width as i32, layer.height as i32);
    (0..9).all(|i| {
        let s = centre + GAP_REACH * IVec2::new(i % 3 - 1, i / 3 - 1);
        s.cmpge(IVec2::ZERO).all()
            && s.cmplt(extent).all()
            && layer.at(s.x as usize, s.y as usize)[3] > 0.0
    })
}

/// `layer_with_surface`: the layer that comes with the pixel's static surface, which lay at `q`
/// in frame t, where the splat leaves it partly uncovered.
fn layer_with_surface(inputs: &TargetTranslucency, pixel: &TargetPixel, q: Vec2) -> Vec4 {
    let layer = inputs.layer;
    let under = q.floor().as_ivec2();
    if inputs.source_normal_id.clamped(under.x, under.y)[3] != 0.0 {
        pixel.fill_hole(q)
    } else if inside_layer(layer, q) {
        layer_at(layer, q)
    } else {
        Vec4::ZERO
    }
}

/// `layer_splatted`: the layer's texels around `x`, moved by their own motion, splatted onto the
/// pixel centred at `centre`: their premultiplied sum, and the share of the pixel the covered
/// ones fill.
fn layer_splatted(
    inputs: &TargetTranslucency,
    motion: &Image,
    x: Vec2,
    centre: Vec2,
) -> (Vec4, f32) {
    let layer = inputs.layer;
    let extent = Vec2::new(layer.width as f32, layer.height as f32);
    let around = x.clamp(Vec2::splat(-1.0), extent + 1.0).floor().as_ivec2();
    let (mut sum, mut weight) = (Vec4::ZERO, 0.0);
    for i in 0..9 {
        let s = around + IVec2::new(i % 3 - 1, i / 3 - 1);
        if s.cmplt(IVec2::ZERO).any() || s.cmpge(extent.as_ivec2()).any() {
            continue;
        }
        let (sx, sy) = (s.x as usize, s.y as usize);
        let moved = s.as_vec2() + 0.5 - inputs.alpha * Vec2::from_slice(motion.at(sx, sy));
        let w = (Vec2::ONE - (moved - centre).abs()).max(Vec2::ZERO);
        let texel = Vec4::from_slice(layer.at(sx, sy));
        sum += (w.x * w.y) * texel;
        if texel.w > 0.0 {
            weight += w.x * w.y;
        }
    }
    (sum, weight)
}

/// `seen_around`: whether frame t saw the pixel's surface at one of the 3x3 texels around q.
fn seen_around(pixel: &TargetPixel, q: Vec2, extent: IVec2) -> bool {
    let centre = q.floor().as_ivec2().clamp(IVec2::ZERO, extent - 1);
    (0..9).any(|i| {
        let s = (centre + IVec2::new(i % 3 - 1, i / 3 - 1)).clamp(IVec2::ZERO, extent - 1);
        pixel.agreement_at(s) >= AGREEMENT_THRESHOLD
    })
}

/// Blends the layer, moved to the target instant, over `frame`; returns the pixels sanitised.
pub fn place(frame: &mut Image, inputs: &TargetTranslucency) -> u32 {
    let mut sanitized = 0;
    let sources = WarpSources {
        shading: inputs.layer,
        geometry: inputs.source_geometry,
        normal_id: inputs.source_normal_id,
    };
    let extent = IVec2::new(frame.width as i32, frame.height as i32);
    for y in 0..frame.height {
        for x in 0..frame.width {
            let warp = inputs.warp;
            let centre = Vec2::new(x as f32, y as f32) + 0.5 + Vec2::from(warp.jitter_delta);
            let mut point = centre
                + Vec2::from_slice(inputs.target.motion.at(x, y)) * Vec2::from(warp.motion_scale);
            let pixel = TargetPixel::new(
                warp,
                &sources,
                &inputs.target,
                IVec2::new(x as i32, y as i32),
            );
            let valid = inputs.target.valid[x + y * frame.width];
            let finite = point.abs().cmple(Vec2::splat(f32::MAX)).all();
            let id = inputs.target.normal_id.at(x, y)[3];
            let static_surface = valid && id == 0.0;
            let takes_layer = finite && (static_surface || object_takes_layer(inputs, point, id));
            let mut over = Vec4::ZERO;
            if let Some(motion) = inputs.motion.filter(|_| takes_layer) {
                let surface_point = point;
                for _ in 0..2 {
                    point = step_from(inputs, motion, point, centre);
                }
                let (sum, weight) = layer_splatted(inputs, motion, point, centre);
                over = sum;
                if weight < 1.0 && static_surface {
                    over += (1.0 - weight) * layer_with_surface(inputs, &pixel, surface_point);
                }
                over /= over.w.max(1.0);
            } else if finite
                && valid
                && !seen_around(&pixel, point.clamp(Vec2::ZERO, extent.as_vec2()), extent)
            {
                over = pixel.fill_hole(point);
            } else if takes_layer {
                over = layer_at(inputs.layer, point);
            }
            if over.w > 0.0 {
                let c = Vec4::from_slice(frame.at(x, y));
                let blended = (over.truncate() + (1.0 - over.w) * c.truncate()).max(Vec3::ZERO);
                let (value, changed) = sanitize_color(blended);
                let rounded = value.to_array().map(round_to_f16);
                frame.set(x, y, &[rounded[0], rounded[1], rounded[2], c.w]);
                sanitized += changed as u32;
            }
        }
    }
    sanitized
}
