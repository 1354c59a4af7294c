// Divides frame t's colour by its modulation factor, leaving shading that varies smoothly across
// textures and so warps and inpaints well: F' = F / (albedo + 0.08 * specular * (1 - metallic)).
// #import gbuffer

struct Params {
    extent: vec2u,
    has_material: u32,
}
var<immediate> params: Params;

@group(0) @binding(0) var color: texture_2d<f32>;
@group(0) @binding(1) var base_color: texture_2d<f32>;
@group(0) @binding(2) var material: texture_2d<f32>;
@group(0) @binding(3) var demodulated: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    let p = id.xy;
    if (any(p >= params.extent)) {
        return;
    }
    let ms = metallic_specular(material, p, params.has_material);
    let factor = modulation(textureLoad(base_color, p, 0).rgb, ms.x, ms.y);
    textureStore(demodulated, p, vec4f(textureLoad(color, p, 0).rgb / factor, 1.0));
}
