// The sky's specular reflection, as PatchexSkyLight's header says the engine shades it: the
// sky's radiance in the mirror direction, from an octahedral map of the normals' world space,
// times the split-sum environment BRDF in Karis' analytic fit ("Physically Based Shading on
// Mobile", the fit Unreal's mobile renderer uses). Needs gbuffer.wgsl and sun_specular.wgsl.
// src/reference/highlights.rs mirrors it.

// A sky's map as a pass reads it: its side and mips, and whether they lie side by side in one
// image's mip 0 (the copy patchex keeps, `SkyMap` in src/passes/highlights.rs) or in the
// image's own mips (the engine's).
struct SkyMap {
    side: u32,
    levels: u32,
    side_by_side: bool,
}

// The side of mip `level`.
fn mip_side(sky: SkyMap, level: u32) -> u32 {
    return sky.side >> level;
}

// Where mip `level` starts when the mips lie side by side.
fn mip_offset(sky: SkyMap, level: u32) -> u32 {
    var offset = 0u;
    for (var m = 0u; m < level; m++) {
        offset += sky.side >> m;
    }
    return offset;
}

// Where unit `direction` falls in an octahedral map of `side` texels a side, in texels (texel
// centres at half-integers).
fn octahedral_texel(direction: vec3f, side: u32) -> vec2f {
    var p = direction.xy / (abs(direction.x) + abs(direction.y) + abs(direction.z));
    if (direction.z < 0.0) {
        p = (1.0 - abs(p.yx)) * select(vec2f(-1.0), vec2f(1.0), p >= vec2f(0.0));
    }
    return (p * 0.5 + 0.5) * f32(side);
}

// A texel of mip `level` by index, one texel beyond an edge allowed: the octahedral map folds
// onto itself there, so the texel across an edge is the one mirrored along it.
fn octahedral_load(map: texture_2d<f32>, sky: SkyMap, level: u32, texel: vec2i) -> vec3f {
    let last = i32(mip_side(sky, level)) - 1;
    var t = texel;
    if (t.x < 0 || t.x > last) {
        t = vec2i(clamp(t.x, 0, last), last - t.y);
    }
    if (t.y < 0 || t.y > last) {
        t = vec2i(last - t.x, clamp(t.y, 0, last));
    }
    var radiance: vec4f;
    if (sky.side_by_side) {
        radiance = textureLoad(map, t + vec2i(i32(mip_offset(sky, level)), 0), 0);
    } else {
        radiance = textureLoad(map, t, i32(level));
    }
    return sanitize_input_color(radiance.rgb).value;
}

// The sky's radiance towards unit `direction` in mip `level`, bilinear between its texels.
fn sky_radiance(map: texture_2d<f32>, sky: SkyMap, level: u32, direction: vec3f) -> vec3f {
    let q = octahedral_texel(direction, mip_side(sky, level)) - 0.5;
    let corner = vec2i(floor(q));
    let f = q - floor(q);
    let top = mix(octahedral_load(map, sky, level, corner),
        octahedral_load(map, sky, level, corner + vec2i(1, 0)), f.x);
    let bottom = mix(octahedral_load(map, sky, level, corner + vec2i(0, 1)),
        octahedral_load(map, sky, level, corner + vec2i(1, 1)), f.x);
    return mix(top, bottom, f.y);
}

// The split-sum environment BRDF's scale and bias on the specular colour, in Karis' fit.
fn environment_brdf(glossy: Glossy, n_dot_v: f32) -> vec3f {
    let c0 = vec4f(-1.0, -0.0275, -0.572, 0.022);
    let c1 = vec4f(1.0, 0.0425, 1.04, -0.04);
    let r = glossy.roughness * c0 + c1;
    let a004 = min(r.x * r.x, exp2(-9.28 * n_dot_v)) * r.x + r.y;
    let ab = vec2f(-1.04, 1.04) * a004 + r.zw;
    return glossy.specular_color * ab.x + ab.y;
}

// The light the sky's specular reflection sends towards `view` (unit, from the surface to the
// camera) from a surface of unit `normal`: the sky in the mirror direction, from the two mips
// around the surface's roughness (mip m holds roughness m / (levels - 1)).
fn sky_specular(map: texture_2d<f32>, sky: SkyMap, normal: vec3f, view: vec3f, glossy: Glossy) -> vec3f {
    let n_dot_v = clamp(dot(normal, view), 0.0, 1.0);
    let mirror = normalize(2.0 * dot(normal, view) * normal - view);
    let lod = glossy.roughness * f32(sky.levels - 1u);
    let below = min(u32(floor(lod)), sky.levels - 1u);
    let above = lod - floor(lod);
    // Each mip is read under the loop's level, the same in every lane: lavapipe reads a level
    // that differs between the lanes of a load from the wrong mip.
    var radiance = vec3f(0.0);
    for (var level = 0u; level < sky.levels; level++) {
        if (level == below) {
            radiance += (1.0 - above) * sky_radiance(map, sky, level, mirror);
        } else if (level == below + 1u) {
            radiance += above * sky_radiance(map, sky, level, mirror);
        }
    }
    return radiance * environment_brdf(glossy, n_dot_v);
}
