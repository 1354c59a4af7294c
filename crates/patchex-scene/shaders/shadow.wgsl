// Sun shadow map: depth only, orthographic light projection. Static and dynamic casters go to
// separate maps so the resolve pass can tell dynamic-object shadows apart.

struct Light {
    light_view_proj: mat4x4<f32>,
}

var<immediate> light: Light;

@vertex
fn vs_main(@location(0) position: vec3<f32>) -> @builtin(position) vec4<f32> {
    return light.light_view_proj * vec4<f32>(position, 1.0);
}
