// A material's surface as the rasterising passes see it: the material's push constants and
// textures, the vertex stage both the G-buffer and the forward pass run, and the surface a
// fragment samples. The including shader declares `frame` (include/frame.wgsl) at group 0.

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

struct Surface {
    // base colour times vertex colour, with its alpha
    base: vec4<f32>,
    metallic: f32,
    roughness: f32,
    emissive: vec3<f32>,
    normal: vec3<f32>,
}

fn sample_surface(input: VertexOutput, front_facing: bool) -> Surface {
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
    var surface: Surface;
    surface.base = material.base_color * input.color * base_sample;
    surface.roughness = clamp(material.roughness * metal_rough.g, 0.03, 1.0);
    surface.metallic = clamp(material.metallic * metal_rough.b, 0.0, 1.0);
    surface.emissive = material.emissive.rgb * emissive_sample;
    surface.normal = shading_normal(input, front_facing, normal_sample, derivatives);
    return surface;
}

// Linear view depth: distance along the camera's forward axis.
fn view_depth(world_position: vec3<f32>) -> f32 {
    return -(frame.view * vec4<f32>(world_position, 1.0)).z;
}

// Backward motion to the previous frame, in pixels.
fn surface_motion(input: VertexOutput) -> vec2<f32> {
    let prev_ndc = input.prev_clip.xy / input.prev_clip.w;
    let prev_pixel = (prev_ndc * 0.5 + 0.5) * frame.viewport.xy;
    return prev_pixel - input.clip.xy;
}
