// Forward pass: blended surfaces (glTF alphaMode BLEND: glass, thin cloth, decals), lit like
// the resolve pass lights the G-buffer, and composited by the host over the lit frame. Drawn
// back to front with premultiplied "over" blending into two targets: the translucent layer
// (radiance times coverage, and coverage) and its motion and depth weighted the same way: the
// mask and the motion an engine hands a frame generator beside the colour, and where particles
// beyond the surfaces are seen through them.

// #import frame
// #import material
// #import lighting

@group(0) @binding(0) var<uniform> frame: Frame;
@group(2) @binding(0) var static_shadow_map: texture_depth_2d;
@group(2) @binding(1) var dynamic_shadow_map: texture_depth_2d;

struct Translucency {
    // premultiplied radiance, coverage
    @location(0) color_coverage: vec4<f32>,
    // backward motion in pixels and linear view depth, times coverage; coverage
    @location(1) motion_coverage: vec4<f32>,
}

@fragment
fn fs_main(input: VertexOutput, @builtin(front_facing) front_facing: bool) -> Translucency {
    let surface = sample_surface(input, front_facing);
    let coverage = clamp(surface.base.a, 0.0, 1.0);
    let to_camera = normalize(frame.camera_position.xyz - input.world_position);
    let n_dot_v = clamp(dot(surface.normal, to_camera), 0.0, 1.0);
    let n_dot_l = clamp(dot(surface.normal, frame.sun_direction.xyz), 0.0, 1.0);
    let light_clip = shadow_coordinates(input.world_position, surface.normal);
    let visibility = sun_visibility(static_shadow_map, light_clip, frame.shadow_params.x)
        * sun_visibility(dynamic_shadow_map, light_clip, frame.shadow_params.x);
    let light = light_surface(surface.base.rgb, surface.metallic, material.specular, surface.roughness, surface.normal, to_camera, n_dot_v, n_dot_l);
    let radiance = light.ambient + light.sun * visibility + surface.emissive;

    var output: Translucency;
    output.color_coverage = vec4<f32>(radiance * coverage, coverage);
    let motion_depth = vec3<f32>(surface_motion(input), view_depth(input.world_position));
    output.motion_coverage = vec4<f32>(motion_depth * coverage, coverage);
    return output;
}
