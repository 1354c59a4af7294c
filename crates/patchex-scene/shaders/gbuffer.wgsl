// G-buffer pass: every mesh is drawn with world-space vertices (static ones baked once,
// skinned ones re-posed on the CPU each frame together with their previous-frame positions),
// so motion vectors come from the previous position without a second skeleton on the GPU.

// #import frame
// #import material

@group(0) @binding(0) var<uniform> frame: Frame;

struct GBuffer {
    // base colour, metallic
    @location(0) base_metallic: vec4<f32>,
    // world normal, roughness
    @location(1) normal_roughness: vec4<f32>,
    // world position, linear view depth
    @location(2) position_depth: vec4<f32>,
    // backward motion in pixels, stencil id, specular
    @location(3) motion_stencil_specular: vec4<f32>,
    // emissive radiance, coverage (1 = geometry, 0 = sky)
    @location(4) emissive_coverage: vec4<f32>,
}

@fragment
fn fs_main(input: VertexOutput, @builtin(front_facing) front_facing: bool) -> GBuffer {
    let surface = sample_surface(input, front_facing);
    if surface.base.a < material.alpha_cutoff {
        discard;
    }

    var output: GBuffer;
    output.base_metallic = vec4<f32>(surface.base.rgb, surface.metallic);
    output.normal_roughness = vec4<f32>(surface.normal, surface.roughness);
    output.position_depth = vec4<f32>(input.world_position, view_depth(input.world_position));
    output.motion_stencil_specular = vec4<f32>(surface_motion(input), material.stencil, material.specular);
    output.emissive_coverage = vec4<f32>(surface.emissive, 1.0);
    return output;
}
