// Resolve pass: lights the G-buffer with the sun and the sky, and writes every dataset layer
// into one planar f32 buffer (one plane per channel, in the order of `layers.rs`), which the
// host copies straight into the EXR channels.
//
// Shading is split the way Unreal does it: DiffuseColor = BaseColor * (1 - Metallic),
// SpecularColor = lerp(0.08 * Specular, BaseColor, Metallic); emissive is added unlit.

// #import frame

struct Options {
    // 1 = light the frame, 0 = G-buffer only (the lit layers are left as zeros)
    lighting: u32,
}

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var base_metallic: texture_2d<f32>;
@group(0) @binding(2) var normal_roughness: texture_2d<f32>;
@group(0) @binding(3) var position_depth: texture_2d<f32>;
@group(0) @binding(4) var motion_stencil_specular: texture_2d<f32>;
@group(0) @binding(5) var emissive_coverage: texture_2d<f32>;
@group(0) @binding(6) var static_shadow_map: texture_depth_2d;
@group(0) @binding(7) var dynamic_shadow_map: texture_depth_2d;
@group(0) @binding(8) var<storage, read_write> planes: array<f32>;
var<immediate> options: Options;

const PI: f32 = 3.14159265;

const PLANE_FINAL: u32 = 0u;
const PLANE_BASE_COLOR: u32 = 3u;
const PLANE_METALLIC: u32 = 6u;
const PLANE_SPECULAR: u32 = 7u;
const PLANE_ROUGHNESS: u32 = 8u;
const PLANE_DEPTH: u32 = 9u;
const PLANE_NORMAL: u32 = 10u;
const PLANE_POSITION: u32 = 13u;
const PLANE_STENCIL: u32 = 16u;
const PLANE_MOTION: u32 = 17u;
const PLANE_NOV: u32 = 19u;
const PLANE_SHADOW_MASK: u32 = 20u;
const PLANE_FINAL_NO_DYNAMIC_SHADOWS: u32 = 21u;
const PLANE_SPECULAR_LIGHT: u32 = 24u;
const PLANE_STATIC_SHADOW_MASK: u32 = 27u;

fn store(plane: u32, pixel: u32, value: f32) {
    let plane_size = u32(frame.viewport.x) * u32(frame.viewport.y);
    planes[plane * plane_size + pixel] = value;
}

fn store3(plane: u32, pixel: u32, value: vec3<f32>) {
    store(plane, pixel, value.x);
    store(plane + 1u, pixel, value.y);
    store(plane + 2u, pixel, value.z);
}

// 3x3 percentage-closer filter over a depth map; the map stores the nearest caster depth.
fn sun_visibility(shadow_map: texture_depth_2d, light_clip: vec3<f32>, bias: f32) -> f32 {
    let size = vec2<i32>(textureDimensions(shadow_map));
    let texel = (light_clip.xy * 0.5 + 0.5) * vec2<f32>(size) - 0.5;
    let base = vec2<i32>(floor(texel));
    // Outside the map's square or depth range nothing is known to cast a shadow.
    if any(abs(light_clip.xy) > vec2<f32>(1.0)) || light_clip.z > 1.0 || light_clip.z < 0.0 {
        return 1.0;
    }
    var lit = 0.0;
    for (var dy = -1; dy <= 1; dy++) {
        for (var dx = -1; dx <= 1; dx++) {
            let coord = clamp(base + vec2<i32>(dx, dy), vec2<i32>(0), size - 1);
            let occluder = textureLoad(shadow_map, coord, 0);
            lit += select(0.0, 1.0, light_clip.z - bias <= occluder);
        }
    }
    return lit / 9.0;
}

fn sky_radiance(direction: vec3<f32>) -> vec3<f32> {
    let up = clamp(direction.y, 0.0, 1.0);
    return mix(frame.sky_horizon.rgb, frame.sky_zenith.rgb, sqrt(up));
}

