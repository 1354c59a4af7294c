//! Mirror of `shaders/include/sun_specular.wgsl`, `shaders/include/sky_specular.wgsl`,
//! `shaders/remove_highlights.wgsl` and `shaders/place_highlights.wgsl`.

use glam::{IVec2, Vec2, Vec3, Vec4};

use super::gbuffer::{
    is_sky, pixel_modulation, round_vec3_to_f16, sanitize, sanitize_color, sanitize_input_color,
};
use super::separate_shadows::share_lost_to_shadows;
use super::warp::{TargetPixel, WarpSources, WarpTarget, AGREEMENT_THRESHOLD, BILINEAR_ACCEPT};
use super::{round_to_f16, Image};
use crate::camera::PixelRays;
use crate::passes::highlights::{SkyMap, Sun, NO_SUN};

const MIN_ROUGHNESS: f32 = 0.02;

/// `Glossy`: the specular and diffuse colours, the roughness, and whether the roughness was
/// sanitised.
struct Glossy {
    specular_color: Vec3,
    diffuse_color: Vec3,
    roughness: f32,
    roughness_changed: bool,
}

fn glossy_material(base_color: &Image, material: Option<&Image>, x: usize, y: usize) -> Glossy {
    let (base, _) = sanitize(Vec3::from_slice(base_color.at(x, y)), 0.0, 1.0);
    let msr = match material {
        Some(material) => sanitize(Vec3::from_slice(&material.at(x, y)[..3]), 0.0, 1.0).0,
        None => Vec3::new(0.0, 0.5, 0.5),
    };
    let (roughness, roughness_changed) = sanitize(Vec3::new(msr.z, 0.0, 0.0), 0.0, 1.0);
    Glossy {
        specular_color: Vec3::splat(0.08 * msr.y).lerp(base, msr.x),
        diffuse_color: base * (1.0 - msr.x),
        roughness: roughness.x.max(MIN_ROUGHNESS),
        roughness_changed,
    }
}

/// `sun_specular`: the light the sun's reflection sends towards `view`, unshadowed.
fn sun_specular(sun: &Sun, normal: Vec3, view: Vec3, glossy: &Glossy) -> Vec3 {
    let n_dot_l = normal.dot(sun.direction);
    let n_dot_v = normal.dot(view).clamp(0.0, 1.0).max(1e-4);
    if n_dot_l <= 0.0 {
        return Vec3::ZERO;
    }
    let half_vector = (sun.direction + view).normalize();
    let n_dot_h = normal.dot(half_vector).clamp(0.0, 1.0);
    let v_dot_h = view.dot(half_vector).clamp(0.0, 1.0);
    let alpha = glossy.roughness * glossy.roughness;
    let alpha2 = alpha * alpha;
    let d_denominator = n_dot_h * n_dot_h * (alpha2 - 1.0) + 1.0;
    let distribution = alpha2 / (std::f32::consts::PI * d_denominator * d_denominator);
    let smith_v = n_dot_l * (n_dot_v * n_dot_v * (1.0 - alpha2) + alpha2).sqrt();
    let smith_l = n_dot_v * (n_dot_l * n_dot_l * (1.0 - alpha2) + alpha2).sqrt();
    let visibility = 0.5 / (smith_v + smith_l).max(1e-6);
    let fresnel_weight = (1.0 - v_dot_h).powf(5.0);
    let fresnel = glossy.specular_color * (1.0 - fresnel_weight) + Vec3::splat(fresnel_weight);
    sun.illuminance * distribution * visibility * fresnel * n_dot_l
}

/// `sun_diffuse_change`: how much more light the sun's Lambert reflection sends from `normal`
/// than frame t's shading holds from `source_normal` (zero: unknown), unshadowed.
fn sun_diffuse_change(sun: &Sun, source_normal: Vec3, normal: Vec3, glossy: &Glossy) -> Vec3 {
    if source_normal == Vec3::ZERO {
        return Vec3::ZERO;
    }
    let turned = normal.dot(sun.direction).max(0.0) - source_normal.dot(sun.direction).max(0.0);
    sun.illuminance * glossy.diffuse_color / std::f32::consts::PI * turned
}

