// Local binary pattern of the warped frame, an input of the inpainting networks: bit k is set
// when neighbour k (clockwise from the top-left) is at least as bright as the centre. Luminance
// of the demodulated shading, neighbours clamped at the image edge. The importing shader binds
// the frame as `warped` (rgba16float, read). src/reference/lbp.rs mirrors it.

const LUMINANCE: vec3f = vec3f(0.2126, 0.7152, 0.0722);
const NEIGHBOURS: array<vec2i, 8> = array<vec2i, 8>(
    vec2i(-1, -1), vec2i(0, -1), vec2i(1, -1), vec2i(1, 0),
    vec2i(1, 1), vec2i(0, 1), vec2i(-1, 1), vec2i(-1, 0));

fn warped_luminance(s: vec2i, extent: vec2u) -> f32 {
    return dot(textureLoad(warped, clamp(s, vec2i(0), vec2i(extent) - 1)).rgb, LUMINANCE);
}

// The code at pixel `p` of a frame of `extent`, 0 to 255.
fn lbp_code(p: vec2u, extent: vec2u) -> u32 {
    let centre = warped_luminance(vec2i(p), extent);
    var code = 0u;
    for (var k = 0u; k < 8u; k++) {
        if (warped_luminance(vec2i(p) + NEIGHBOURS[k], extent) >= centre) {
            code |= 1u << k;
        }
    }
    return code;
}
