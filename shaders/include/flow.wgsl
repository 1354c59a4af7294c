// What the Farneback optical-flow passes share. Each quantity's pyramid lives in one atlas
// image: level 0 at the origin, every coarser level beside it (src/passes/shadow_flow.rs lays
// them out). A level is its offset and size in the atlas; reads never leave it.
// src/reference/optical_flow.rs mirrors this file.

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

// A setting read through an image's size, which the driver cannot know when it compiles:
// lavapipe then compiles the pass once rather than anew for each setting (the story is in
// include/warp.wgsl; tests/shader_settings.rs holds the flow's passes to it).
fn unspecialised(setting: u32, image: texture_2d<f32>) -> u32 {
    return select(0u, setting, textureDimensions(image).x != 0u);
}
