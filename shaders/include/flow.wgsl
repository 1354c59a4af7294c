// What the Farneback optical-flow passes share besides their atlases (atlas.wgsl).

// A setting read through an image's size, which the driver cannot know when it compiles:
// lavapipe then compiles the pass once rather than anew for each setting (the story is in
// include/warp.wgsl; tests/shader_settings.rs holds the flow's passes to it).
fn unspecialised(setting: u32, image: texture_2d<f32>) -> u32 {
    return select(0u, setting, textureDimensions(image).x != 0u);
}