// Karis' analytic fit of the split-sum environment BRDF ("Physically Based Shading on Mobile").
fn environment_brdf(specular_color: vec3<f32>, roughness: f32, n_dot_v: f32) -> vec3<f32> {
    let c0 = vec4<f32>(-1.0, -0.0275, -0.572, 0.022);
    let c1 = vec4<f32>(1.0, 0.0425, 1.04, -0.04);
    let r = roughness * c0 + c1;
    let a004 = min(r.x * r.x, exp2(-9.28 * n_dot_v)) * r.x + r.y;
    let ab = vec2<f32>(-1.04, 1.04) * a004 + r.zw;
    return specular_color * ab.x + ab.y;
}

fn project_to_pixel(view_proj: mat4x4<f32>, world: vec3<f32>) -> vec2<f32> {
    let clip = view_proj * vec4<f32>(world, 1.0);
    return (clip.xy / clip.w * 0.5 + 0.5) * frame.viewport.xy;
}

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let width = u32(frame.viewport.x);
    let height = u32(frame.viewport.y);
    if id.x >= width || id.y >= height {
        return;
    }
    let coord = vec2<i32>(id.xy);
    let pixel = id.y * width + id.x;
    let pixel_center = vec2<f32>(id.xy) + 0.5;
    let camera = frame.camera_position.xyz;
    let far = frame.viewport.w;

    let emissive_cov = textureLoad(emissive_coverage, coord, 0);
    if emissive_cov.w < 0.5 {
        // Sky: a point at distance `far` along the pixel's view ray.
        let ndc = vec4<f32>(pixel_center / frame.viewport.xy * 2.0 - 1.0, 1.0, 1.0);
        let far_point = frame.inv_view_proj * ndc;
        let direction = normalize(far_point.xyz / far_point.w - camera);
        let world = camera + far * direction;
        let sky = sky_radiance(direction);
        store3(PLANE_BASE_COLOR, pixel, vec3<f32>(0.0));
        store(PLANE_METALLIC, pixel, 0.0);
        store(PLANE_SPECULAR, pixel, 0.5);
        store(PLANE_ROUGHNESS, pixel, 1.0);
        store(PLANE_DEPTH, pixel, far);
        store3(PLANE_NORMAL, pixel, -direction);
        store3(PLANE_POSITION, pixel, world);
        store(PLANE_STENCIL, pixel, 0.0);
        let motion = project_to_pixel(frame.prev_view_proj, world) - pixel_center;
        store(PLANE_MOTION, pixel, motion.x);
        store(PLANE_MOTION + 1u, pixel, motion.y);
        store(PLANE_NOV, pixel, 1.0);
        store(PLANE_SHADOW_MASK, pixel, 1.0);
        store(PLANE_STATIC_SHADOW_MASK, pixel, 1.0);
        let lit = select(vec3<f32>(0.0), sky, options.lighting == 1u);
        store3(PLANE_FINAL, pixel, lit);
        store3(PLANE_FINAL_NO_DYNAMIC_SHADOWS, pixel, lit);
        store3(PLANE_SPECULAR_LIGHT, pixel, vec3<f32>(0.0));
        return;
    }

    let base_m = textureLoad(base_metallic, coord, 0);
    let normal_r = textureLoad(normal_roughness, coord, 0);
    let position_d = textureLoad(position_depth, coord, 0);
    let motion_s = textureLoad(motion_stencil_specular, coord, 0);
    let base_color = base_m.rgb;
    let metallic = base_m.w;
    let normal = normal_r.xyz;
    let roughness = normal_r.w;
    let world = position_d.xyz;
    let specular = motion_s.w;
    let to_camera = normalize(camera - world);
    let n_dot_v = clamp(dot(normal, to_camera), 0.0, 1.0);

    store3(PLANE_BASE_COLOR, pixel, base_color);
    store(PLANE_METALLIC, pixel, metallic);
    store(PLANE_SPECULAR, pixel, specular);
    store(PLANE_ROUGHNESS, pixel, roughness);
    store(PLANE_DEPTH, pixel, position_d.w);
    store3(PLANE_NORMAL, pixel, normal);
    store3(PLANE_POSITION, pixel, world);
    store(PLANE_STENCIL, pixel, motion_s.z);
    store(PLANE_MOTION, pixel, motion_s.x);
    store(PLANE_MOTION + 1u, pixel, motion_s.y);
    store(PLANE_NOV, pixel, n_dot_v);

    // Shadow lookups offset along the normal by a few texels to avoid acne on lit slopes.
    let sun = frame.sun_direction.xyz;
    let n_dot_l = clamp(dot(normal, sun), 0.0, 1.0);
    let offset_world = world + normal * frame.shadow_params.y;
    let light_clip4 = frame.light_view_proj * vec4<f32>(offset_world, 1.0);
    let light_clip = light_clip4.xyz / light_clip4.w;
    let static_visibility = sun_visibility(static_shadow_map, light_clip, frame.shadow_params.x);
    let dynamic_visibility = sun_visibility(dynamic_shadow_map, light_clip, frame.shadow_params.x);
    store(PLANE_SHADOW_MASK, pixel, dynamic_visibility);
    store(PLANE_STATIC_SHADOW_MASK, pixel, static_visibility);
    if options.lighting != 1u {
        store3(PLANE_FINAL, pixel, vec3<f32>(0.0));
        store3(PLANE_FINAL_NO_DYNAMIC_SHADOWS, pixel, vec3<f32>(0.0));
        store3(PLANE_SPECULAR_LIGHT, pixel, vec3<f32>(0.0));
        return;
    }

    let diffuse_color = base_color * (1.0 - metallic);
    let specular_color = mix(vec3<f32>(0.08 * specular), base_color, metallic);

    // Direct sun: Lambert plus GGX with height-correlated Smith visibility and Schlick Fresnel.
    let half_vector = normalize(sun + to_camera);
    let n_dot_h = clamp(dot(normal, half_vector), 0.0, 1.0);
    let v_dot_h = clamp(dot(to_camera, half_vector), 0.0, 1.0);
    let alpha = roughness * roughness;
    let alpha2 = alpha * alpha;
    let d_denominator = n_dot_h * n_dot_h * (alpha2 - 1.0) + 1.0;
    let distribution = alpha2 / (PI * d_denominator * d_denominator);
    let n_dot_v_safe = max(n_dot_v, 1e-4);
    let smith_v = n_dot_l * sqrt(n_dot_v_safe * n_dot_v_safe * (1.0 - alpha2) + alpha2);
    let smith_l = n_dot_v_safe * sqrt(n_dot_l * n_dot_l * (1.0 - alpha2) + alpha2);
    let visibility_term = 0.5 / max(smith_v + smith_l, 1e-6);
    let fresnel_weight = pow(1.0 - v_dot_h, 5.0);
    let fresnel = specular_color * (1.0 - fresnel_weight) + vec3<f32>(fresnel_weight);
    let sun_specular_brdf = distribution * visibility_term * fresnel;
    let sun_brdf = diffuse_color / PI + sun_specular_brdf;
    let sun_light = frame.sun_radiance.rgb * sun_brdf * n_dot_l;

    // Sky: hemisphere irradiance for diffuse, the reflected sky for specular; not shadowed.
    let up = normal.y * 0.5 + 0.5;
    let ambient_irradiance = mix(frame.ground_ambient.rgb, frame.sky_zenith.rgb, up);
    let reflected = reflect(-to_camera, normal);
    let sky_specular = sky_radiance(reflected) * environment_brdf(specular_color, roughness, n_dot_v);
    let ambient_light = diffuse_color * ambient_irradiance + sky_specular;

    let emissive = emissive_cov.rgb;
    let unshadowed_by_dynamic = ambient_light + sun_light * static_visibility + emissive;
    let lit = ambient_light + sun_light * static_visibility * dynamic_visibility + emissive;
    store3(PLANE_FINAL, pixel, lit);
    store3(PLANE_FINAL_NO_DYNAMIC_SHADOWS, pixel, unshadowed_by_dynamic);
    let sun_specular = frame.sun_radiance.rgb * sun_specular_brdf * n_dot_l * static_visibility * dynamic_visibility;
    store3(PLANE_SPECULAR_LIGHT, pixel, sun_specular + sky_specular);
}
