// Sun and sky lighting, shared by the resolve pass (opaque surfaces from the G-buffer) and the
// forward pass (blended surfaces). Shading is split the way Unreal does it: DiffuseColor =
// BaseColor * (1 - Metallic), SpecularColor = lerp(0.08 * Specular, BaseColor, Metallic).
// The including shader declares `frame` (include/frame.wgsl).

const PI: f32 = 3.14159265;

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

// Where `world` falls in the shadow maps, offset along the normal by a few texels to avoid acne
// on lit slopes.
fn shadow_coordinates(world: vec3<f32>, normal: vec3<f32>) -> vec3<f32> {
    let offset_world = world + normal * frame.shadow_params.y;
    let light_clip = frame.light_view_proj * vec4<f32>(offset_world, 1.0);
    return light_clip.xyz / light_clip.w;
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

// A surface's light before the sun's shadows, in parts: the shadows multiply `sun` and
// `sun_specular`, and `sun_specular` and `sky_specular` are the view-dependent part.
struct SurfaceLight {
    ambient: vec3<f32>,
    sun: vec3<f32>,
    sun_specular: vec3<f32>,
    sky_specular: vec3<f32>,
}

fn light_surface(
    base_color: vec3<f32>,
    metallic: f32,
    specular: f32,
    roughness: f32,
    normal: vec3<f32>,
    to_camera: vec3<f32>,
    n_dot_v: f32,
    n_dot_l: f32,
) -> SurfaceLight {
    let sun = frame.sun_direction.xyz;
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

    return SurfaceLight(ambient_light, sun_light, frame.sun_radiance.rgb * sun_specular_brdf * n_dot_l, sky_specular);
}
