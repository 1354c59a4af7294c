// How far frame t's texel `s` is from showing a surface of linear depth `depth` and unit normal
// `normal`, seen from `offset` pixels away in a window of `radius`: -log of a weight, as the
// hole fill (fill.wgsl) and the translucency's estimate of the surface behind
// (separate_translucency.wgsl) weigh texels. `packed` is the texel's normal and id. The pass
// binds `source_depth` (frame t's packed depth). Needs gbuffer.wgsl. src/reference/warp.rs
// (`surface_cost`) mirrors it.

// The widths of the terms (chosen on the validation scenes for the fill): relative depth
// difference and normal difference (length of the vectors' difference). A non-finite depth on
// either side counts as relative difference 1.
const MATCH_SIGMA_DEPTH: f32 = 0.03;
const MATCH_SIGMA_NORMAL: f32 = 0.15;

fn surface_cost(depth: f32, normal: vec3f, s: vec2i, packed: u32, offset: vec2i, radius: i32) -> f32 {
    let source_w = textureLoad(source_depth, s, 0).r;
    let relative = abs(source_w - depth) / max(max(source_w, depth), 1e-30);
    let depth_term = select(1.0, relative, relative <= 1.0) / MATCH_SIGMA_DEPTH;
    let normal_delta = unpack_normal(packed) - normal;
    let normal_term = dot(normal_delta, normal_delta) / (MATCH_SIGMA_NORMAL * MATCH_SIGMA_NORMAL);
    let distance_term = f32(dot(offset, offset)) / f32(radius * radius);
    return depth_term * depth_term + normal_term + distance_term;
}