/// A sky's mips as a pass reads them (`SkyMap` in the shaders): the engine's, one image each,
/// or patchex's copy, side by side in one image.
#[derive(Clone, Copy)]
pub enum SkyMips<'a> {
    Separate(&'a [Image]),
    SideBySide { image: &'a Image, map: SkyMap },
}

impl<'a> SkyMips<'a> {
    fn levels(self) -> usize {
        match self {
            SkyMips::Separate(mips) => mips.len(),
            SkyMips::SideBySide { map, .. } => map.levels as usize,
        }
    }

    fn side(self, level: usize) -> usize {
        match self {
            SkyMips::Separate(mips) => mips[level].width,
            SkyMips::SideBySide { map, .. } => (map.side >> level) as usize,
        }
    }

    fn texel(self, level: usize, x: usize, y: usize) -> &'a [f32] {
        match self {
            SkyMips::Separate(mips) => mips[level].at(x, y),
            SkyMips::SideBySide { image, map } => {
                image.at(map.offset(level as u32) as usize + x, y)
            }
        }
    }
}

/// `octahedral_texel`: where unit `direction` falls in an octahedral map of `side` texels.
fn octahedral_texel(direction: Vec3, side: usize) -> Vec2 {
    let mut p = direction.truncate() / (direction.x.abs() + direction.y.abs() + direction.z.abs());
    if direction.z < 0.0 {
        let sign = Vec2::new(
            if p.x >= 0.0 { 1.0 } else { -1.0 },
            if p.y >= 0.0 { 1.0 } else { -1.0 },
        );
        p = (Vec2::ONE - Vec2::new(p.y.abs(), p.x.abs())) * sign;
    }
    (p * 0.5 + 0.5) * side as f32
}

/// `octahedral_load`: a texel of mip `level`, the one mirrored along the edge across it.
fn octahedral_load(sky: SkyMips, level: usize, x: i32, y: i32) -> Vec3 {
    let last = sky.side(level) as i32 - 1;
    let (mut x, mut y) = (x, y);
    if x < 0 || x > last {
        (x, y) = (x.clamp(0, last), last - y);
    }
    if y < 0 || y > last {
        (x, y) = (last - x, y.clamp(0, last));
    }
    sanitize_input_color(Vec3::from_slice(
        &sky.texel(level, x as usize, y as usize)[..3],
    ))
    .0
}

/// `sky_radiance`: the sky towards unit `direction` in mip `level`, bilinear.
fn sky_radiance(sky: SkyMips, level: usize, direction: Vec3) -> Vec3 {
    let q = octahedral_texel(direction, sky.side(level)) - 0.5;
    let corner = q.floor();
    let f = q - corner;
    let (x, y) = (corner.x as i32, corner.y as i32);
    let load = |dx, dy| octahedral_load(sky, level, x + dx, y + dy);
    let top = load(0, 0).lerp(load(1, 0), f.x);
    let bottom = load(0, 1).lerp(load(1, 1), f.x);
    top.lerp(bottom, f.y)
}

/// `environment_brdf`: the split-sum scale and bias on the specular colour (Karis' fit).
fn environment_brdf(glossy: &Glossy, n_dot_v: f32) -> Vec3 {
    let c0 = Vec4::new(-1.0, -0.0275, -0.572, 0.022);
    let c1 = Vec4::new(1.0, 0.0425, 1.04, -0.04);
    let r = glossy.roughness * c0 + c1;
    let a004 = (r.x * r.x).min((-9.28 * n_dot_v).exp2()) * r.x + r.y;
    let ab = Vec2::new(-1.04, 1.04) * a004 + Vec2::new(r.z, r.w);
    glossy.specular_color * ab.x + Vec3::splat(ab.y)
}

/// `sky_specular`: the light the sky's reflection sends towards `view`, from the two mips
/// around the roughness.
fn sky_specular(sky: SkyMips, normal: Vec3, view: Vec3, glossy: &Glossy) -> Vec3 {
    let n_dot_v = normal.dot(view).clamp(0.0, 1.0);
    let mirror = (2.0 * normal.dot(view) * normal - view).normalize();
    let levels = sky.levels();
    let lod = glossy.roughness * (levels - 1) as f32;
    let below = (lod.floor() as usize).min(levels - 1);
    let above = lod - lod.floor();
    // The shader reads each mip under a loop level (which lavapipe needs); the sum is the same.
    let mut radiance = (1.0 - above) * sky_radiance(sky, below, mirror);
    if below + 1 < levels {
        radiance += above * sky_radiance(sky, below + 1, mirror);
    }
    radiance * environment_brdf(glossy, n_dot_v)
}

