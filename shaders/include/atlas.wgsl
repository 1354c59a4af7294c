// Pyramid levels in atlas images, as the shadow flow keeps them: level 0 at the origin, every
// coarser level beside it (src/passes/shadow_flow.rs lays them out). A level is its offset and
// size in the atlas; reads never leave it. src/reference/optical_flow.rs mirrors this file.

// Texel `q` of a level, clamped to the level so that its borders replicate.
fn level_texel(offset: vec2u, size: vec2u, q: vec2i) -> vec2i {
    return vec2i(offset) + clamp(q, vec2i(0), vec2i(size) - 1);
}

// Bilinear sample of a level at `pos`, in texels with texel centres at integers. Positions far
// outside are brought back first, so no float-to-integer conversion overflows.
fn level_bilinear(atlas: texture_2d<f32>, offset: vec2u, size: vec2u, pos: vec2f) -> vec4f {
    let inside = clamp(pos, vec2f(-1.0), vec2f(size));
    let base = floor(inside);
    let f = inside - base;
    let b = vec2i(base);
    let t00 = textureLoad(atlas, level_texel(offset, size, b), 0);
    let t10 = textureLoad(atlas, level_texel(offset, size, b + vec2i(1, 0)), 0);
    let t01 = textureLoad(atlas, level_texel(offset, size, b + vec2i(0, 1)), 0);
    let t11 = textureLoad(atlas, level_texel(offset, size, b + vec2i(1, 1)), 0);
    let top = t00 * (1.0 - f.x) + t10 * f.x;
    let bottom = t01 * (1.0 - f.x) + t11 * f.x;
    return top * (1.0 - f.y) + bottom * f.y;
}

// The flow of the pyramid's finest level at pixel p of a frame of `extent`: bilinear in
// position, multiplied by the size ratio in length. Rounded to half floats, as engines' motion
// vectors come: the shadow layer's warp follows it at the precision the shadow sub-task was
// tuned with.
fn frame_flow(atlas: texture_2d<f32>, offset: vec2u, size: vec2u, extent: vec2u, p: vec2u) -> vec2f {
    let ratio = vec2f(extent) / vec2f(size);
    let pos = (vec2f(p) + 0.5) / ratio - 0.5;
    let d = level_bilinear(atlas, offset, size, pos).xy * ratio;
    return quantizeToF16(d);
}
