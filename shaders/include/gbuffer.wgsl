// G-buffer conventions shared by every pass. src/reference/gbuffer.rs mirrors this file.

// Floor of the modulation factor. Demodulating divides by it, so a black or near-black surface
// would otherwise turn a little noise into a huge value; with the floor, demodulation followed by
// remodulation with the same G-buffer gives the input back exactly.
const MIN_MODULATION: f32 = 0.01;

// Linear depth stored for pixels that hit no geometry (sky, far plane, infinite far).
const SKY_DEPTH: f32 = 1e30;

// Values of `has_material` and `has_stencil`.
const ABSENT: u32 = 0u;

// Unreal's split of base colour into diffuse and specular colour, summed:
// BaseColor * (1 - Metallic) + lerp(0.08 * Specular, BaseColor, Metallic)
//   = BaseColor + 0.08 * Specular * (1 - Metallic).
fn modulation(base_color: vec3f, metallic: f32, specular: f32) -> vec3f {
    return max(base_color + vec3f(0.08 * specular * (1.0 - metallic)), vec3f(MIN_MODULATION));
}

// Metallic and specular of pixel `p` from the material image (R metallic, G specular, as in
// Unreal's GBufferB), or Unreal's defaults (0, 0.5) when the engine gave no material image.
fn metallic_specular(material: texture_2d<f32>, p: vec2u, has_material: u32) -> vec2f {
    if (has_material == ABSENT) {
        return vec2f(0.0, 0.5);
    }
    return textureLoad(material, p, 0).rg;
}

fn is_sky(linear_depth: f32) -> bool {
    return linear_depth >= 0.5 * SKY_DEPTH;
}