/// The sky's mips side by side as the removal keeps them, sanitised and rounded to f16, and
/// the texels sanitised.
fn keep_sky(mips: &[Image]) -> (Image, u32) {
    let side = mips[0].width;
    let width = mips.iter().map(|mip| mip.width).sum();
    let mut kept = Image::new(width, side, 4);
    let mut sanitized = 0;
    let mut offset = 0;
    for mip in mips {
        for y in 0..mip.height {
            for x in 0..mip.width {
                let (radiance, changed) =
                    sanitize_input_color(Vec3::from_slice(&mip.at(x, y)[..3]));
                sanitized += changed as u32;
                kept.set(
                    offset + x,
                    y,
                    &round_vec3_to_f16(radiance).extend(1.0).to_array(),
                );
            }
        }
        offset += mip.width;
    }
    (kept, sanitized)
}

/// What frame t's highlights are taken out with, as `SourceHighlights` binds it.
pub struct SourceHighlights<'a> {
    /// The sun and its visibility; without one (a sky alone), no pixel is lit by a sun.
    pub sun: Option<(Sun, &'a Image)>,
    /// `PatchexSkyLight.radiance`, one image a mip.
    pub sky: Option<&'a [Image]>,
    /// With a shadow input, how its shadows are in the shading.
    pub shadows: Option<ShadowsInShading<'a>>,
    pub base_color: &'a Image,
    pub material: Option<&'a Image>,
    /// Frame t's camera.
    pub rays: PixelRays,
    /// Frame t's packed G-buffer (`Packed::geometry` and `normal_id`).
    pub geometry: &'a Image,
    pub normal_id: &'a Image,
}

/// Frame t's shadow input as the removal reads it (`ShadowsInShading`).
pub struct ShadowsInShading<'a> {
    pub mask: &'a Image,
    /// Separated: the input's colours (lit, without dynamic shadows) and the separation's layer.
    pub separated: Option<(&'a Image, &'a Image, &'a Image)>,
}

/// What `remove` gives back.
pub struct Removed {
    /// Frame t's shading less its highlights.
    pub shading: Image,
    /// Its visibility of the sun, one channel, rounded to f16 as kept.
    pub visibility: Image,
    /// With the shadows separated: the layer made again without the highlight.
    pub shadow_layer: Option<Image>,
    /// With a sky: its mips side by side, as kept for the target.
    pub kept_sky: Option<Image>,
    pub sanitized: u32,
}

pub fn remove(shading: &Image, inputs: &SourceHighlights) -> Removed {
    let (width, height) = (shading.width, shading.height);
    let unit = |image: &Image, x, y| sanitize(Vec3::new(image.at(x, y)[0], 0.0, 0.0), 0.0, 1.0);
    let separated = inputs.shadows.as_ref().and_then(|s| s.separated);
    // The visibility the shading holds, and whether the engine's needed sanitising.
    // Static pixels of separated shadows hold the colour without them.
    let separated_at = |x, y| separated.is_some() && inputs.normal_id.at(x, y)[3] == 0.0;
    let lit_at = |x, y| {
        let Some((_, visibility)) = inputs.sun else {
            return (0.0, false);
        };
        let (seen, changed) = unit(visibility, x, y);
        let dynamic = match &inputs.shadows {
            Some(shadows) if !separated_at(x, y) => unit(shadows.mask, x, y).0.x,
            _ => 1.0,
        };
        (seen.x * dynamic, changed)
    };
    let has_highlight = |x, y, lit: f32| {
        let normal = Vec3::from_slice(&inputs.normal_id.at(x, y)[..3]);
        (lit > 0.0 || inputs.sky.is_some())
            && !is_sky(inputs.geometry.at(x, y)[3])
            && normal != Vec3::ZERO
    };
    let sun = inputs.sun.map_or(NO_SUN, |(sun, _)| sun);
    let (kept_sky, mut sanitized) = match inputs.sky {
        Some(map) => {
            let (kept, sanitized) = keep_sky(map);
            (Some(kept), sanitized)
        }
        None => (None, 0),
    };
    let visibility = Image::from_fn(width, height, 1, |x, y| vec![round_to_f16(lit_at(x, y).0)]);
    let mut shadow_layer = separated.map(|(_, _, layer)| layer.clone());
    let output = Image::from_fn(width, height, 4, |x, y| {
        let s = Vec4::from_slice(shading.at(x, y));
        let (lit, changed) = lit_at(x, y);
        if !has_highlight(x, y, lit) {
            sanitized += changed as u32;
            return s.to_array().to_vec();
        }
        let glossy = glossy_material(inputs.base_color, inputs.material, x, y);
        sanitized += (changed || glossy.roughness_changed) as u32;
        let normal = Vec3::from_slice(&inputs.normal_id.at(x, y)[..3]);
        let rays = &inputs.rays;
        let ray = rays.at_origin + x as f32 * rays.per_x + y as f32 * rays.per_y;
        let view = -ray.normalize();
        let highlight = if lit > 0.0 {
            lit * sun_specular(&sun, normal, view, &glossy)
        } else {
            Vec3::ZERO
        };
        let reflection = inputs.sky.map_or(Vec3::ZERO, |mips| {
            sky_specular(SkyMips::Separate(mips), normal, view, &glossy)
        });
        let (factor, _) = pixel_modulation(inputs.base_color, inputs.material, x, y);
        let scale = (s.w / factor.max_element()).max(1.0);
        let rgb = round_vec3_to_f16(s.truncate() - (highlight + reflection) / (factor * scale));
        if let (Some((color, unshadowed, _)), Some(layer), true) =
            (separated, shadow_layer.as_mut(), separated_at(x, y))
        {
            let mask = unit(inputs.shadows.as_ref().expect("separated").mask, x, y)
                .0
                .x;
            let lit_color = sanitize_input_color(Vec3::from_slice(&color.at(x, y)[..3])).0;
            let unshadowed = sanitize_input_color(Vec3::from_slice(&unshadowed.at(x, y)[..3])).0;
            let share = share_lost_to_shadows(
                (lit_color - mask * highlight - reflection).max(Vec3::ZERO),
                (unshadowed - highlight - reflection).max(Vec3::ZERO),
            );
            let alpha = layer.at(x, y)[3];
            layer.set(x, y, &round_vec3_to_f16(share).extend(alpha).to_array());
        }
        rgb.extend(s.w).to_array().to_vec()
    });
    Removed {
        shading: output,
        visibility,
        shadow_layer,
        kept_sky,
        sanitized,
    }
}

