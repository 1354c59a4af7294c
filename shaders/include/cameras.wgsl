// Both instants' cameras, as the extrapolation writes them into its counters before its first
// stage (`warp::cameras`; src/camera.rs `PixelRays` computes the rays). Each instant's camera as rays through its pixel centres, scaled to unit linear depth: the
// surface seen through pixel (x, y) lies at position + depth * (at_origin + x per_x + y per_y).
// Exact for any perspective projection, since linear depth runs along its axis.
struct Cameras {
    source_position: vec3f,
    source_at_origin: vec3f,
    source_per_x: vec3f,
    source_per_y: vec3f,
    target_position: vec3f,
    target_at_origin: vec3f,
    target_per_x: vec3f,
    target_per_y: vec3f,
    // How the target's engine depth and normals read (gbuffer.wgsl `linear_depth`,
    // `unit_normal`).
    target_depth_curve: vec4f,
    target_far: f32,
    target_depth_convention: u32,
    target_normal_encoding: u32,
    target_has_stencil: u32,
}
