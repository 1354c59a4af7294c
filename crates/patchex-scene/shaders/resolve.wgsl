// Resolve pass: lights the G-buffer with the sun and the sky, and writes every dataset layer
// into one planar f32 buffer (one plane per channel, in the order of `layers.rs`), which the
// host copies straight into the EXR channels. Emissive is added unlit.

// #import frame
// #import lighting

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

    let n_dot_l = clamp(dot(normal, frame.sun_direction.xyz), 0.0, 1.0);
    let light_clip = shadow_coordinates(world, normal);
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

    let light = light_surface(base_color, metallic, specular, roughness, normal, to_camera, n_dot_v, n_dot_l);
    let emissive = emissive_cov.rgb;
    let unshadowed_by_dynamic = light.ambient + light.sun * static_visibility + emissive;
    let lit = light.ambient + light.sun * static_visibility * dynamic_visibility + emissive;
    store3(PLANE_FINAL, pixel, lit);
    store3(PLANE_FINAL_NO_DYNAMIC_SHADOWS, pixel, unshadowed_by_dynamic);
    let sun_specular = light.sun_specular * static_visibility * dynamic_visibility;
    store3(PLANE_SPECULAR_LIGHT, pixel, sun_specular + light.sky_specular);
}
