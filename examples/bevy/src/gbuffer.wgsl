// What patchex reads and Bevy does not write as such, made from Bevy's prepasses:
//
// - base colour and Unreal's (metallic, specular, roughness), unpacked from Bevy's deferred
//   G-buffer as pbr_deferred_functions.wgsl packs them:
//     r: pack4x8unorm(base colour ^ (1 / 2.2), perceptual roughness)
//     b: pack4x8unorm(reflectance, metallic, diffuse occlusion, clearcoat)
//   Bevy's specular colour is 0.16 * reflectance^2, Unreal's 0.08 * specular: specular is
//   2 * reflectance^2.
// - a dynamic-object id: Bevy has no per-object id buffer, so a pixel whose motion vector differs
//   from the motion the camera alone gives its surface is taken for a moving object (id 1).
//
// The pass also binds every other image patchex reads or writes afterwards (colour, normals, the
// output) so that wgpu leaves each in a layout the example knows when the commands patchex
// records run: sampled ones read-only, storage ones GENERAL.

struct Cameras {
    // This instant's wgpu clip space (y up) to world.
    world_from_clip: mat4x4<f32>,
    // The previous instant's world to clip: where the motion vectors point.
    previous_clip_from_world: mat4x4<f32>,
    // A pixel moving further than the camera moves it by more than this, in pixels, is dynamic.
    dynamic_threshold: f32,
}

@group(0) @binding(0) var deferred_gbuffer: texture_2d<u32>;
@group(0) @binding(1) var depth: texture_depth_2d;
@group(0) @binding(2) var normals: texture_2d<f32>;
@group(0) @binding(3) var motion_vectors: texture_2d<f32>;
@group(0) @binding(4) var colour: texture_2d<f32>;
@group(0) @binding(5) var base_color: texture_storage_2d<rgba8unorm, write>;
@group(0) @binding(6) var material: texture_storage_2d<rgba8unorm, write>;
@group(0) @binding(7) var object_id: texture_storage_2d<r8uint, write>;
@group(0) @binding(8) var generated: texture_storage_2d<rgba16float, write>;
@group(0) @binding(9) var<uniform> cameras: Cameras;

@compute @workgroup_size(8, 8)
fn unpack(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(deferred_gbuffer);
    if any(id.xy >= size) {
        return;
    }
    let packed = textureLoad(deferred_gbuffer, id.xy, 0);
    let colour_and_roughness = unpack4x8unorm(packed.r);
    let properties = unpack4x8unorm(packed.b);
    let reflectance = properties.x;
    let metallic = properties.y;
    textureStore(base_color, id.xy, vec4(pow(colour_and_roughness.rgb, vec3(2.2)), 1.0));
    textureStore(material, id.xy, vec4(metallic, 2.0 * reflectance * reflectance, colour_and_roughness.a, 1.0));
    textureStore(object_id, id.xy, vec4(select(0u, 1u, is_dynamic(id.xy, vec2<f32>(size))), 0u, 0u, 0u));
}

fn is_dynamic(pixel: vec2<u32>, size: vec2<f32>) -> bool {
    let device_depth = textureLoad(depth, pixel, 0);
    // Reversed Z, infinite far plane: 0 is the sky, which moves with the camera.
    if device_depth <= 0.0 {
        return false;
    }
    let uv = (vec2<f32>(pixel) + 0.5) / size;
    let clip = vec4(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0, device_depth, 1.0);
    let world = cameras.world_from_clip * clip;
    let previous_clip = cameras.previous_clip_from_world * world;
    let previous_uv = vec2(0.5, -0.5) * previous_clip.xy / previous_clip.w + 0.5;
    // Bevy's motion vectors: this instant's UV minus the previous one's.
    let camera_motion = uv - previous_uv;
    let motion = textureLoad(motion_vectors, pixel, 0).xy;
    return length((motion - camera_motion) * size) > cameras.dynamic_threshold;
}
