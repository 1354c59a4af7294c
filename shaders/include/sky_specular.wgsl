// The sky's specular reflection, as PatchexSkyLight's header says the engine shades it: the
// sky's radiance in the mirror direction, from an octahedral map of the normals' world space,
// times the split-sum environment BRDF in Karis' analytic fit ("Physically Based Shading on
// Mobile", the fit Unreal's mobile renderer uses). Needs gbuffer.wgsl and sun_specular.wgsl.
// src/reference/highlights.rs mirrors it.

// Where unit `direction` falls in an octahedral map of `side` texels a side, in texels (texel
// centres at half-integers).
fn octahedral_texel(direction: vec3f, side: u32) -> vec2f {
    var p = direction.xy / (abs(direction.x) + abs(direction.y) + abs(direction.z));
    if (direction.z < 0.0) {
        p = (1.0 - abs(p.yx)) * select(vec2f(-1.0), vec2f(1.0), p >= vec2f(0.0));
    }
    return (p * 0.5 + 0.5) * f32(side);
}

// A texel of the map by index, one texel beyond an edge allowed: the octahedral map folds
// onto itself there, so the texel across an edge is the one mirrored along it.
fn octahedral_load(map: texture_2d<f32>, texel: vec2i, side: u32) -> vec3f {
    let last = i32(side) - 1;
    var t = texel;
    if (t.x < 0 || t.x > last) {
        t = vec2i(clamp(t.x, 0, last), last - t.y);
    }
    if (t.y < 0 || t.y > last) {
        t = vec2i(last - t.x, clamp(t.y, 0, last));
    }
    return sanitize_input_color(textureLoad(map, t, 0).rgb).value;
}

// The sky's radiance towards unit `direction`, bilinear between the map's texels.
fn sky_radiance(map: texture_2d<f32>, side: u32, direction: vec3f) -> vec3f {
    let q = octahedral_texel(direction, side) - 0.5;
    let corner = vec2i(floor(q));
    let f = q - floor(q);
    let top = mix(octahedral_load(map, corner, side), octahedral_load(map, corner + vec2i(1, 0), side), f.x);
    let bottom = mix(octahedral_load(map, corner + vec2i(0, 1), side),
        octahedral_load(map, corner + vec2i(1, 1), side), f.x);
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
// camera) from a surface of unit `normal`.
fn sky_specular(map: texture_2d<f32>, side: u32, normal: vec3f, view: vec3f, glossy: Glossy) -> vec3f {
    let n_dot_v = clamp(dot(normal, view), 0.0, 1.0);
    let mirror = normalize(2.0 * dot(normal, view) * normal - view);
    return sky_radiance(map, side, mirror) * environment_brdf(glossy, n_dot_v);
}