/// What the target's highlights are placed with, as `TargetHighlights` binds it.
pub struct TargetHighlights<'a> {
    /// Frame t's sun, or `NO_SUN`.
    pub sun: Sun,
    /// Frame t's visibility, as `remove` kept it.
    pub kept_visibility: &'a Image,
    /// Frame t's sky mips, as `remove` kept them side by side, and how many.
    pub kept_sky: Option<(&'a Image, usize)>,
    /// Frame t's packed G-buffer (`Packed::geometry` and `normal_id`).
    pub source_geometry: &'a Image,
    pub source_normal_id: &'a Image,
    /// The target's packed G-buffer: positions with linear depth, normals as the engine stored
    /// them (unit) with object ids, and which pixels are usable.
    pub geometry: &'a Image,
    pub normal_id: &'a Image,
    pub valid: &'a [bool],
    pub base_color: &'a Image,
    pub material: Option<&'a Image>,
    pub motion: &'a Image,
    /// The call's warp (`WarpSettings::params`): motion scale, jitter and agreement test.
    pub warp: &'a crate::passes::warp::Params,
    /// With a shadow input: the dynamic shadows' share at the target.
    pub shadow_share: Option<&'a Image>,
    /// With a target shadow input placing the shadows: its mask.
    pub target_mask: Option<&'a Image>,
    /// The target's camera.
    pub rays: PixelRays,
}

/// `seen_from_source`: frame t's visibility and normal where it saw the surface of target pixel
/// `pixel` around `q`; where no texel around q shows it, both as the fill spreads them
/// (from `spread_visibility`).
fn seen_from_source(
    kept: &Image,
    source_normal_id: &Image,
    pixel: &TargetPixel,
    q: Vec2,
) -> (f32, Vec3) {
    let agrees = |x: i32, y: i32| pixel.agreement_at(IVec2::new(x, y)) >= AGREEMENT_THRESHOLD;
    let normal_at = |x: i32, y: i32| Vec3::from_slice(&source_normal_id.clamped(x, y)[..3]);
    let corner = (q - 0.5).floor();
    let f = q - 0.5 - corner;
    let (cx, cy) = (corner.x as i32, corner.y as i32);
    let (mut weight, mut agreeing, mut normal) = (0.0, 0.0, Vec3::ZERO);
    for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
        let w = if dx == 1 { f.x } else { 1.0 - f.x } * if dy == 1 { f.y } else { 1.0 - f.y };
        if agrees(cx + dx, cy + dy) {
            weight += w;
            agreeing += w * kept.clamped(cx + dx, cy + dy)[0];
            normal += w * normal_at(cx + dx, cy + dy);
        }
    }
    if weight >= BILINEAR_ACCEPT {
        return (agreeing / weight, normal.normalize_or_zero());
    }
    let (centre_x, centre_y) = (q.x.floor() as i32, q.y.floor() as i32);
    let last = (kept.width as i32 - 1, kept.height as i32 - 1);
    let (centre_x, centre_y) = (centre_x.clamp(0, last.0), centre_y.clamp(0, last.1));
    let (mut count, mut sum, mut normal) = (0.0, 0.0, Vec3::ZERO);
    for i in 0..9 {
        let (x, y) = (centre_x + i % 3 - 1, centre_y + i / 3 - 1);
        if agrees(x, y) {
            count += 1.0;
            sum += kept.clamped(x, y)[0];
            normal += normal_at(x, y);
        }
    }
    if count > 0.0 {
        return (sum / count, normal.normalize_or_zero());
    }
    let filled = pixel.fill_hole(q);
    (
        filled.x,
        Vec3::new(filled.y, filled.z, filled.w).normalize_or_zero(),
    )
}

