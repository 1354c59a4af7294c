// Multiplies the extrapolated shading by the target instant's own modulation factor and writes the
// engine's output image: texture detail comes from the target's G-buffer, not from the warp.
// #import gbuffer

struct Params {
    extent: vec2u,
    has_material: u32,
}
var<immediate> params: Params;

@group(0) @binding(0) var shading: texture_2d<f32>;
@group(0) @binding(1) var base_color: texture_2d<f32>;
@group(0) @binding(2) var material: texture_2d<f32>;
@group(0) @binding(3) var output: texture_storage_2d<rgba16float, write>;

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    let p = id.xy;
    if (any(p >= params.extent)) {
        return;
    }
    let ms = metallic_specular(material, p, params.has_material);
    let factor = modulation(textureLoad(base_color, p, 0).rgb, ms.x, ms.y);
    textureStore(output, p, vec4f(textureLoad(shading, p, 0).rgb * factor, 1.0));
}
