// The frame's uniforms, read by the G-buffer and resolve passes. build.rs mirrors this struct
// on the host (`FrameUniforms`, src/render/uniforms.rs), so its layout is written once, here.
struct Frame {
    view_proj: mat4x4<f32>,
    prev_view_proj: mat4x4<f32>,
    view: mat4x4<f32>,
    inv_view_proj: mat4x4<f32>,
    light_view_proj: mat4x4<f32>,
    camera_position: vec4<f32>,
    sun_direction: vec4<f32>,
    sun_radiance: vec4<f32>,
    sky_zenith: vec4<f32>,
    sky_horizon: vec4<f32>,
    ground_ambient: vec4<f32>,
    // width, height, near, far
    viewport: vec4<f32>,
    // x: depth bias (light clip units), y: normal offset (metres), zw: padding
    shadow_params: vec4<f32>,
}
