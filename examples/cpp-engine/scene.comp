// The example engine's renderer: ray-casts one instant of its scene (three balls rolling over a
// checkered floor, lit by a sun, casting shadows) and writes the G-buffers a deferred renderer
// has: lit colour, base colour, world normal, hardware depth, a stencil id per ball, and
// backward motion vectors to an earlier instant; and patchex's shadow input: the sun's
// visibility through the balls (the dynamic casters) and the colour lit as if they cast none.
#version 450

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0, rgba16f) uniform writeonly image2D color_out;
layout(set = 0, binding = 1, rgba8) uniform writeonly image2D base_color_out;
layout(set = 0, binding = 2, rgba16f) uniform writeonly image2D normal_out;
layout(set = 0, binding = 3, r32f) uniform writeonly image2D depth_out;
layout(set = 0, binding = 4, r8ui) uniform writeonly uimage2D stencil_out;
layout(set = 0, binding = 5, rg32f) uniform writeonly image2D motion_out;
layout(set = 0, binding = 6, r32f) uniform writeonly image2D shadow_mask_out;
layout(set = 0, binding = 7, rgba16f) uniform writeonly image2D color_without_dynamic_shadows_out;

const int BALLS = 3;

// Mirrors `Instant` in engine.cpp (std140).
layout(set = 0, binding = 8) uniform Instant {
  mat4 view_projection;
  // The earlier instant the motion vectors point to.
  mat4 earlier_view_projection;
  vec4 eye;
  vec4 sun;  // xyz: unit direction towards the sun
  vec4 balls[BALLS];  // xyz centre, w radius
  vec4 earlier_balls[BALLS];
}
instant;

const float SKY_DISTANCE = 1.0e4;

struct Hit {
  float distance;
  vec3 normal;
  int ball;  // -1: floor, -2: sky
};

float ball_distance(vec3 origin, vec3 direction, vec4 ball) {
  vec3 to_origin = origin - ball.xyz;
  float b = dot(to_origin, direction);
  float c = dot(to_origin, to_origin) - ball.w * ball.w;
  float discriminant = b * b - c;
  if (discriminant < 0.0) return -1.0;
  return -b - sqrt(discriminant);
}

Hit trace(vec3 origin, vec3 direction) {
  Hit hit = Hit(SKY_DISTANCE, vec3(0.0), -2);
  if (direction.y < 0.0) {
    hit = Hit(-origin.y / direction.y, vec3(0.0, 1.0, 0.0), -1);
  }
  for (int i = 0; i < BALLS; ++i) {
    float d = ball_distance(origin, direction, instant.balls[i]);
    if (d > 1.0e-3 && d < hit.distance) {
      vec3 point = origin + d * direction;
      hit = Hit(d, normalize(point - instant.balls[i].xyz), i);
    }
  }
  return hit;
}

bool in_shadow(vec3 point) {
  for (int i = 0; i < BALLS; ++i) {
    if (ball_distance(point, instant.sun.xyz, instant.balls[i]) > 1.0e-3) return true;
  }
  return false;
}

vec3 albedo(Hit hit, vec3 point) {
  if (hit.ball == -1) {
    // Floor: large checks with a finer grid, so that a wrong warp shows.
    vec2 cell = floor(point.xz * 1.5);
    float checks = mod(cell.x + cell.y, 2.0);
    vec2 grid = abs(fract(point.xz * 6.0) - 0.5);
    float line = step(0.46, max(grid.x, grid.y));
    return mix(vec3(0.62, 0.58, 0.5), vec3(0.28, 0.3, 0.34), checks) * (1.0 - 0.3 * line);
  }
  // Balls: stripes fixed to the ball, so its texture moves with it.
  vec3 local = point - instant.balls[hit.ball].xyz;
  float stripes = step(0.0, sin(local.y * 14.0));
  vec3 tint = vec3[](vec3(0.85, 0.25, 0.2), vec3(0.2, 0.6, 0.85), vec3(0.9, 0.75, 0.2))[hit.ball];
  return mix(tint, vec3(0.95), 0.6 * stripes);
}

vec2 to_pixel(mat4 view_projection, vec3 point, vec2 size) {
  vec4 clip = view_projection * vec4(point, 1.0);
  return (clip.xy / clip.w * 0.5 + 0.5) * size;
}

void main() {
  ivec2 size = imageSize(color_out);
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, size))) return;

  vec2 pixel = vec2(p) + 0.5;
  vec2 ndc = pixel / vec2(size) * 2.0 - 1.0;
  mat4 inverse_view_projection = inverse(instant.view_projection);
  vec4 far_point = inverse_view_projection * vec4(ndc, 1.0, 1.0);
  vec3 direction = normalize(far_point.xyz / far_point.w - instant.eye.xyz);
  Hit hit = trace(instant.eye.xyz, direction);
  vec3 point = instant.eye.xyz + hit.distance * direction;

  vec3 base = vec3(0.0);
  vec3 color;
  vec3 color_without_dynamic_shadows;
  float visibility = 1.0;
  vec3 normal = -direction;
  float depth = 1.0;
  uint stencil = 0u;
  vec3 earlier_point = point;
  if (hit.ball == -2) {
    color = mix(vec3(0.55, 0.68, 0.85), vec3(0.25, 0.4, 0.7), clamp(direction.y * 2.0, 0.0, 1.0));
    color_without_dynamic_shadows = color;
  } else {
    base = albedo(hit, point);
    normal = hit.normal;
    // Every caster is a ball, and every ball is dynamic.
    visibility = in_shadow(point + 1.0e-3 * normal) ? 0.0 : 1.0;
    float sun = max(dot(normal, instant.sun.xyz), 0.0);
    // patchex's demodulation rule with no material image (metallic 0, specular 0.5).
    color = (base + 0.04) * (0.25 + 0.75 * sun * visibility);
    color_without_dynamic_shadows = (base + 0.04) * (0.25 + 0.75 * sun);
    vec4 clip = instant.view_projection * vec4(point, 1.0);
    depth = clip.z / clip.w;
    if (hit.ball >= 0) {
      stencil = uint(hit.ball + 1);
      earlier_point = point - instant.balls[hit.ball].xyz + instant.earlier_balls[hit.ball].xyz;
    }
  }
  vec2 motion = to_pixel(instant.earlier_view_projection, earlier_point, vec2(size)) - pixel;

  imageStore(color_out, p, vec4(color, 1.0));
  imageStore(base_color_out, p, vec4(base, 1.0));
  imageStore(normal_out, p, vec4(normal, 0.0));
  imageStore(depth_out, p, vec4(depth));
  imageStore(stencil_out, p, uvec4(stencil));
  imageStore(motion_out, p, vec4(motion, 0.0, 0.0));
  imageStore(shadow_mask_out, p, vec4(visibility));
  imageStore(color_without_dynamic_shadows_out, p, vec4(color_without_dynamic_shadows, 1.0));
}
