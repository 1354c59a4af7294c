// Local binary pattern of the warped frame, an input of the inpainting networks: bit k is set
// when neighbour k (clockwise from the top-left) is at least as bright as the centre. Written as
// code / 255 in R16F, which the networks' input holds anyway. Luminance of the demodulated
// shading, neighbours clamped at the image edge.

struct Params {
    extent: vec2u,
}
var<immediate> params: Params;

@group(0) @binding(0) var warped: texture_storage_2d<rgba16float, read>;
@group(0) @binding(1) var lbp: texture_storage_2d<r16float, write>;

const LUMINANCE: vec3f = vec3f(0.2126, 0.7152, 0.0722);
const NEIGHBOURS: array<vec2i, 8> = array<vec2i, 8>(
    vec2i(-1, -1), vec2i(0, -1), vec2i(1, -1), vec2i(1, 0),
    vec2i(1, 1), vec2i(0, 1), vec2i(-1, 1), vec2i(-1, 0));

fn luminance(s: vec2i) -> f32 {
    return dot(textureLoad(warped, clamp(s, vec2i(0), vec2i(params.extent) - 1)).rgb, LUMINANCE);
}

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    let p = id.xy;
    if (any(p >= params.extent)) {
        return;
    }
    let centre = luminance(vec2i(p));
    var code = 0u;
    for (var k = 0u; k < 8u; k++) {
        if (luminance(vec2i(p) + NEIGHBOURS[k]) >= centre) {
            code |= 1u << k;
        }
    }
    textureStore(lbp, p, vec4f(f32(code) / 255.0, 0.0, 0.0, 0.0));
}
