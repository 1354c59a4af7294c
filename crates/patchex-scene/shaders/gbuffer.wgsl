// G-buffer pass: every mesh is drawn with world-space vertices (static ones baked once,
// skinned ones re-posed on the CPU each frame together with their previous-frame positions),
// so motion vectors come from the previous position without a second skeleton on the GPU.

// #import frame

struct Material {
    base_color: vec4<f32>,
    // rgb: emissive factor times strength
    emissive: vec4<f32>,
    metallic: f32,
    roughness: f32,
    normal_scale: f32,
    alpha_cutoff: f32,
    specular: f32,
    stencil: f32,
}

@group(0) @binding(0) var<uniform> frame: Frame;
@group(1) @binding(0) var base_color_texture: texture_2d<f32>;
@group(1) @binding(1) var metallic_roughness_texture: texture_2d<f32>;
@group(1) @binding(2) var normal_texture: texture_2d<f32>;
@group(1) @binding(3) var emissive_texture: texture_2d<f32>;
@group(1) @binding(4) var material_sampler: sampler;
var<immediate> material: Material;

struct VertexInput {
    @location(0) position: vec3<f32>,
    @location(1) prev_position: vec3<f32>,
    @location(2) normal: vec3<f32>,
    // w = 0 marks a vertex without a tangent: the fragment shader derives one from derivatives
    @location(3) tangent: vec4<f32>,
    @location(4) uv: vec2<f32>,
    @location(5) color: vec4<f32>,
}

struct VertexOutput {
    @builtin(position) clip: vec4<f32>,
    @location(0) world_position: vec3<f32>,
    @location(1) prev_clip: vec4<f32>,
    @location(2) normal: vec3<f32>,
    @location(3) tangent: vec4<f32>,
    @location(4) uv: vec2<f32>,
    @location(5) color: vec4<f32>,
}

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

@vertex
fn vs_main(input: VertexInput) -> VertexOutput {
    var output: VertexOutput;
    output.clip = frame.view_proj * vec4<f32>(input.position, 1.0);
    output.world_position = input.position;
    output.prev_clip = frame.prev_view_proj * vec4<f32>(input.prev_position, 1.0);
    output.normal = input.normal;
    output.tangent = input.tangent;
    output.uv = input.uv;
    output.color = input.color;
    return output;
}

// Screen-space derivatives of the surface, taken before any branch so every quad lane
// computes them (derivatives in divergent control flow are undefined on real GPUs).
struct SurfaceDerivatives {
    dp_dx: vec3<f32>,
    dp_dy: vec3<f32>,
    duv_dx: vec2<f32>,
    duv_dy: vec2<f32>,
}

fn shading_normal(input: VertexOutput, front_facing: bool, sampled_normal: vec3<f32>, d: SurfaceDerivatives) -> vec3<f32> {
    var geometric = normalize(input.normal);
    if !front_facing {
        geometric = -geometric;
    }
    var tangent = input.tangent.xyz;
    var handedness = input.tangent.w;
    if handedness == 0.0 {
        // Tangent frame from screen-space derivatives (Mikkelsen, "Bump Mapping Unparametrized Surfaces").
        tangent = d.dp_dx * d.duv_dy.y - d.dp_dy * d.duv_dx.y;
        handedness = select(1.0, -1.0, d.duv_dx.x * d.duv_dy.y - d.duv_dy.x * d.duv_dx.y < 0.0);
    }
    let orthogonal = tangent - geometric * dot(geometric, tangent);
    if dot(orthogonal, orthogonal) < 1e-12 {
        return geometric;
    }
    let t = normalize(orthogonal);
    let b = cross(geometric, t) * handedness;
    let scaled = vec3<f32>(sampled_normal.xy * material.normal_scale, sampled_normal.z);
    let mapped = t * scaled.x + b * scaled.y + geometric * scaled.z;
    if dot(mapped, mapped) < 1e-12 {
        return geometric;
    }
    return normalize(mapped);
}

@fragment
fn fs_main(input: VertexOutput, @builtin(front_facing) front_facing: bool) -> GBuffer {
    // Every implicit-derivative sample and derivative comes first, in uniform control flow.
    let base_sample = textureSample(base_color_texture, material_sampler, input.uv);
    // glTF packs roughness in green and metalness in blue.
    let metal_rough = textureSample(metallic_roughness_texture, material_sampler, input.uv);
    let emissive_sample = textureSample(emissive_texture, material_sampler, input.uv).rgb;
    let normal_sample = textureSample(normal_texture, material_sampler, input.uv).xyz * 2.0 - 1.0;
    let derivatives = SurfaceDerivatives(
        dpdx(input.world_position),
        dpdy(input.world_position),
        dpdx(input.uv),
        dpdy(input.uv),
    );

    let base = material.base_color * input.color * base_sample;
    if base.a < material.alpha_cutoff {
        discard;
    }
    let roughness = clamp(material.roughness * metal_rough.g, 0.03, 1.0);
    let metallic = clamp(material.metallic * metal_rough.b, 0.0, 1.0);
    let emissive = material.emissive.rgb * emissive_sample;
    let normal = shading_normal(input, front_facing, normal_sample, derivatives);

    let prev_ndc = input.prev_clip.xy / input.prev_clip.w;
    let prev_pixel = (prev_ndc * 0.5 + 0.5) * frame.viewport.xy;
    let motion = prev_pixel - input.clip.xy;
    let view_depth = -(frame.view * vec4<f32>(input.world_position, 1.0)).z;

    var output: GBuffer;
    output.base_metallic = vec4<f32>(base.rgb, metallic);
    output.normal_roughness = vec4<f32>(normal, roughness);
    output.position_depth = vec4<f32>(input.world_position, view_depth);
    output.motion_stencil_specular = vec4<f32>(motion, material.stencil, material.specular);
    output.emissive_coverage = vec4<f32>(emissive, 1.0);
    return output;
}
