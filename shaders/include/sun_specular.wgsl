// The sun's specular reflection, as PatchexSunLight's header says the engine shades it: a GGX
// distribution of alpha = roughness^2, height-correlated Smith visibility and Schlick's Fresnel
// (the glTF metallic-roughness model; Unreal's default lit); and the change in its Lambert
// reflection where a surface turned. Needs gbuffer.wgsl.
// src/reference/highlights.rs mirrors it.

const PI: f32 = 3.14159265;
// A smaller roughness makes a highlight a point no pixel can resolve, and its distribution's
// peak overflows.
const MIN_ROUGHNESS: f32 = 0.02;

// The sun, as the highlight passes take it in their parameters.
struct Sun {
    // Unit, towards the sun.
    direction: vec3f,
    illuminance: vec3f,
}

// A pixel's material as its reflection needs it.
struct Glossy {
    specular_color: vec3f,
    // Lambert's albedo, base colour times (1 - metallic).
    diffuse_color: vec3f,
    roughness: f32,
    // The roughness was sanitised. (The base colour, metallic and specular are the pixel's
    // modulation, which counts them.)
    roughness_changed: bool,
}

// Pixel `p`'s specular colour and roughness from its base colour and material (R metallic,
// G specular, B roughness), or metallic 0, specular 0.5, roughness 0.5 without a material
// image.
fn glossy_material(base_color: texture_2d<f32>, material: texture_2d<f32>, p: vec2u, has_material: u32) -> Glossy {
    let base = sanitize_unit(textureLoad(base_color, p, 0).rgb).value;
    var msr = Sanitized(vec3f(0.0, 0.5, 0.5), false);
    if (has_material != ABSENT) {
        msr = sanitize_unit(textureLoad(material, p, 0).rgb);
    }
    let roughness = sanitize_unit(vec3f(msr.value.z, 0.0, 0.0));
    return Glossy(mix(vec3f(0.08 * msr.value.y), base, msr.value.x), base * (1.0 - msr.value.x),
        max(roughness.value.x, MIN_ROUGHNESS), roughness.changed);
}

// The light the sun's specular reflection sends towards `view` (unit, from the surface to the
// camera) from a surface of unit `normal`, unshadowed.
fn sun_specular(sun: Sun, normal: vec3f, view: vec3f, glossy: Glossy) -> vec3f {
    let n_dot_l = dot(normal, sun.direction);
    let n_dot_v = max(clamp(dot(normal, view), 0.0, 1.0), 1e-4);
    if (n_dot_l <= 0.0) {
        return vec3f(0.0);
    }
    let half_vector = normalize(sun.direction + view);
    let n_dot_h = clamp(dot(normal, half_vector), 0.0, 1.0);
    let v_dot_h = clamp(dot(view, half_vector), 0.0, 1.0);
    let alpha = glossy.roughness * glossy.roughness;
    let alpha2 = alpha * alpha;
    let d_denominator = n_dot_h * n_dot_h * (alpha2 - 1.0) + 1.0;
    let distribution = alpha2 / (PI * d_denominator * d_denominator);
    let smith_v = n_dot_l * sqrt(n_dot_v * n_dot_v * (1.0 - alpha2) + alpha2);
    let smith_l = n_dot_v * sqrt(n_dot_l * n_dot_l * (1.0 - alpha2) + alpha2);
    let visibility = 0.5 / max(smith_v + smith_l, 1e-6);
    let fresnel_weight = pow(1.0 - v_dot_h, 5.0);
    let fresnel = glossy.specular_color * (1.0 - fresnel_weight) + vec3f(fresnel_weight);
    return sun.illuminance * distribution * visibility * fresnel * n_dot_l;
}

// How much more light the sun's diffuse (Lambert) reflection sends from a surface of unit
// `normal` than frame t's shading holds from it lit at `source_normal`, unshadowed: what a
// surface that turned towards or away from the sun gains or loses. Zero where the surface did
// not turn, or where frame t's normal is unknown (zero).
fn sun_diffuse_change(sun: Sun, source_normal: vec3f, normal: vec3f, glossy: Glossy) -> vec3f {
    if (all(source_normal == vec3f(0.0))) {
        return vec3f(0.0);
    }
    let turned = max(dot(normal, sun.direction), 0.0) - max(dot(source_normal, sun.direction), 0.0);
    return sun.illuminance * glossy.diffuse_color / PI * turned;
}