/// The colour with the target's highlights added, and the pixels sanitised.
pub fn place(color: &Image, inputs: &TargetHighlights) -> (Image, u32) {
    let mut sanitized = 0;
    // Frame t's visibility and normals, as the fill reads shading.
    let kept = inputs.kept_visibility;
    let spread_visibility = Image::from_fn(kept.width, kept.height, 4, |x, y| {
        let normal = &inputs.source_normal_id.at(x, y)[..3];
        vec![kept.at(x, y)[0], normal[0], normal[1], normal[2]]
    });
    let sources = WarpSources {
        shading: &spread_visibility,
        geometry: inputs.source_geometry,
        normal_id: inputs.source_normal_id,
    };
    let target = WarpTarget {
        geometry: inputs.geometry,
        normal_id: inputs.normal_id,
        motion: inputs.motion,
        camera_position: inputs.rays.position,
        valid: inputs.valid,
    };
    let output = Image::from_fn(color.width, color.height, 4, |x, y| {
        let c = Vec4::from_slice(color.at(x, y));
        let motion = Vec2::from_slice(&inputs.motion.at(x, y)[..2]);
        let q = Vec2::new(x as f32, y as f32)
            + 0.5
            + motion * Vec2::from(inputs.warp.motion_scale)
            + Vec2::from(inputs.warp.jitter_delta);
        let normal_id = inputs.normal_id.at(x, y);
        let normal = Vec3::from_slice(&normal_id[..3]);
        let geometry = inputs.geometry.at(x, y);
        let usable = inputs.valid[x + y * color.width]
            && !is_sky(geometry[3])
            && normal != Vec3::ZERO
            && !q.is_nan();
        if !usable {
            return c.to_array().to_vec();
        }
        let rays = &inputs.rays;
        let ray = rays.at_origin + x as f32 * rays.per_x + y as f32 * rays.per_y;
        let pixel = TargetPixel::new(
            inputs.warp,
            &sources,
            &target,
            IVec2::new(x as i32, y as i32),
        );
        let (lit, source_normal) = seen_from_source(kept, inputs.source_normal_id, &pixel, q);
        let glossy = glossy_material(inputs.base_color, inputs.material, x, y);
        let view = -ray.normalize();
        let mut sun_light = sun_specular(&inputs.sun, normal, view, &glossy);
        if normal_id[3] != 0.0 {
            sun_light += sun_diffuse_change(&inputs.sun, source_normal, normal, &glossy);
        }
        let mut highlight = lit * sun_light;
        match (inputs.target_mask, inputs.shadow_share) {
            (Some(mask), _) if normal_id[3] == 0.0 => {
                highlight *= sanitize(Vec3::new(mask.at(x, y)[0], 0.0, 0.0), 0.0, 1.0)
                    .0
                    .x;
            }
            (_, Some(share)) => highlight *= Vec3::ONE + Vec3::from_slice(&share.at(x, y)[..3]),
            _ => {}
        }
        if let Some((image, levels)) = inputs.kept_sky {
            let map = SkyMap {
                side: image.height as u32,
                levels: levels as u32,
            };
            let sky = SkyMips::SideBySide { image, map };
            highlight += sky_specular(sky, normal, view, &glossy);
        }
        let (sum, changed) = sanitize_color(c.truncate() + highlight);
        sanitized += (glossy.roughness_changed || changed) as u32;
        round_vec3_to_f16(sum).extend(1.0).to_array().to_vec()
    });
    (output, sanitized)
}
